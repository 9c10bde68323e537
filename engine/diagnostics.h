// Measurements of a state, computed once and shared by the CLI and the tests.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/scene.h"

namespace carom {

struct Diagnostics {
    double kineticEnergy = 0.0;        // sum of m v^2 / 2, summed in double in id order
    double potentialEnergy = 0.0;      // in the world's gravity g: -sum of m g.x (0 without gravity)
    std::array<double, 2> momentum{};  // sum of m v
    double maxOverlap = 0.0;           // largest r_i + r_j - |x_i - x_j| over touching pairs, 0 if none
    std::size_t escaped = 0;           // particles whose centre is outside the box or not finite

    double totalEnergy() const { return kineticEnergy + potentialEnergy; }
};

// The overlapping pairs of a state, found in O(N log N) (sortIntoCells).
// A pile of disks can overlap in ~N^2 pairs: counting stops after
// kOverlapsCountedPerDisk x N, far more than any state a run leaves (whose
// overlaps are a step's, a few per disk).
constexpr std::size_t kOverlapsCountedPerDisk = 8;
struct Overlaps {
    std::size_t pairs = 0;                          // pairs with r_i + r_j > |x_i - x_j|
    bool allCounted = true;                         // false where counting stopped: more than `pairs` overlap,
                                                    //   deepest the deepest among them
    double deepest = 0.0;                           // the largest r_i + r_j - |x_i - x_j|, 0 if none
    std::array<std::uint32_t, 2> deepestPair{};     // the ids of that pair (the lowest on ties)
    std::size_t coincident = 0;                     // pairs whose centres are equal (no collision normal),
                                                    //   all counted
    std::array<std::uint32_t, 2> coincidentPair{};  // the one with the lowest first id, then second id
};
Overlaps findOverlaps(const std::vector<Particle>& particles, const WorldDef& world);
// r_a + r_b - |x_a - x_b| in double, to the nearest image in a periodic box.
double overlapOf(const Particle& a, const Particle& b, const WorldDef& world);
// Counts a pair that overlaps by `overlap` into `found`, as findOverlaps
// does; false, counting nothing, once `found` holds `counted` pairs.
bool countOverlap(Overlaps& found, std::size_t counted, std::array<std::uint32_t, 2> pair, double overlap);

// Every field.
Diagnostics measure(const std::vector<Particle>& particles, const WorldDef& world);
// Energies, momentum and escaped particles: one pass, no grid search
// (maxOverlap stays 0), for callers that measure every frame.
Diagnostics measureMotion(const std::vector<Particle>& particles, const WorldDef& world);
// World::readView on the host: the views in the particles' order, into
// out[0..size), and their sums, in double.
ViewSums measureView(const std::vector<Particle>& particles, const WorldDef& world, ViewValue value, DiskView* out);

}  // namespace carom
