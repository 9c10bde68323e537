// Helpers shared by the tests: the backends under test and small scenes.
#pragma once

#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "backends/backend.h"

namespace carom::test {

// Every backend this build has. Each physics test runs once per backend.
// OpenCL uses the device named by CAROM_TEST_DEVICE (as --device), else the
// default device; PoCL stands in for a GPU on machines without one.
inline std::vector<std::string> backendKinds() { return availableBackends(); }

// Backend `kind` (and OpenCL `pipeline`) on the device under test.
inline BackendDef testBackendDef(const std::string& kind, const std::string& pipeline = "seed") {
    const char* device = std::getenv("CAROM_TEST_DEVICE");
    return BackendDef{kind, device ? device : "", pipeline};
}

inline std::unique_ptr<Backend> makeTestBackend(const std::string& kind, const WorldDef& world) {
    return makeBackend(testBackendDef(kind), world);
}

// Every backend and OpenCL pipeline this build has.
inline std::vector<BackendDef> backendPipelines() {
    std::vector<BackendDef> defs;
    for (const std::string& kind : availableBackends()) {
        if (kind != "opencl") {
            defs.push_back(testBackendDef(kind));
            continue;
        }
        for (const char* pipeline : {"seed", "resident"}) defs.push_back(testBackendDef(kind, pipeline));
    }
    return defs;
}

// "cpu", "opencl seed", "opencl resident": for CAPTURE.
inline std::string describe(const BackendDef& def) {
    return def.kind == "opencl" ? def.kind + " " + def.pipeline : def.kind;
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

// What a run leaves: the particles and the contact totals.
struct Run {
    std::vector<Particle> particles;
    ContactTotals contacts;
};

// Runs `steps` steps of `particles` on a fresh backend `def`.
inline Run run(const BackendDef& def, const WorldDef& world, const std::vector<Particle>& particles,
               std::uint64_t steps) {
    auto backend = makeBackend(def, world);
    backend->setParticles(particles);
    backend->step(steps);
    Run r;
    backend->readParticles(r.particles);
    r.contacts = backend->contacts();
    return r;
}

// Runs `steps` steps of `particles` on a fresh backend and returns the result.
inline std::vector<Particle> simulate(const std::string& kind, const WorldDef& world,
                                      const std::vector<Particle>& particles, std::uint64_t steps,
                                      std::uint64_t* collisions = nullptr, ContactTotals* contacts = nullptr) {
    Run r = run(testBackendDef(kind), world, particles, steps);
    if (collisions) *collisions = r.contacts.collisions;
    if (contacts) *contacts = r.contacts;
    return std::move(r.particles);
}

}  // namespace carom::test
