#include "app/validate/runs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/diagnostics.h"
#include "engine/observables.h"

namespace carom::validation {

namespace {

// Scales the velocities so that temperature(particles, Periodic) is kT.
void scaleToTemperature(std::vector<Particle>& particles, double kT) {
    const double scale = std::sqrt(kT / temperature(particles, Boundary::Periodic));
    for (Particle& p : particles) {
        p.velocity.x = float(p.velocity.x * scale);
        p.velocity.y = float(p.velocity.y * scale);
    }
}

// The fewest blocks the error estimate merges blocks down to.
constexpr std::size_t kMinMergedBlocks = 8;

}  // namespace

std::string format(const char* pattern, double value) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

Check makeCheck(const std::string& section, const std::string& name, double measured, double expected, double deviation,
                double limit, const std::string& criterion) {
    Check c{section, name, measured, expected, deviation, limit, criterion, false};
    c.passed = deviation <= limit;  // false for NaN
    return c;
}

void removeDrift(std::vector<Particle>& particles) {
    double mass = 0, px = 0, py = 0;
    for (const Particle& p : particles) {
        mass += p.mass;
        px += double(p.mass) * p.velocity.x;
        py += double(p.mass) * p.velocity.y;
    }
    for (Particle& p : particles) {
        p.velocity.x = float(p.velocity.x - px / mass);
        p.velocity.y = float(p.velocity.y - py / mass);
    }
}

void thermalVelocities(std::vector<Particle>& particles, double kT, std::uint64_t seed) {
    Random random(seed);
    for (Particle& p : particles) {
        const double s = std::sqrt(kT / p.mass);
        p.velocity.x = float(s * random.normal());
        p.velocity.y = float(s * random.normal());
    }
    removeDrift(particles);
    scaleToTemperature(particles, kT);
}

Box periodicBox(std::uint32_t particles, double packing, float dt, std::uint64_t seed, CollisionScheme scheme) {
    SceneDef scene;
    scene.particles = particles;
    scene.packing = float(packing);
    scene.seed = seed;
    InitialState initial = makeInitialState(scene);
    Box box;
    box.world.width = initial.width;
    box.world.height = initial.height;
    box.world.dt = dt;
    box.world.boundary = Boundary::Periodic;
    box.world.collisions = scheme;
    box.particles = std::move(initial.particles);
    thermalVelocities(box.particles, 1.0, seed ^ 0x9e3779b97f4a7c15ull);
    return box;
}

std::uint64_t stepsFor(double time, double dt) { return std::max<std::uint64_t>(1, std::llround(time / dt)); }

std::unique_ptr<Backend> loaded(const EngineDef& def, const Box& box) {
    std::unique_ptr<Backend> backend = makeBackend(def, box.world);
    backend->setParticles(box.particles);
    return backend;
}

BlockStatistics runBlocks(Backend& backend, int blocks, double blockTime) {
    const WorldDef& world = backend.world();
    const std::uint64_t steps = stepsFor(blockTime, world.dt);
    std::vector<Particle> state;
    backend.readParticles(state);
    const double n = double(state.size());
    const double diameter = 2.0 * state.front().radius, mass = state.front().mass;
    const double energyStart = measure(state, world).totalEnergy();
    double kTStart = temperature(state, world.boundary);
    BlockStatistics result;
    result.blocks = blocks;
    result.blockTime = blockTime;
    std::vector<double> z, rateRatio;
    for (int b = 0; b < blocks; ++b) {
        backend.resetContacts();
        backend.step(steps);
        backend.readParticles(state);
        const double kTEnd = temperature(state, world.boundary);
        const double kT = 0.5 * (kTStart + kTEnd);
        kTStart = kTEnd;
        const ContactTotals& contacts = backend.contacts();
        const Thermodynamics t = thermodynamics(contacts, kT, state.size(), world);
        z.push_back(t.virialZ);
        // The identity relates the frequency to the collisions' share of Z,
        // sigma sum J / (2 N kT t): Z - 1 only as N -> infinity, since the
        // kinetic share is (N - 1) / N in a periodic box (at N = 4096 and
        // eta = 0.1 the difference is 0.1 % of the frequency).
        const double collisionalZ = contacts.virial / (2.0 * contacts.time * n * kT);
        rateRatio.push_back(2.0 * t.collisionRate / collisionFrequency(1.0 + collisionalZ, kT, diameter, mass));
        result.collisionRate += t.collisionRate / blocks;
        result.kT += kT / blocks;
        result.lateContacts += contacts.lateContacts;
        result.maxRounds = std::max(result.maxRounds, contacts.maxRounds);
    }
    result.zBlocks = z;
    result.z = blockingAverage(z, kMinMergedBlocks);
    result.rateRatio = blockingAverage(rateRatio, kMinMergedBlocks);
    result.energyChange = measure(state, world).totalEnergy() / energyStart - 1.0;
    return result;
}

Check rateCheck(const std::string& section, const std::string& name, const MeanAndError& ratio, double tolerance,
                double target) {
    const std::string bound = target > 0 ? "max(" + format("%.2g", 100 * target) + " %, 3 standard errors)"
                                         : std::string("3 standard errors");
    return makeCheck(
        section, name, ratio.mean, 1.0, std::abs(ratio.mean - 1.0), tolerance,
        "|omega / (4 Z_c/sigma sqrt(kT/pi m)) - 1| <= " + bound + " = " + format("%.2g", 100 * tolerance) + " %");
}

double collisionTime(double packing) { return 1.0 / collisionFrequency(referenceZ(packing), 1.0, 2.0, 1.0); }

}  // namespace carom::validation
