#include "app/validate/runs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace carom::validation {

namespace {

// kT of `disks` in the periodic box `world`, as World measures it.
double temperatureOf(const WorldDef& world, const std::vector<Disk>& disks) {
    World measuring(world);
    measuring.setDisks(disks);
    return measuring.temperature();
}

// Gaussian velocities of variance kT/m per component, zero total momentum,
// kT exact (in the periodic box `world`).
void thermalVelocities(const WorldDef& world, std::vector<Disk>& disks, double kT, std::uint64_t seed) {
    Random random(seed);
    for (Disk& d : disks) {
        const double s = std::sqrt(kT / d.mass);
        d.velocity.x = float(s * random.normal());
        d.velocity.y = float(s * random.normal());
    }
    removeDrift(disks);
    const double scale = std::sqrt(kT / temperatureOf(world, disks));
    for (Disk& d : disks) {
        d.velocity.x = float(d.velocity.x * scale);
        d.velocity.y = float(d.velocity.y * scale);
    }
}

// The fewest blocks the error estimate merges blocks down to.
constexpr std::size_t kMinMergedBlocks = 8;

}  // namespace

Check makeCheck(const std::string& section, const std::string& name, double measured, double expected, double deviation,
                double limit, const std::string& criterion) {
    Check c{section, name, measured, expected, deviation, limit, criterion, false};
    c.passed = deviation <= limit;  // false for NaN
    return c;
}

void removeDrift(std::vector<Disk>& disks) {
    double mass = 0, px = 0, py = 0;
    for (const Disk& d : disks) {
        mass += d.mass;
        px += double(d.mass) * d.velocity.x;
        py += double(d.mass) * d.velocity.y;
    }
    for (Disk& d : disks) {
        d.velocity.x = float(d.velocity.x - px / mass);
        d.velocity.y = float(d.velocity.y - py / mass);
    }
}

Box periodicBox(std::uint32_t particles, double packing, float dt, std::uint64_t seed, CollisionScheme scheme) {
    SceneDef def;
    def.particles = particles;
    def.packing = float(packing);
    def.seed = seed;
    Scene scene = makeScene(def);
    Box box;
    box.world.width = scene.width;
    box.world.height = scene.height;
    box.world.dt = dt;
    box.world.boundary = Boundary::Periodic;
    box.world.collisions = scheme;
    box.disks = std::move(scene.disks);
    thermalVelocities(box.world, box.disks, 1.0, seed ^ 0x9e3779b97f4a7c15ull);
    return box;
}

std::uint64_t stepsFor(double time, double dt) { return std::max<std::uint64_t>(1, std::llround(time / dt)); }

World loaded(const EngineDef& engine, const WorldDef& def, const std::vector<Disk>& disks) {
    World world(onEngine(def, engine));
    world.setDisks(disks);
    return world;
}

World loaded(const EngineDef& engine, const Box& box) { return loaded(engine, box.world, box.disks); }

double diskEnergy(const World& world) { return world.kineticEnergy() + world.potentialEnergy(); }

BlockStatistics runBlocks(World& world, int blocks, double blockTime) {
    const std::uint64_t steps = stepsFor(blockTime, world.def().dt);
    const Disk first = world.disks().front();
    const double n = double(world.diskCount());
    const double diameter = 2.0 * first.radius, mass = first.mass;
    const double energyStart = diskEnergy(world);
    BlockStatistics result;
    result.blocks = blocks;
    result.blockTime = blockTime;
    std::vector<double> z, rateRatio;
    for (int b = 0; b < blocks; ++b) {
        world.resetMeasurements();
        world.step(steps);
        // kT is the mean of the block's first and last.
        const Measurements m = world.measurements();
        z.push_back(m.compressibility);
        // The identity relates the frequency to the collisions' share of Z,
        // sigma sum J / (2 N kT t): Z - 1 only as N -> infinity, since the
        // kinetic share is (N - 1) / N in a periodic box (at N = 4096 and
        // eta = 0.1 the difference is 0.1 % of the frequency).
        const double collisionalZ = m.collisionVirial / (2.0 * m.time * n * m.temperature);
        rateRatio.push_back(2.0 * m.collisionRate /
                            collisionFrequency(1.0 + collisionalZ, m.temperature, diameter, mass));
        result.collisionRate += m.collisionRate / blocks;
        result.kT += m.temperature / blocks;
        result.lateContacts += m.lateContacts;
        result.maxRounds = std::max(result.maxRounds, m.maxRounds);
    }
    result.zBlocks = z;
    result.z = blockingAverage(z, kMinMergedBlocks);
    result.rateRatio = blockingAverage(rateRatio, kMinMergedBlocks);
    result.energyChange = diskEnergy(world) / energyStart - 1.0;
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
