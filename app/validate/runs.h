// What the sections of `carom validate` share (app/validate/checks.cpp and
// events.cpp): the periodic box of equal disks they start from (drawn with
// carom::Random, reproducible everywhere), worlds on an engine, measurement
// in blocks, and the making of checks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "app/format.h"

#include <carom/carom.h>

#include "app/validate/checks.h"

namespace carom::validation {

using app::format;  // app/format.h

// A check that passes when deviation <= limit (false for a NaN deviation).
Check makeCheck(const std::string& section, const std::string& name, double measured, double expected, double deviation,
                double limit, const std::string& criterion);

// Removes the centre-of-mass velocity (a periodic box conserves it, so it
// would carry energy that is not heat).
void removeDrift(std::vector<Disk>& disks);

struct Box {
    WorldDef world;
    std::vector<Disk> disks;
};

// A periodic box of N disks of radius 1 and mass 1 at the packing fraction
// (makeScene's hexagonal lattice) with thermal velocities at kT = 1: Gaussian
// of variance kT/m per component, zero total momentum, kT exact. Run by the
// collision scheme given.
Box periodicBox(std::uint32_t particles, double packing, float dt, std::uint64_t seed,
                CollisionScheme scheme = CollisionScheme::Pairwise);

// Steps of dt in `time`, at least one.
std::uint64_t stepsFor(double time, double dt);

// The world `def` on `engine`, loaded with `disks`.
World loaded(const EngineDef& engine, const WorldDef& def, const std::vector<Disk>& disks);
// The box on `engine`.
World loaded(const EngineDef& engine, const Box& box);

// The energy of the world's disks as disks() gives them, in float (with
// the events scheme World::totalEnergy is the engine's exact double one).
double diskEnergy(const World& world);

// Continues the world's run (a periodic box of equal disks) for `blocks`
// blocks of `blockTime`, measuring each from its Measurements. The
// velocities are left alone: kT is what the energy gives.
BlockStatistics runBlocks(World& world, int blocks, double blockTime);

// The check of a disk's collision frequency against collisionFrequency,
// within the larger of `target` (relative) and three standard errors.
Check rateCheck(const std::string& section, const std::string& name, const MeanAndError& ratio, double tolerance,
                double target);

// The mean time between two collisions of one disk at kT = 1 (m = 1, sigma = 2).
double collisionTime(double packing);

}  // namespace carom::validation
