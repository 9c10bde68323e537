// Helpers shared by the tests: the backends under test and small scenes.
#pragma once

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "backends/backend.h"

namespace carom::test {

// Every backend this build has. Each physics test runs once per backend.
// OpenCL uses the device named by CAROM_TEST_DEVICE (as --device), else the
// default device; PoCL stands in for a GPU on machines without one.
inline std::vector<std::string> backendKinds() { return availableBackends(); }

inline std::unique_ptr<Backend> makeTestBackend(const std::string& kind, const WorldDef& world) {
    const char* device = std::getenv("CAROM_TEST_DEVICE");
    return makeBackend(BackendDef{kind, device ? device : ""}, world);
}

inline Particle disk(float x, float y, float vx, float vy, float mass = 1.0f, float radius = 1.0f) {
    Particle p{};
    p.position = float2{x, y};
    p.velocity = float2{vx, vy};
    p.mass = mass;
    p.radius = radius;
    return p;
}

inline WorldDef box(float width, float height, float dt = 0.01f) {
    WorldDef w;
    w.width = width;
    w.height = height;
    w.dt = dt;
    return w;
}

// Runs `steps` steps of `particles` on a fresh backend and returns the result.
inline std::vector<Particle> simulate(const std::string& kind, const WorldDef& world,
                                      const std::vector<Particle>& particles, std::uint64_t steps,
                                      std::uint64_t* collisions = nullptr, ContactTotals* contacts = nullptr) {
    auto backend = makeTestBackend(kind, world);
    backend->setParticles(particles);
    backend->step(steps);
    std::vector<Particle> result;
    backend->readParticles(result);
    if (collisions) *collisions = backend->collisions();
    if (contacts) *contacts = backend->contacts();
    return result;
}

}  // namespace carom::test
