// World::setStopCheck: a stop request is honoured within a step (between
// events, between substeps), and a step cut short returns to its start, so
// that stepping on gives the bits of a call never stopped.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <vector>

#include <carom/carom.h>

#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

using Clock = std::chrono::steady_clock;

Scene gas(std::uint32_t count, float speed) {
    SceneDef def;
    def.particles = count;
    def.packing = 0.3f;
    def.speed = speed;
    def.seed = 11;
    return makeScene(def);
}

World worldOf(const Scene& scene, const EngineDef& engine, CollisionScheme scheme, float dt, float maxTravel,
              Boundary boundary = Boundary::Walls) {
    WorldDef def;
    def.width = scene.width;
    def.height = scene.height;
    def.boundary = boundary;
    def.dt = dt;
    def.collisions = scheme;
    def.maxTravel = maxTravel;
    def.engine = engine.engine;
    def.device = engine.device;
    World world(def);
    world.setDisks(scene.disks);
    return world;
}

bool sameDisks(const World& a, const World& b) {
    const std::vector<Disk> x = a.disks(), y = b.disks();
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(Disk)) == 0;
}

// A check that says stop at its first call, which step() makes only after
// running for a while (kStopCheckInterval): within the step.
struct StopAtOnce {
    int* calls;
    bool operator()() const { return ++*calls > 0; }
};

// Steps `world`, whose first step is long, with a check that stops it at
// once; then checks that it holds its start, and that stepping on without
// the check gives what `fresh` (the same world, never stopped) gives.
void requireStopReturnsToTheStart(World& world, World& fresh, std::uint64_t steps) {
    const std::vector<Disk> start = world.disks();
    const double startEnergy = world.totalEnergy();
    int calls = 0;
    world.setStopCheck(StopAtOnce{&calls});
    world.step(steps);
    CHECK(calls == 1);
    CHECK(world.stepCount() == 0);
    CHECK(world.time() == 0.0);
    CHECK(world.collisionCount() == 0);
    CHECK(world.measurements().substeps == 0);
    CHECK(world.totalEnergy() == startEnergy);
    const std::vector<Disk> now = world.disks();
    CHECK(std::memcmp(now.data(), start.data(), start.size() * sizeof(Disk)) == 0);

    world.setStopCheck({});
    world.step(steps);
    fresh.step(steps);
    CHECK(world.stepCount() == steps);
    CHECK(sameDisks(world, fresh));
    CHECK(world.collisionCount() == fresh.collisionCount());
    CHECK(world.measurements().substeps == fresh.measurements().substeps);
    CHECK(world.measurements().collisionVirial == fresh.measurements().collisionVirial);
    CHECK(world.snapshot().time == fresh.snapshot().time);
}

}  // namespace

TEST_CASE("stop: a stop check cuts an events step short between events, and the world returns to its start") {
    // One step of ~10^5 events: far longer than the check's interval.
    const Scene scene = gas(2000, 300.0f);
    World world = worldOf(scene, EngineDef{}, CollisionScheme::Events, 1.0f, 0.0f);
    World fresh = worldOf(scene, EngineDef{}, CollisionScheme::Events, 1.0f, 0.0f);
    requireStopReturnsToTheStart(world, fresh, 1);
    CHECK(world.eventCounts().collisions == fresh.eventCounts().collisions);
    CHECK(world.exactPositions() == fresh.exactPositions());
}

CAROM_BACKEND_TEST_CASE("stop: a stop check cuts a step of many substeps short, and the world returns to its start") {
    // maxTravel 3 x 10^-4 of a radius at this speed: ~1 700 substeps in one step.
    const Scene scene = gas(2000, 10.0f);
    World world = worldOf(scene, def, CollisionScheme::Pairwise, 0.05f, 3e-4f);
    World fresh = worldOf(scene, def, CollisionScheme::Pairwise, 0.05f, 3e-4f);
    requireStopReturnsToTheStart(world, fresh, 1);
}

TEST_CASE("stop: a stop check stops many short steps between two, promptly, and the steps taken are whole") {
    const Scene scene = gas(2000, 1.0f);
    for (CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Events}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        World world = worldOf(scene, EngineDef{}, scheme, 0.01f, 0.0f);
        const Clock::time_point start = Clock::now();
        world.setStopCheck([start] { return Clock::now() - start > std::chrono::milliseconds(100); });
        world.step(std::uint64_t(1) << 40);
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        CHECK(seconds < 5.0);  // 0.1 s and a check's interval, with room for a loaded machine
        const std::uint64_t taken = world.stepCount();
        CHECK(taken > 0);
        CHECK(world.time() == double(taken) * double(0.01f));
        World fresh = worldOf(scene, EngineDef{}, scheme, 0.01f, 0.0f);
        fresh.step(taken);
        CHECK(sameDisks(world, fresh));
        CHECK(world.collisionCount() == fresh.collisionCount());
    }
}

TEST_CASE("stop: a restored events world keeps its stop check") {
    const Scene scene = gas(2000, 1e3f);
    World world = worldOf(scene, EngineDef{}, CollisionScheme::Events, 1.0f, 0.0f);
    int calls = 0;
    world.setStopCheck(StopAtOnce{&calls});
    world.restore(world.snapshot());  // an events restore replaces the engine
    world.step(1);
    CHECK(calls == 1);
    CHECK(world.stepCount() == 0);
}

// The tallies are drained every 1 024 substeps, the periodic images with
// them: a long step that began with a drain of the steps before, then was
// cut short, must give those images back (its tallies return to the step's
// start, undrained, and are drained again).
CAROM_BACKEND_TEST_CASE("stop: a step cut short after its tallies were drained keeps the periodic images") {
    const Scene scene = gas(2000, 10.0f);
    // ~1 700 substeps a step at this speed, a tenth of the disks wrapped
    World world = worldOf(scene, def, CollisionScheme::Pairwise, 0.5f, 3e-3f, Boundary::Periodic);
    World fresh = worldOf(scene, def, CollisionScheme::Pairwise, 0.5f, 3e-3f, Boundary::Periodic);
    world.step(1);  // leaves wraps in the tallies, and the drain's count past 0
    fresh.step(1);
    int calls = 0;
    world.setStopCheck(StopAtOnce{&calls});
    world.step(1);
    CHECK(world.stepCount() == 1);
    world.setStopCheck({});
    world.step(1);
    fresh.step(1);
    CHECK(sameDisks(world, fresh));
    const std::vector<Image> images = world.images();
    CHECK(images == fresh.images());
    CHECK(std::any_of(images.begin(), images.end(), [](const Image& i) { return i[0] != 0 || i[1] != 0; }));
}
