// The Backend interface: one implementation per compute device family.
//
// A step is always: build the grid (engine/grid.h) -> resolveCollisions ->
// integrate, with the per-particle physics of kernels/physics.h. Backends
// differ only in where those loops run.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/carom.h"
#include "engine/grid.h"

namespace carom {

class Backend {
public:
    explicit Backend(const WorldDef& world);
    virtual ~Backend() = default;
    Backend(const Backend&) = delete;
    Backend& operator=(const Backend&) = delete;

    virtual std::string name() const = 0;    // "cpu" or "opencl"
    virtual std::string device() const = 0;  // human-readable device description
    // True when divide and sqrt are correctly rounded, so that this backend's
    // trajectories are bitwise identical to the CPU backend's.
    virtual bool exactArithmetic() const = 0;

    // Validates the particles against the world, sizes the grid for their
    // largest radius, loads them and resets the collision counter.
    void setParticles(const std::vector<Particle>& particles);
    // Advances the simulation by `steps` steps of world().dt.
    virtual void step(std::uint64_t steps) = 0;
    // Copies the current state into `particles` (in id order).
    virtual void readParticles(std::vector<Particle>& particles) = 0;
    // Pairs that received an impulse, summed over all steps since setParticles.
    virtual std::uint64_t collisions() = 0;

    // Changes dt and gravity between steps (the box stays fixed); throws
    // Error for values out of range.
    void setMotion(float dt, float2 gravity);

    const WorldDef& world() const { return world_; }
    std::size_t particleCount() const { return particleCount_; }

protected:
    virtual void load(const std::vector<Particle>& particles) = 0;

    WorldDef world_;
    Grid grid_;  // geometry fixed by setParticles, contents rebuilt each step
    std::size_t particleCount_ = 0;
};

// Creates the backend `def.kind` for the world; throws Error for an unknown
// kind or device, or when OpenCL is unavailable.
std::unique_ptr<Backend> makeBackend(const BackendDef& def, const WorldDef& world);

// The backend kinds this build offers, for messages and tests.
std::vector<std::string> availableBackends();

}  // namespace carom
