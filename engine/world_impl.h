// World's state (include/carom/world.h), shared by engine/world.cpp and the
// checkpoints of engine/io.cpp.
#pragma once

#include <carom/world.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend.h"

namespace carom {

struct World::Impl {
    WorldDef def;
    std::unique_ptr<Backend> backend;
    std::uint64_t step = 0;              // the step the state holds
    std::uint64_t collisionsBefore = 0;  // since the scene began, before the measurements' interval
    std::vector<std::string> warnings;   // the last start's (validateStart)
    double intervalStartTemperature = 0.0;  // kT when the measurements' interval began
    // The state as last read from the backend, while it is current.
    std::vector<Particle> state;
    bool stateCurrent = false;

    const std::vector<Particle>& current() {
        if (!stateCurrent) {
            backend->readParticles(state);
            stateCurrent = true;
        }
        return state;
    }
    // Starts from `particles`, which hold step `step` of a scene in which
    // `collisions` pairs collided so far.
    void start(std::vector<Particle> particles, std::uint64_t step, std::uint64_t collisions);
};

struct WorldAccess {
    static World::Impl& of(const World& world) { return *world.impl_; }
};

}  // namespace carom
