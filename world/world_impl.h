// World's state (include/carom/world.h), shared by world/world.cpp and the
// checkpoints of io/io.cpp.
#pragma once

#include <carom/world.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "engine/diagnostics.h"

namespace carom {

struct World::Impl {
    WorldDef def;
    std::unique_ptr<Backend> backend;
    std::uint64_t step = 0;  // the step the state holds
    // time() = motionTime + (step - motionStep) x dt: dt may change (setMotion).
    double motionTime = 0.0;
    std::uint64_t motionStep = 0;
    std::uint64_t collisionsBefore = 0;     // since the scene began, before the measurements' interval
    std::vector<std::string> warnings;      // the last start's (validateStart)
    double intervalStartTemperature = 0.0;  // kT when the measurements' interval began
    // The state as last read from the backend, and its energies and
    // momentum, while they are current (one read and one pass per state,
    // however many observables a caller asks for).
    std::vector<Particle> state;
    bool stateCurrent = false;
    Diagnostics stateMotion;
    bool motionCurrent = false;

    double time() const { return motionTime + double(step - motionStep) * def.dt; }
    const std::vector<Particle>& current() {
        if (!stateCurrent && backend->particleCount() > 0) {
            backend->readParticles(state);
            stateCurrent = true;
            motionCurrent = false;
        }
        return state;
    }
    const Diagnostics& motion() {
        current();
        if (!motionCurrent) {
            stateMotion = measureMotion(state, def);
            motionCurrent = true;
        }
        return stateMotion;
    }
    // Starts from `particles`, which hold step `step` of a scene in which
    // `collisions` pairs collided so far; `source` names them in messages.
    void start(std::vector<Particle> particles, std::uint64_t step, double time, std::uint64_t collisions,
               const std::string& source, DeepOverlaps deepOverlaps = DeepOverlaps::Warn);
    // Replaces the state with an edited one, at the same step and collision count.
    void edit(std::vector<Particle> particles);
    // Loads `particles` as the state at `step`, with `collisions` so far.
    void load(std::vector<Particle> particles, std::uint64_t step, std::uint64_t collisions);
};

struct WorldAccess {
    static World::Impl& of(const World& world) { return *world.impl_; }
};

}  // namespace carom
