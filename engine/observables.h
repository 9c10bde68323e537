// Temperature, pressure and collision rate: what a gas's state and its
// collisions say about it, with the formulas of the hard-disk reference
// (docs/validation/README.md cites them).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/scene.h"

namespace carom {

// What the collisions and walls did over an interval, summed by the backend
// (Backend::contacts()).
struct ContactTotals {
    std::uint64_t collisions = 0;         // pairs that received an impulse, each pair once
    double virial = 0.0;                  // sum over those impulses of r_ij . J_ij = 2 mu_ij |v_n| r_ij
                                          //   [mass length^2/time]
    std::array<double, 4> wallImpulse{};  // momentum delivered to the left, right, bottom
                                          //   and top wall [mass length/time]
    double time = 0.0;                    // simulated time covered [time]
    std::uint64_t steps = 0;              // steps taken
    std::uint64_t substeps = 0;           // substeps taken (more than steps with maxTravel > 0 or the
                                          //   pairwise scheme's grid allowance)
    // Pairwise scheme only:
    std::uint64_t lateContacts = 0;  // pairs resolved while overlapping beyond rounding, and disks
                                     //   found past a wall: contacts the rounds could not order in time
    std::uint32_t maxRounds = 0;     // the most rounds one (sub)step used (kMaxPairwiseRounds at most)
};

// kT of a state (k = 1) [mass length^2/time^2]: the kinetic energy per
// degree-of-freedom pair. With walls, E_kin / N. In a periodic box the
// centre of mass moves freely and carries no heat: (E_kin - P^2/2M) / (N - 1).
double temperature(const std::vector<Particle>& particles, Boundary boundary);

// Pressure and rates over the interval `contacts` covers, at temperature kT.
struct Thermodynamics {
    double temperature = 0.0;    // kT, as given
    double collisionRate = 0.0;  // collisions per particle per unit time, each pair once
                                 //   (a disk's own collision frequency is twice this)
    // Collision virial pressure: P A = E_kin + virial / (2 t), E_kin the
    // thermal kinetic energy ((N - 1) kT in a periodic box, N kT with walls).
    // Exact for a periodic box; with walls it misses the walls' share (use
    // wallPressure).
    double virialPressure = 0.0;  // [mass/time^2]
    double virialZ = 0.0;         // P A / (N kT), the compressibility factor
    // Walls only (zero in a periodic box): impulse / (t x wall length).
    std::array<double, 4> wallPressure{};  // left, right, bottom, top
    double wallPressureMean = 0.0;         // all walls' impulse / (t x perimeter)
    double wallZ = 0.0;                    // wallPressureMean A / (N kT), A = W H
};

Thermodynamics thermodynamics(const ContactTotals& contacts, double kT, std::size_t particleCount,
                              const WorldDef& world);

}  // namespace carom
