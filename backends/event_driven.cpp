#include "backends/event_driven.h"

#include "engine/diagnostics.h"
#include "engine/event_state.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace carom {
namespace {

constexpr double kNever = HUGE_VAL;
// How far below where it arrives a disk too slow to rise that high sinks
// before it bounces off a wall, relative to the longer box side: a bounce
// then takes at least sqrt(2 depth / g), never zero time, and a resting
// pile's floor lies a few depths low.
constexpr double kRestingDepth = 1e-12;
// Collisions of pairs closer than this fraction of their contact distance
// count as overlapping (EventCounts::overlapping): deeper than rounding.
constexpr double kOverlapTolerance = 1e-9;
// How far outside its cell a restored disk may lie, relative to the box
// side: rounding at a crossing leaves it a few ulps past the edge.
constexpr double kCellSlack = 1e-9;
// Events between re-sorts of the storage order, per disk: disks move a few
// diameters in that time (the re-sorts took 0.3 % of the time at N = 10^5).
constexpr std::uint64_t kSortInterval = 8;
// Events at one unchanging time, per disk, beyond which the engine stops
// (a chain of simultaneous collisions is a few per disk; more means double
// precision can no longer tell the times apart).
constexpr std::uint64_t kMaxEventsAtOneTime = 1000;
// Events between two looks for a stop (Backend::stopHere), in a step that
// can be stopped: a look reads the clock.
constexpr std::uint64_t kEventsPerStopCheck = 256;

// The time s >= 0 at which h(s) = h0 + u s + a s^2 / 2 first reaches 0
// while decreasing: a disk at height h0 above a boundary (a wall, a cell
// edge) with velocity u and acceleration a towards it negative. A disk
// found below by rounding (h0 < 0) counts as on it. kNever if it never
// arrives. The roots are taken in the forms without cancellation.
double arrivalTime(double h0, double u, double a) {
    if (h0 < 0) h0 = 0;
    if (u < 0) {
        const double d = u * u - 2 * a * h0;
        if (d < 0) return kNever;  // pushed back (a > 0) before it arrives
        return 2 * h0 / (-u + std::sqrt(d));
    }
    if (a >= 0) return kNever;  // moving away and not pulled back
    return (u + std::sqrt(u * u - 2 * a * h0)) / -a;
}

// The time until an approaching pair at separation (dx, dy) with relative
// velocity (dvx, dvy) touches at distance sigma: the first root of
// |d + dv s| = sigma in the stable form c / (-b + sqrt(b^2 - a c)).
// A receding pair is never scheduled, an approaching overlapping one (by
// rounding) collides at once: no collision repeats in zero time.
// Computed whole and then selected, without branches: whether a neighbour
// approaches is a coin toss the processor cannot predict.
double contactTime(double dx, double dy, double dvx, double dvy, double sigma) {
    const double b = dx * dvx + dy * dvy;
    const double c = dx * dx + dy * dy - sigma * sigma;
    const double a = dvx * dvx + dvy * dvy;
    const double d = b * b - a * c;
    const double root = c / (-b + std::sqrt(std::max(d, 0.0)));
    const double approaching = c <= 0 ? 0.0 : d <= 0 ? kNever : root;  // d <= 0: they pass each other
    return b < 0 ? approaching : kNever;
}

// A hint to start loading memory that will be read soon.
inline void prefetch(const void* address) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(address);
#else
    (void)address;
#endif
}

// Cell `index` of `count` along one axis of length `extent`, where index
// may be one past either end: wrapped in a periodic box, with the offset of
// the image it stands for in `shift`; -1 beyond a wall.
std::int64_t neighbourCell(std::int64_t index, std::uint32_t count, double extent, bool periodic, double& shift) {
    if (index >= 0 && index < count) return index;
    if (!periodic) return -1;
    shift = index < 0 ? -extent : extent;
    return index < 0 ? index + count : index - count;
}

double nearestImage(double d, double extent) {
    if (d > 0.5 * extent) return d - extent;
    if (d < -0.5 * extent) return d + extent;
    return d;
}

// The earliest of a disk's candidate events. Equal times go to the lower
// key (the event code, or the partner's particle id), so the choice depends
// neither on the storage order nor on the order the cells are scanned in.
struct Candidate {
    double time = kNever;
    std::int32_t code = kEventNone;  // an event code or the partner's storage index
    std::int64_t key = kEventNone;
    void offer(double t, std::int32_t c, std::int64_t k) {
        if (t < time || (t == time && k < key)) {
            time = t;
            code = c;
            key = k;
        }
    }
    void offer(double t, std::int32_t c) { offer(t, c, c); }
};

}  // namespace

EventDrivenBackend::Flight EventDrivenBackend::flight(double x, double y, double vx, double vy, double s) const {
    return Flight{x + (vx + 0.5 * gx_ * s) * s, y + (vy + 0.5 * gy_ * s) * s, vx + gx_ * s, vy + gy_ * s};
}

EventDrivenBackend::EventDrivenBackend(const WorldDef& world) : Backend(world) {}

std::string EventDrivenBackend::device() const { return "CPU, one thread, double precision (event-driven)"; }

void EventDrivenBackend::load(const std::vector<Particle>& particles) {
    const std::size_t n = particles.size();
    width_ = world_.width;
    height_ = world_.height;
    gx_ = world_.gravity.x;
    gy_ = world_.gravity.y;
    periodic_ = world_.boundary == Boundary::Periodic;
    // The grid Backend sized: cells a hair wider than the largest diameter,
    // at least 3 a side in a periodic box, so the 3 x 3 cells around a disk
    // are distinct and hold every disk it can touch.
    columns_ = std::uint32_t(grid_.geometry.cols);
    rows_ = std::uint32_t(grid_.geometry.rows);
    cellWidth_ = width_ / columns_;
    cellHeight_ = height_ / rows_;
    restingDepth_ = kRestingDepth * std::max(width_, height_);
    step_ = stepNumber();
    stepOrigin_ = 0;  // step k ends at k dt, in this run and in any run resumed from it
    timeOrigin_ = 0.0;
    now_ = double(step_) * double(world_.dt);

    disks_.assign(n, Disk{});
    scheduled_.assign(n, Scheduled{});
    mass_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Particle& p = particles[i];
        Disk& d = disks_[i];
        d.x = p.position.x;
        d.y = p.position.y;
        if (periodic_) {  // a centre on the far edge is the same point as one on the near edge
            if (d.x >= width_) d.x -= width_;
            if (d.y >= height_) d.y -= height_;
        }
        d.vx = p.velocity.x;
        d.vy = p.velocity.y;
        d.time = now_;
        d.radius = p.radius;
        const auto column = std::uint32_t(std::clamp(std::floor(d.x / cellWidth_), 0.0, double(columns_ - 1)));
        const auto row = std::uint32_t(std::clamp(std::floor(d.y / cellHeight_), 0.0, double(rows_ - 1)));
        d.cell = row * columns_ + column;
        d.id = std::uint32_t(i);
        scheduled_[i] = Scheduled{kNever, kEventNone, 0};
        mass_[i] = p.mass;
    }
    sortByCell();
    for (std::uint32_t i = 0; i < n; ++i) schedule(i);
    counts_ = EventCounts{};
    undrained_ = ContactTotals{};
}

void EventDrivenBackend::sortByCell() {
    const std::size_t n = disks_.size();
    // A stable counting sort by cell: the order is a function of the state.
    std::vector<std::uint32_t> start(std::size_t(columns_) * rows_ + 1, 0);
    for (const Disk& d : disks_) ++start[d.cell + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    std::vector<std::uint32_t> index(n);  // old storage index -> new
    for (std::size_t i = 0; i < n; ++i) index[i] = start[disks_[i].cell]++;
    std::vector<Disk> disks(n);
    std::vector<Scheduled> scheduled(n);
    std::vector<double> mass(n);
    for (std::size_t i = 0; i < n; ++i) {
        disks[index[i]] = disks_[i];
        Scheduled e = scheduled_[i];
        if (e.event >= 0) e.event = std::int32_t(index[e.event]);
        scheduled[index[i]] = e;
        mass[index[i]] = mass_[i];
    }
    disks_ = std::move(disks);
    scheduled_ = std::move(scheduled);
    mass_ = std::move(mass);

    head_.assign(std::size_t(columns_) * rows_, -1);
    previous_.assign(n, -1);
    for (std::uint32_t i = std::uint32_t(n); i-- > 0;) link(i);  // each list in storage order
    std::vector<double> times(n);
    std::vector<std::uint32_t> ids(n);
    for (std::size_t i = 0; i < n; ++i) {
        times[i] = scheduled_[i].time;
        ids[i] = disks_[i].id;
    }
    calendar_.reset(times, ids);
    eventsSinceSort_ = 0;
}

std::optional<EventEngineState> EventDrivenBackend::saveState() const {
    EventEngineState state{now_, std::vector<EventDiskState>(disks_.size())};
    for (std::size_t i = 0; i < disks_.size(); ++i) {
        const Disk& d = disks_[i];
        const Scheduled& e = scheduled_[i];
        state.disks[d.id] = EventDiskState{d.x,
                                           d.y,
                                           d.vx,
                                           d.vy,
                                           d.time,
                                           e.time,
                                           e.event >= 0 ? std::int32_t(disks_[e.event].id) : e.event,
                                           e.partnerCollisions,
                                           d.collisions,
                                           d.cell};
    }
    return state;
}

void EventDrivenBackend::restoreState(const EventEngineState& state) {
    if (state.disks.size() != disks_.size())
        throw Error("the event-driven state holds " + std::to_string(state.disks.size()) + " disks, the particles " +
                    std::to_string(disks_.size()));
    if (const std::string problem = eventStateProblem(state, world_.boundary); !problem.empty()) throw Error(problem);
    const std::uint64_t cells = std::uint64_t(columns_) * rows_;
    struct Centre {
        double x, y;
        std::uint32_t id;
    };
    std::vector<Centre> centres(state.disks.size());  // at the state's time
    for (std::size_t i = 0; i < state.disks.size(); ++i) {
        const EventDiskState& d = state.disks[i];
        const std::string which = "events state: disk " + std::to_string(i);
        if (d.cell >= cells)
            throw Error(which + " is in cell " + std::to_string(d.cell) + "; this box has " + std::to_string(cells) +
                        " cells (" + std::to_string(columns_) + " x " + std::to_string(rows_) + ")");
        const std::uint32_t column = d.cell % columns_, row = d.cell / columns_;
        // No crossing out of the box through a wall.
        if (!periodic_ &&
            ((d.event == kEventCrossLeft && column == 0) || (d.event == kEventCrossRight && column + 1 == columns_) ||
             (d.event == kEventCrossDown && row == 0) || (d.event == kEventCrossUp && row + 1 == rows_)))
            throw Error(which + " has event code " + std::to_string(d.event) + ", a crossing out of cell " +
                        std::to_string(d.cell) + " through the box's wall");
        // Its centre within rounding of its cell, at its own time and at the
        // state's (its next event, a crossing at the soonest, comes later).
        const double slackX = kCellSlack * width_, slackY = kCellSlack * height_;
        const auto inCell = [&](double x, double y) {
            return x >= column * cellWidth_ - slackX && x <= (column + 1) * cellWidth_ + slackX &&
                   y >= row * cellHeight_ - slackY && y <= (row + 1) * cellHeight_ + slackY;
        };
        const Flight now = flight(d.x, d.y, d.vx, d.vy, state.time - d.time);
        if (!inCell(d.x, d.y) || !inCell(now.x, now.y))
            throw Error(which + " at (" + std::to_string(d.x) + ", " + std::to_string(d.y) + "), (" +
                        std::to_string(now.x) + ", " + std::to_string(now.y) +
                        ") at the state's time, is not in its cell " + std::to_string(d.cell) + " (column " +
                        std::to_string(column) + ", row " + std::to_string(row) + " of cells " +
                        std::to_string(cellWidth_) + " x " + std::to_string(cellHeight_) + ")");
        // A periodic box's edges are one place: a centre on one is on the other.
        const auto wrapped = [&](double v, double side) { return periodic_ ? v - side * std::floor(v / side) : v; };
        centres[i] = Centre{wrapped(now.x, width_), wrapped(now.y, height_), std::uint32_t(i)};
    }
    // Two disks on one centre: their collision has no direction (as
    // validateStart refuses for the float disks).
    std::sort(centres.begin(), centres.end(), [](const Centre& a, const Centre& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.id < b.id;
    });
    for (std::size_t k = 1; k < centres.size(); ++k) {
        const Centre &a = centres[k - 1], &b = centres[k];
        if (a.x == b.x && a.y == b.y)
            throw Error("events state: disks " + std::to_string(a.id) + " and " + std::to_string(b.id) +
                        " have the same centre (" + std::to_string(a.x) + ", " + std::to_string(a.y) +
                        ") at the state's time: their collision has no direction; allowed: distinct centres");
    }
    // In id order (the partners' storage indices are their ids), then sorted.
    std::vector<double> mass(disks_.size());
    std::vector<Disk> disks(disks_.size());
    for (const Disk& d : disks_) {
        mass[d.id] = mass_[&d - disks_.data()];
        disks[d.id].radius = d.radius;
    }
    for (std::size_t i = 0; i < disks.size(); ++i) {
        const EventDiskState& s = state.disks[i];
        disks[i] = Disk{s.x, s.y, s.vx, s.vy, s.time, disks[i].radius, -1, s.collisions, s.cell, std::uint32_t(i)};
        scheduled_[i] = Scheduled{s.eventTime, s.event, s.partnerCollisions};
    }
    disks_ = std::move(disks);
    mass_ = std::move(mass);
    now_ = state.time;
    // Step k ends at k dt, as in the run that saved the state, unless the
    // state's time is not its step's: then the steps count from it.
    const bool onStep = now_ == double(step_) * double(world_.dt);
    timeOrigin_ = onStep ? 0.0 : now_;
    stepOrigin_ = onStep ? 0 : step_;
    sortByCell();
    counts_ = EventCounts{};
    undrained_ = ContactTotals{};
    // setParticles' images are those of the state's wrapped positions; images_
    // keeps the crossings' part of them.
    const std::vector<Image> shown = images();
    for (std::size_t i = 0; i < shown.size(); ++i)
        for (int axis = 0; axis < 2; ++axis)  // images_ - (shown - images_), modulo 2^32 as every count
            addToImage(images_[i][axis], static_cast<std::int32_t>(static_cast<std::uint32_t>(images_[i][axis]) -
                                                                   static_cast<std::uint32_t>(shown[i][axis])));
}

void EventDrivenBackend::link(std::uint32_t i) {
    Disk& d = disks_[i];
    std::int32_t& first = head_[d.cell];
    d.next = first;
    previous_[i] = -1;
    if (first >= 0) previous_[first] = std::int32_t(i);
    first = std::int32_t(i);
}

void EventDrivenBackend::unlink(std::uint32_t i) {
    const Disk& d = disks_[i];
    if (previous_[i] >= 0)
        disks_[previous_[i]].next = d.next;
    else
        head_[d.cell] = d.next;
    if (d.next >= 0) previous_[d.next] = previous_[i];
}

void EventDrivenBackend::moveTo(std::uint32_t i, double time) {
    Disk& d = disks_[i];
    if (time == d.time) return;
    const Flight f = flight(d.x, d.y, d.vx, d.vy, time - d.time);
    d.x = f.x;
    d.y = f.y;
    d.vx = f.vx;
    d.vy = f.vy;
    d.time = time;
}

double EventDrivenBackend::wallTime(double h0, double u, double a) const {
    const double s = arrivalTime(h0, u, a);
    // Pulled towards the wall and arriving slower than a fall through the
    // resting depth: it bounces that much lower instead, never in zero time.
    if (a < 0 && u * u - 2 * a * std::max(h0, 0.0) < -2 * a * restingDepth_)
        return arrivalTime(std::max(h0, 0.0) + restingDepth_, u, a);
    return s;
}

void EventDrivenBackend::schedule(std::uint32_t i) {
    const Disk& d = disks_[i];  // at now_
    const double r = d.radius;
    Candidate next;
    if (!periodic_) {
        next.offer(wallTime(d.x - r, d.vx, gx_), kEventWallLeft);
        next.offer(wallTime(width_ - r - d.x, -d.vx, -gx_), kEventWallRight);
        next.offer(wallTime(d.y - r, d.vy, gy_), kEventWallBottom);
        next.offer(wallTime(height_ - r - d.y, -d.vy, -gy_), kEventWallTop);
    }
    const std::uint32_t column = d.cell % columns_, row = d.cell / columns_;
    // A walled box's edge cells have a wall where a crossing would be.
    if (periodic_ || column > 0) next.offer(arrivalTime(d.x - column * cellWidth_, d.vx, gx_), kEventCrossLeft);
    if (periodic_ || column + 1 < columns_)
        next.offer(arrivalTime((column + 1) * cellWidth_ - d.x, -d.vx, -gx_), kEventCrossRight);
    if (periodic_ || row > 0) next.offer(arrivalTime(d.y - row * cellHeight_, d.vy, gy_), kEventCrossDown);
    if (periodic_ || row + 1 < rows_)
        next.offer(arrivalTime((row + 1) * cellHeight_ - d.y, -d.vy, -gy_), kEventCrossUp);
    if (next.time < kNever) next.time += now_;

    // The first disk of each of the 3 x 3 cells, loaded (and prefetched)
    // before any list is walked, so that their cache misses overlap.
    std::int32_t first[9];
    double shiftX[9], shiftY[9];  // the partner image's offset: 0 or -+ the box side in a periodic box
    int cells = 0;
    for (int dr = -1; dr <= 1; ++dr) {
        double dy = 0;
        const std::int64_t nr = neighbourCell(std::int64_t(row) + dr, rows_, height_, periodic_, dy);
        if (nr < 0) continue;
        for (int dc = -1; dc <= 1; ++dc) {
            double dx = 0;
            const std::int64_t nc = neighbourCell(std::int64_t(column) + dc, columns_, width_, periodic_, dx);
            if (nc < 0) continue;
            const std::int32_t j = head_[std::size_t(nr) * columns_ + std::size_t(nc)];
            if (j < 0) continue;
            prefetch(&disks_[j]);
            shiftX[cells] = dx;
            shiftY[cells] = dy;
            first[cells++] = j;
        }
    }
    for (int c = 0; c < cells; ++c) {
        for (std::int32_t j = first[c]; j >= 0;) {
            const Disk& o = disks_[j];
            if (j != std::int32_t(i)) {
                const Flight p = flight(o.x, o.y, o.vx, o.vy, now_ - o.time);  // the partner at now_
                // The image across the edge the cell was reached through: in a
                // box 3 cells wide the nearest image can be another one.
                const double t = contactTime(d.x - (p.x + shiftX[c]), d.y - (p.y + shiftY[c]), d.vx - p.vx, d.vy - p.vy,
                                             r + o.radius);
                if (t < kNever) next.offer(now_ + t, j, o.id);
            }
            j = o.next;
        }
    }
    if (next.time == kNever) next.code = kEventNone;  // nothing ahead (at rest, or flying parallel)
    scheduled_[i] = Scheduled{next.time, next.code, next.code >= 0 ? disks_[next.code].collisions : 0u};
    calendar_.set(i, next.time);
}

bool EventDrivenBackend::runUntil(double time, bool stoppable) {
    lastStepEvents_ = 0;
    while (calendar_.nextTime() <= time) {
        if (++lastStepEvents_ % kEventsPerStopCheck == 0 && stoppable && stopHere()) return false;
        if (++eventsSinceSort_ > kSortInterval * disks_.size()) sortByCell();
        const std::uint32_t i = calendar_.next();
        const Scheduled e = scheduled_[i];
        if (e.time > now_) {
            now_ = e.time;
            eventsAtNow_ = 0;
        } else if (++eventsAtNow_ > kMaxEventsAtOneTime * disks_.size()) {
            throw Error("the event-driven engine took " + std::to_string(eventsAtNow_) + " events at time " +
                        std::to_string(now_) +
                        " without time advancing: times this large (or these disks) are "
                        "beyond what double precision resolves");
        }
        const std::int32_t event = e.event;
        if (event >= 0) {
            if (disks_[event].collisions == e.partnerCollisions) {
                collide(i, std::uint32_t(event));
            } else {  // the partner's motion changed since: look again
                ++counts_.stale;
                moveTo(i, now_);
                schedule(i);
            }
        } else if (event >= kEventWallTop) {
            bounce(i, event);
        } else {
            cross(i, event);
        }
    }
    now_ = std::max(now_, time);
    return true;
}

void EventDrivenBackend::collide(std::uint32_t i, std::uint32_t j) {
    moveTo(i, now_);
    moveTo(j, now_);
    Disk& a = disks_[i];
    Disk& b = disks_[j];
    double dx = a.x - b.x, dy = a.y - b.y;
    if (periodic_) {
        dx = nearestImage(dx, width_);
        dy = nearestImage(dy, height_);
    }
    const double approach = dx * (a.vx - b.vx) + dy * (a.vy - b.vy);
    if (approach < 0) {  // rounding can leave a grazing pair receding by now
        const double distance2 = dx * dx + dy * dy;
        const double sigma = a.radius + b.radius;
        const double mi = mass_[i], mj = mass_[j];
        // The elastic impulse along the centre line, as in kernels/physics.h.
        const double f = 2 * approach / ((mi + mj) * distance2);
        a.vx -= mj * f * dx;
        a.vy -= mj * f * dy;
        b.vx += mi * f * dx;
        b.vy += mi * f * dy;
        ++a.collisions;
        ++b.collisions;
        ++counts_.collisions;
        if (distance2 < sigma * sigma * (1 - kOverlapTolerance)) ++counts_.overlapping;
        ++undrained_.collisions;
        // r_ij . J_ij with r_ij = sigma_ij exactly, J = 2 mu |v_n|.
        undrained_.virial += sigma * 2 * (mi * mj / (mi + mj)) * -approach / std::sqrt(distance2);
    }
    schedule(i);
    schedule(j);
}

void EventDrivenBackend::bounce(std::uint32_t i, std::int32_t wall) {
    moveTo(i, now_);
    Disk& d = disks_[i];
    const int side = kEventWallLeft - wall;  // 0 left, 1 right, 2 bottom, 3 top
    double& v = side < 2 ? d.vx : d.vy;
    // Only towards the wall: rounding may have turned it already.
    if (side % 2 == 0 ? v < 0 : v > 0) {
        undrained_.wallImpulse[side] += 2 * mass_[i] * std::fabs(v);
        v = -v;
        ++d.collisions;
        ++counts_.wallBounces;
    }
    schedule(i);
}

void EventDrivenBackend::cross(std::uint32_t i, std::int32_t direction) {
    moveTo(i, now_);
    unlink(i);
    Disk& d = disks_[i];
    std::uint32_t column = d.cell % columns_, row = d.cell / columns_;
    switch (direction) {
        case kEventCrossLeft:
            if (column == 0) {
                column = columns_;
                d.x += width_;  // periodic: it enters on the right
                addToImage(images_[d.id][0], -1);
            }
            --column;
            break;
        case kEventCrossRight:
            if (++column == columns_) {
                column = 0;
                d.x -= width_;
                addToImage(images_[d.id][0], 1);
            }
            break;
        case kEventCrossDown:
            if (row == 0) {
                row = rows_;
                d.y += height_;
                addToImage(images_[d.id][1], -1);
            }
            --row;
            break;
        default:  // kEventCrossUp
            if (++row == rows_) {
                row = 0;
                d.y -= height_;
                addToImage(images_[d.id][1], 1);
            }
            break;
    }
    d.cell = row * columns_ + column;
    link(i);
    ++counts_.cellCrossings;
    schedule(i);
}

std::uint64_t EventDrivenBackend::advance(std::uint64_t substeps, float dt) {
    for (std::uint64_t s = 0; s < substeps; ++s) {
        if (stopHere()) return s;
        // A step that may be long keeps its start, so that a stop can cut it
        // short: a call's first, and one after a step of an event per disk
        // or more (a copy costs less than that step did).
        const bool keep = stopCheckSet() && (s == 0 || lastStepEvents_ >= disks_.size());
        if (keep) keepStepStart();
        // The step's end as a function of the step number alone, so that how
        // the steps are split into calls never changes a sampling time.
        ++step_;
        if (!runUntil(timeOrigin_ + double(step_ - stepOrigin_) * double(dt), keep)) {
            returnToStepStart();
            return s;
        }
    }
    return substeps;
}

void EventDrivenBackend::keepStepStart() { kept_ = changedByStep(); }

void EventDrivenBackend::returnToStepStart() { changedByStep() = kept_; }

void EventDrivenBackend::motionChanged() {
    // Every disk to now_ under the old gravity, then new trajectories.
    for (std::uint32_t i = 0; i < disks_.size(); ++i) moveTo(i, now_);
    gx_ = world_.gravity.x;
    gy_ = world_.gravity.y;
    timeOrigin_ = now_;
    stepOrigin_ = step_;
    for (std::uint32_t i = 0; i < disks_.size(); ++i) schedule(i);
}

namespace {

// A coordinate of a disk that free flight took a hair outside a periodic
// box, before the crossing event wraps it: wrapped, the wrap added to `image`.
double wrapped(double x, double side, std::int32_t& image) {
    if (x < 0) {
        addToImage(image, -1);
        return x + side;
    }
    if (x >= side) {
        addToImage(image, 1);
        return x - side;
    }
    return x;
}

}  // namespace

std::vector<ExactDisk> EventDrivenBackend::exactState(std::vector<Image>* images) const {
    std::vector<ExactDisk> state(disks_.size());
    if (images) *images = images_;
    for (std::size_t i = 0; i < disks_.size(); ++i) {
        const Disk& d = disks_[i];
        const Flight f = flight(d.x, d.y, d.vx, d.vy, now_ - d.time);
        double x = f.x, y = f.y;
        if (periodic_) {
            Image ignored{0, 0};
            Image& image = images ? (*images)[d.id] : ignored;
            x = wrapped(x, width_, image[0]);
            y = wrapped(y, height_, image[1]);
        }
        state[d.id] = ExactDisk{x, y, f.vx, f.vy, mass_[i], d.radius};
    }
    return state;
}

std::vector<Image> EventDrivenBackend::images() {
    std::vector<Image> images;
    roundedParticles(exactState(&images), &images);
    return images;
}

void EventDrivenBackend::readParticles(std::vector<Particle>& particles) { particles = roundedParticles(exactState()); }

std::vector<Particle> EventDrivenBackend::roundedParticles(const std::vector<ExactDisk>& exact,
                                                           std::vector<Image>* images) const {
    std::vector<Particle> particles(exact.size());
    const auto width = float(width_), height = float(height_);
    for (std::size_t i = 0; i < exact.size(); ++i) {
        const ExactDisk& e = exact[i];
        Particle p{};
        p.position = {float(e.x), float(e.y)};
        p.velocity = {float(e.vx), float(e.vy)};
        p.mass = float(e.mass);
        p.radius = float(e.radius);
        if (periodic_) {  // a coordinate a hair below the side rounds up to it, which is 0 in the next image
            if (!(p.position.x < width)) {
                p.position.x = 0.0f;
                if (images) addToImage((*images)[i][0], 1);
            }
            if (!(p.position.y < height)) {
                p.position.y = 0.0f;
                if (images) addToImage((*images)[i][1], 1);
            }
        } else {  // within the bounds validateParticles reads back (a resting disk may sink a hair)
            p.position.x = std::clamp(p.position.x, p.radius, width - p.radius);
            p.position.y = std::clamp(p.position.y, p.radius, height - p.radius);
        }
        particles[i] = p;
    }
    return particles;
}

ViewSums EventDrivenBackend::exactSums(const std::vector<ExactDisk>& exact) const {
    ViewSums sums;
    for (const ExactDisk& e : exact) {
        const double speedSquared = e.vx * e.vx + e.vy * e.vy;
        sums.kineticEnergy += 0.5 * e.mass * speedSquared;
        sums.potentialEnergy -= e.mass * (gx_ * e.x + gy_ * e.y);
        sums.momentum[0] += e.mass * e.vx;
        sums.momentum[1] += e.mass * e.vy;
        sums.mass += e.mass;
        sums.speedSquared += speedSquared;
    }
    return sums;
}

double EventDrivenBackend::kineticEnergy() const { return exactSums(exactState()).kineticEnergy; }

std::optional<double> EventDrivenBackend::exactTotalEnergy() const {
    const ViewSums sums = exactSums(exactState());
    return sums.kineticEnergy + sums.potentialEnergy;
}

std::vector<std::array<double, 2>> EventDrivenBackend::exactPositions() const {
    std::vector<std::array<double, 2>> positions;
    positions.reserve(disks_.size());
    for (const ExactDisk& d : exactState()) positions.push_back({d.x, d.y});
    return positions;
}

std::optional<ViewSums> EventDrivenBackend::readView(ViewValue value, DiskView* out) {
    const std::vector<ExactDisk> exact = exactState();
    const ViewSums copy = measureView(roundedParticles(exact), world(), value, out);
    ViewSums sums = exactSums(exact);
    sums.minValue = copy.minValue;
    sums.maxValue = copy.maxValue;
    return sums;
}

float EventDrivenBackend::maxSpeedSquared() {
    double largest = 0;
    for (const ExactDisk& e : exactState()) largest = std::max(largest, e.vx * e.vx + e.vy * e.vy);
    return float(largest);
}

void EventDrivenBackend::drainTallies(ContactTotals& totals) {
    addUndrained(totals);
    undrained_ = ContactTotals{};
}

void EventDrivenBackend::addUndrained(ContactTotals& totals) {
    totals.collisions += undrained_.collisions;
    totals.virial += undrained_.virial;
    for (int w = 0; w < 4; ++w) totals.wallImpulse[w] += undrained_.wallImpulse[w];
}

}  // namespace carom
