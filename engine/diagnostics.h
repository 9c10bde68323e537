// Measurements of a state, computed once and shared by the CLI and the tests.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "engine/carom.h"

namespace carom {

struct Diagnostics {
    double kineticEnergy = 0.0;           // sum of m v^2 / 2, summed in double in id order
    double potentialEnergy = 0.0;         // in the world's gravity g: -sum of m g.x (0 without gravity)
    std::array<double, 2> momentum{};     // sum of m v
    double maxOverlap = 0.0;              // largest r_i + r_j - |x_i - x_j| over touching pairs, 0 if none
    std::size_t escaped = 0;              // particles whose centre is outside the box or not finite

    double totalEnergy() const { return kineticEnergy + potentialEnergy; }
};

// Every field.
Diagnostics measure(const std::vector<Particle>& particles, const WorldDef& world);
// Energies, momentum and escaped particles: one pass, no grid search
// (maxOverlap stays 0), for callers that measure every frame.
Diagnostics measureMotion(const std::vector<Particle>& particles, const WorldDef& world);

}  // namespace carom
