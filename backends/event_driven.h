// The event-driven scheme (--collisions events): exact hard-disk dynamics on
// one CPU thread, in double. Disks fly freely (parabolas under gravity)
// between instantaneous events, taken one at a time in time order:
//   - disk-disk collisions: the first root of |dx + dv s| = r_i + r_j for an
//     approaching pair (gravity moves both alike, so their relative motion
//     stays linear), with the elastic two-body impulse along the centre line;
//   - wall bounces (reflective walls): the first root of a quadratic;
//   - cell crossings: a disk moves between the cells of at least one largest
//     diameter that keep every search local (3 x 3 cells).
// Each disk holds one scheduled event, the earliest of these; a collision
// changes two disks' velocities and counters, which makes every event
// computed with their old motion stale: found lazily when it comes up
// (partner counters, as in Rapaport's and Marin-Risso-Cordero's codes).
// The calendar is the complete binary tree of Marin, Risso and Cordero
// (backends/event_calendar.h).
//
// Round-off: an approaching pair found overlapping collides at once and a
// receding one is never scheduled, so a collision can only repeat after
// another event changed a velocity; a disk found past a wall or a cell
// boundary is treated as on it (Bannerman, Lue and Woods 2014). Under
// gravity a disk arriving at a wall slower than a fall through
// kRestingDepth (1e-12 of the longer box side) bounces that much below
// where it arrived instead, so a resting pile's bounces never take zero
// time; its floor sinks by a few resting depths (tests/test_events.cpp).
//
// Backend::step advances the time by dt per step; dt only sets when the
// state is sampled. The sampled state is the double state projected to the
// current time and rounded to float, which leaves the double state as it
// is: sampling never changes the dynamics.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <tuple>
#include <vector>

#include <carom/types.h>

#include "backends/backend.h"
#include "backends/event_calendar.h"

namespace carom {

// A disk's exact state at the current time, in double.
struct ExactDisk {
    double x, y, vx, vy, mass, radius;
};

class EventDrivenBackend final : public Backend {
public:
    explicit EventDrivenBackend(const WorldDef& world);

    std::string device() const override;
    bool exactArithmetic() const override { return true; }

    // The state at the current time, rounded to float (periodic positions
    // wrapped into the box, wall positions kept inside it).
    void readParticles(std::vector<Particle>& particles) override;
    // The views of the float copy, with the sums of the double state.
    std::optional<ViewSums> readView(ViewValue value, DiskView* out) override;

    // The state at the current time in double, in id order.
    std::vector<ExactDisk> exactState() const { return exactState(nullptr); }
    // Each disk's image for readParticles' positions: images_ holds the
    // wraps of the cell crossings; a disk about to cross, or whose position
    // rounds to the box's side, is wrapped here, and counted here.
    std::vector<Image> images() override;
    // Kinetic energy, and kinetic minus sum m g.x (the conserved total with
    // gravity), at the current time, in double.
    double kineticEnergy() const;
    std::optional<double> exactTotalEnergy() const override;
    // The current time since setParticles (or the origin of the restored state).
    double time() const { return now_; }
    EventCounts eventCounts() const override { return counts_; }
    std::vector<std::array<double, 2>> exactPositions() const override;
    // Cells per row and column of the cell lists (EventDiskState::cell).
    std::uint32_t columns() const { return columns_; }
    std::uint32_t rows() const { return rows_; }

    // What a snapshot keeps, and back (Backend::restoreState): the state
    // is checked whole (eventStateProblem, then the cells) before anything
    // changes.
    std::optional<EventEngineState> saveState() const override;
    void restoreState(const EventEngineState& state) override;

private:
    // exactState(), with each disk's image for its wrapped position in
    // `images` when that is not null.
    std::vector<ExactDisk> exactState(std::vector<Image>* images) const;
    // `exact` (exactState()) rounded to float, as readParticles gives it;
    // `images`, when not null, exactState's images, to which a position
    // rounded up to the side (and so wrapped to 0) adds its wrap.
    std::vector<Particle> roundedParticles(const std::vector<ExactDisk>& exact,
                                           std::vector<Image>* images = nullptr) const;
    // The energies, momentum, mass and v^2 of `exact` summed in double (no values).
    ViewSums exactSums(const std::vector<ExactDisk>& exact) const;

    void load(const std::vector<Particle>& particles) override;
    std::uint64_t advance(std::uint64_t substeps, float dt) override;
    void keepStepStart() override;
    void returnToStepStart() override;
    float maxSpeedSquared() override;
    void drainTallies(ContactTotals& totals) override;
    void addUndrained(ContactTotals& totals) override;
    void motionChanged() override;

    // Disks are stored in the order of their cells (row by row), re-sorted
    // every kSortInterval x N events as they wander, so that a neighbour
    // search reads nearby memory. Every choice between equal times goes by
    // particle id, never by this order: it changes no result.
    void sortByCell();
    // Finds disk i's earliest event from now_ (the disk is at now_) and
    // puts it in the calendar.
    void schedule(std::uint32_t i);
    // When a disk at height h0 above a wall, with velocity u and
    // acceleration a along the wall's inward normal, reaches it.
    double wallTime(double h0, double u, double a) const;
    // Takes the events up to `time` in order, then sets now_ to it, and
    // returns true; with `stoppable`, returns false between two events
    // where stopHere() says stop. Counts the events in lastStepEvents_.
    bool runUntil(double time, bool stoppable);
    // The events: each moves its disks to now_ and schedules them again.
    void collide(std::uint32_t i, std::uint32_t j);
    void bounce(std::uint32_t i, std::int32_t wall);
    void cross(std::uint32_t i, std::int32_t direction);
    // Free flight of disk i to `time`.
    void moveTo(std::uint32_t i, double time);
    // Where free flight takes a disk at (x, y) with velocity (vx, vy) in `s`.
    struct Flight {
        double x, y, vx, vy;
    };
    Flight flight(double x, double y, double vx, double vy, double s) const;
    void link(std::uint32_t i);
    void unlink(std::uint32_t i);

    // What a neighbour search reads, in one cache line per disk: the
    // trajectory, the size, the cell, the next disk in the cell's list.
    struct alignas(64) Disk {
        double x, y, vx, vy;  // at `time` (EventDiskState)
        double time;
        double radius;
        std::int32_t next;         // the next disk in its cell's list (storage index), -1 at the end
        std::uint32_t collisions;  // EventDiskState::collisions
        std::uint32_t cell;        // EventDiskState::cell
        std::uint32_t id;          // its particle id
    };
    // A disk's scheduled event (EventDiskState::eventTime, event with the
    // partner's storage index, partnerCollisions).
    struct Scheduled {
        double time;
        std::int32_t event;
        std::uint32_t partnerCollisions;
    };
    std::vector<Disk> disks_;  // in storage order, as are the three below
    std::vector<Scheduled> scheduled_;
    std::vector<double> mass_;
    std::vector<std::int32_t> previous_;  // the previous disk in its cell's list, -1 at the start
    std::vector<std::int32_t> head_;      // each cell's first disk, -1 for none
    EventCalendar calendar_;              // leaves in storage order, ties by particle id
    std::uint64_t eventsSinceSort_ = 0;
    std::uint64_t eventsAtNow_ = 0;  // events taken since the time last advanced
    double now_ = 0.0;
    // Step `step_` ends at timeOrigin_ + (step_ - stepOrigin_) dt: the origin
    // moves only when setMotion changes dt.
    std::uint64_t step_ = 0, stepOrigin_ = 0;
    double timeOrigin_ = 0.0;
    double width_ = 0.0, height_ = 0.0, gx_ = 0.0, gy_ = 0.0;
    double cellWidth_ = 0.0, cellHeight_ = 0.0, restingDepth_ = 0.0;
    std::uint32_t columns_ = 1, rows_ = 1;
    bool periodic_ = false;
    EventCounts counts_;
    ContactTotals undrained_;           // collisions, virial and wall impulses since the last drainTallies
    std::uint64_t lastStepEvents_ = 0;  // the events of the last runUntil

    // What a step changes: keepStepStart() copies it, returnToStepStart() restores it.
    auto changedByStep() {
        return std::tie(disks_, scheduled_, mass_, previous_, head_, calendar_, eventsSinceSort_, eventsAtNow_, step_,
                        now_, counts_, undrained_);
    }
    std::tuple<std::vector<Disk>, std::vector<Scheduled>, std::vector<double>, std::vector<std::int32_t>,
               std::vector<std::int32_t>, EventCalendar, std::uint64_t, std::uint64_t, std::uint64_t, double,
               EventCounts, ContactTotals>
        kept_;
};

}  // namespace carom
