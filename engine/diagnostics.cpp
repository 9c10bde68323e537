#include "engine/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/grid.h"
#include "engine/parallel.h"

namespace carom {

namespace {

// Entries of the sorted disks per run of cells that findOverlaps searches on
// one thread: large enough that a run's share of the wave's wait is small.
constexpr std::size_t kOverlapRun = 1 << 16;

// Whether a pair overlapping by `overlap` is the deepest of those `found`
// holds: deeper, or as deep with the lower ids (so in any order of visits).
bool deeper(double overlap, std::array<std::uint32_t, 2> pair, const Overlaps& found) {
    return overlap > found.deepest || (overlap == found.deepest && found.pairs > 0 && pair < found.deepestPair);
}

// One disk's share of the sums, in double: measureMotion and measureView add
// the same terms, so their energies and momentum agree bit for bit.
struct MotionTerms {
    double speedSquared, kinetic, potential;  // v^2, m v^2 / 2, -m g . x
    std::array<double, 2> momentum;           // m v
};

MotionTerms motionTerms(const Particle& p, const WorldDef& world) {
    const double vx = p.velocity.x, vy = p.velocity.y, speedSquared = vx * vx + vy * vy;
    return {speedSquared,
            0.5 * p.mass * speedSquared,
            -(p.mass * (double(world.gravity.x) * p.position.x + double(world.gravity.y) * p.position.y)),
            {p.mass * vx, p.mass * vy}};
}

}  // namespace

Diagnostics measureMotion(const std::vector<Particle>& particles, const WorldDef& world) {
    Diagnostics d;
    for (const Particle& p : particles) {
        const MotionTerms terms = motionTerms(p, world);
        d.kineticEnergy += terms.kinetic;
        d.momentum[0] += terms.momentum[0];
        d.momentum[1] += terms.momentum[1];
        d.potentialEnergy += terms.potential;
        const float2 x = p.position;
        const bool inside = x.x >= 0.0f && x.x <= world.width && x.y >= 0.0f && x.y <= world.height;
        if (!inside) ++d.escaped;  // also counts NaN
    }
    return d;
}

ViewSums measureView(const std::vector<Particle>& particles, const WorldDef& world, ViewValue value, DiskView* out) {
    ViewSums sums;
    sums.minValue = particles.empty() ? 0.0f : HUGE_VALF;
    sums.maxValue = particles.empty() ? 0.0f : -HUGE_VALF;
    for (std::size_t i = 0; i < particles.size(); ++i) {
        const Particle& p = particles[i];
        float shown = p.radius;
        switch (value) {
            case ViewValue::Speed: shown = std::sqrt(p.velocity.x * p.velocity.x + p.velocity.y * p.velocity.y); break;
            case ViewValue::Mass: shown = p.mass; break;
            case ViewValue::Radius: break;
            case ViewValue::Id: shown = float(i); break;
        }
        out[i] = {p.position, p.radius, shown};
        const MotionTerms terms = motionTerms(p, world);
        sums.kineticEnergy += terms.kinetic;
        sums.potentialEnergy += terms.potential;
        sums.momentum[0] += terms.momentum[0];
        sums.momentum[1] += terms.momentum[1];
        sums.mass += p.mass;
        sums.speedSquared += terms.speedSquared;
        sums.minValue = std::min(sums.minValue, shown);
        sums.maxValue = std::max(sums.maxValue, shown);
    }
    return sums;
}

double overlapOf(const Particle& a, const Particle& b, const WorldDef& world) {
    const bool periodic = world.boundary == Boundary::Periodic;
    // The separation along one axis, to the nearest image in a periodic box.
    const auto separation = [&](double d, double extent) {
        if (!periodic) return d;
        return d - extent * std::round(d / extent);
    };
    const double distance = std::hypot(separation(double(a.position.x) - b.position.x, world.width),
                                       separation(double(a.position.y) - b.position.y, world.height));
    return double(a.radius) + b.radius - distance;
}

bool countOverlap(Overlaps& found, std::size_t counted, std::array<std::uint32_t, 2> pair, double overlap) {
    if (found.pairs == counted) return false;  // one more than counted: "more than"
    if (deeper(overlap, pair, found)) {
        found.deepest = overlap;
        found.deepestPair = pair;
    }
    ++found.pairs;
    return true;
}

Overlaps findOverlaps(const std::vector<Particle>& particles, const WorldDef& world) {
    Overlaps found;
    const DiskCells cells = sortIntoCells(particles.data(), particles.size(), caromBoxOf(world));
    // Equal centres lie next to each other, ids ascending: a run of k is
    // k (k - 1) / 2 pairs, its first two ids the lowest pair.
    for (auto first = cells.sorted.begin(); first != cells.sorted.end();) {
        const auto last = std::find_if(first, cells.sorted.end(),
                                       [&](const DiskCells::Entry& e) { return e.x != first->x || e.y != first->y; });
        const std::size_t k = std::size_t(last - first);
        if (k > 1) {
            const std::array<std::uint32_t, 2> pair{first[0].id, first[1].id};
            if (found.coincident == 0 || pair < found.coincidentPair) found.coincidentPair = pair;
            found.coincident += k * (k - 1) / 2;
        }
        first = last;
    }

    const std::size_t counted = kOverlapsCountedPerDisk * particles.size();
    // Visits the pairs of sorted[from, to) into `into` until it holds `counted`.
    const auto search = [&](std::size_t from, std::size_t to, Overlaps& into) {
        return forEachOverlappingPairIn(cells, from, to, [&](std::uint32_t i, std::uint32_t j) {
            return countOverlap(into, counted, {i, j}, overlapOf(particles[i], particles[j], world));
        });
    };
    // Runs of cells searched in parallel, a wave at a time, and taken in
    // order: the deepest pair is the same whichever run found it. The run
    // in which the count passes `counted` is searched again from where the
    // runs before it left off, so the pairs counted are those a search in
    // one pass counts, and a wave past that point is all the extra work.
    const std::vector<std::size_t> runs = cellRuns(cells, kOverlapRun);
    const std::size_t runCount = runs.size() - 1;
    const std::size_t wave = 4 * std::size_t(parallelThreads());
    std::vector<Overlaps> parts(std::min(wave, runCount));
    for (std::size_t first = 0; first < runCount; first += wave) {
        const auto n = static_cast<std::int64_t>(std::min(wave, runCount - first));
#pragma omp parallel for schedule(dynamic, 1) if (n > 1)
        for (std::int64_t r = 0; r < n; ++r) {
            parts[std::size_t(r)] = Overlaps{};
            parts[std::size_t(r)].allCounted =
                search(runs[first + std::size_t(r)], runs[first + std::size_t(r) + 1], parts[std::size_t(r)]);
        }
        for (std::size_t r = 0; r < std::size_t(n); ++r) {
            const Overlaps& part = parts[r];
            if (!part.allCounted || found.pairs + part.pairs > counted) {
                found.allCounted = search(runs[first + r], cells.sorted.size(), found);
                return found;
            }
            if (part.pairs > 0 && deeper(part.deepest, part.deepestPair, found)) {
                found.deepest = part.deepest;
                found.deepestPair = part.deepestPair;
            }
            found.pairs += part.pairs;
        }
    }
    return found;
}

Diagnostics measure(const std::vector<Particle>& particles, const WorldDef& world) {
    Diagnostics d = measureMotion(particles, world);
    d.maxOverlap = findOverlaps(particles, world).deepest;
    return d;
}

}  // namespace carom
