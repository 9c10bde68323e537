// What the sections of `carom validate` share (app/validate/checks.cpp and
// events.cpp): reproducible random numbers (carom::Random), the periodic box of equal disks
// they start from, measurement in blocks, and the making of checks.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <carom/world.h>

#include "app/validate/checks.h"
#include "backends/backend.h"

namespace carom::validation {

// printf of one number, for messages and criteria.
std::string format(const char* pattern, double value);

// A check that passes when deviation <= limit (false for a NaN deviation).
Check makeCheck(const std::string& section, const std::string& name, double measured, double expected, double deviation,
                double limit, const std::string& criterion);

// Removes the centre-of-mass velocity (a periodic box conserves it, so it
// would carry energy that is not heat).
void removeDrift(std::vector<Particle>& particles);

// Gaussian velocities of variance kT/m per component, zero total momentum, kT exact.
void thermalVelocities(std::vector<Particle>& particles, double kT, std::uint64_t seed);

struct Box {
    WorldDef world;
    std::vector<Particle> particles;
};

// A periodic box of N disks of radius 1 and mass 1 at the packing fraction
// (makeInitialState's hexagonal lattice) with thermal velocities at kT = 1,
// run by the collision scheme given.
Box periodicBox(std::uint32_t particles, double packing, float dt, std::uint64_t seed,
                CollisionScheme scheme = CollisionScheme::Pairwise);

// Steps of dt in `time`, at least one.
std::uint64_t stepsFor(double time, double dt);

// The backend `def` on a box, loaded with its particles.
std::unique_ptr<Backend> loaded(const EngineDef& def, const Box& box);

// Continues the backend's run (a periodic box of equal disks) for `blocks`
// blocks of `blockTime`, measuring each from the contacts the backend
// counts. The velocities are left alone: kT is what the energy gives.
BlockStatistics runBlocks(Backend& backend, int blocks, double blockTime);

// The check of a disk's collision frequency against collisionFrequency,
// within the larger of `target` (relative) and three standard errors.
Check rateCheck(const std::string& section, const std::string& name, const MeanAndError& ratio, double tolerance,
                double target);

// The mean time between two collisions of one disk at kT = 1 (m = 1, sigma = 2).
double collisionTime(double packing);

}  // namespace carom::validation
