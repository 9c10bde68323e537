// World::snapshot and World::restore: a restored world steps on bit for bit
// on every engine and scheme; a snapshot that does not fit is refused,
// naming what is wrong, and leaves the world as it was; a checkpoint file
// holds the snapshot exactly; carom::io's writers write what the engine
// measures of the world's disks.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <carom/carom.h>
#include <carom/io.h>

#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include "io/checkpoint.h"
#include "io/stats.h"
#include "io/trajectory.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

// Polydisperse disks of unequal masses, moving: every field matters.
Scene polydisperse(std::uint32_t count) {
    SceneDef def;
    def.particles = count;
    def.packing = 0.4f;
    def.radiusMin = 0.5f;
    def.radiusMax = 1.2f;
    def.massMin = 0.5f;
    def.massMax = 4.0f;
    def.speed = 1.5f;
    def.seed = 11;
    return makeScene(def);
}

WorldDef worldOf(const Scene& scene, CollisionScheme scheme, Boundary boundary, const EngineDef& engine) {
    WorldDef def;
    def.width = scene.width;
    def.height = scene.height;
    def.dt = 0.01f;
    def.boundary = boundary;
    def.gravity = boundary == Boundary::Walls ? Vec2{0.1f, -0.5f} : Vec2{0.0f, 0.0f};
    def.collisions = scheme;
    return onEngine(def, engine);
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every field a snapshot restores, bit for bit (not the engine, the device
// or maxTravel, which stay the restored world's).
void checkSame(const Snapshot& a, const Snapshot& b) {
    CHECK(a.world.width == b.world.width);
    CHECK(a.world.height == b.world.height);
    CHECK(a.world.dt == b.world.dt);
    CHECK(a.world.gravity.x == b.world.gravity.x);
    CHECK(a.world.gravity.y == b.world.gravity.y);
    CHECK(a.world.boundary == b.world.boundary);
    CHECK(a.world.collisions == b.world.collisions);
    CHECK(a.step == b.step);
    CHECK(sameBits(a.time, b.time));
    CHECK(a.collisions == b.collisions);
    CHECK(sameBits(a.disks, b.disks));
    REQUIRE(a.events.has_value() == b.events.has_value());
    if (a.events) {
        CHECK(sameBits(a.events->time, b.events->time));
        CHECK(sameBits(a.events->disks, b.events->disks));
    }
}

// 2N steps of one world equal N steps, a snapshot, and N steps of a world
// restored from it: a fresh one, and the first one rewound.
void checkContinues(const WorldDef& def, const Scene& scene, std::uint64_t half) {
    World original(def);
    original.setDisks(scene.disks);
    original.step(half);
    const Snapshot halfway = original.snapshot();
    CHECK(halfway.step == half);
    CHECK(halfway.disks.size() == scene.disks.size());
    CHECK(halfway.events.has_value() == (def.collisions == CollisionScheme::Events));
    original.step(half);
    const Snapshot end = original.snapshot();
    CHECK(end.collisions > halfway.collisions);

    World fresh(def);
    fresh.restore(halfway);
    CHECK(fresh.stepCount() == half);
    CHECK(fresh.collisionCount() == halfway.collisions);
    checkSame(fresh.snapshot(), halfway);
    fresh.step(half);
    checkSame(fresh.snapshot(), end);
    CHECK(fresh.exactPositions() == original.exactPositions());
    CHECK(sameBits(fresh.totalEnergy(), original.totalEnergy()));

    original.restore(halfway);  // rewound
    original.step(half);
    checkSame(original.snapshot(), end);
}

// `world`'s state in bytes, for "nothing changed".
std::string stateOf(const World& world) {
    Snapshot s = world.snapshot();
    return encodeCheckpoint(s);
}

std::string refusalOf(World& world, const Snapshot& snapshot) {
    const std::string before = stateOf(world);
    const Measurements measured = world.measurements();
    const std::vector<std::string> warnings = world.warnings();
    std::string message;
    try {
        world.restore(snapshot);
    } catch (const Error& e) {
        message = e.what();
    }
    CHECK_FALSE(message.empty());
    // Left as it was: the same state, measurements and warnings.
    CHECK(stateOf(world) == before);
    CHECK(world.measurements().collisions == measured.collisions);
    CHECK(world.measurements().time == measured.time);
    CHECK(world.warnings() == warnings);
    return message;
}

std::string fileText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

CAROM_BACKEND_TEST_CASE("snapshot: a restored world steps on bit for bit, in the pairwise and simultaneous schemes") {
    const Scene scene = polydisperse(1000);
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous})
        for (Boundary boundary : {Boundary::Walls, Boundary::Periodic}) {
            CAPTURE(std::string(collisionSchemeName(scheme)));
            CAPTURE(std::string(boundaryName(boundary)));
            checkContinues(worldOf(scene, scheme, boundary, def), scene, 200);
        }
}

TEST_CASE("snapshot: a restored world steps on bit for bit in the events scheme, the engine's exact state included") {
    const Scene scene = polydisperse(400);
    for (Boundary boundary : {Boundary::Walls, Boundary::Periodic}) {
        CAPTURE(std::string(boundaryName(boundary)));
        checkContinues(worldOf(scene, CollisionScheme::Events, boundary, EngineDef{}), scene, 100);
    }
}

TEST_CASE("snapshot: restore takes dt and gravity, keeps maxTravel, and restarts the measurements") {
    const Scene scene = polydisperse(300);
    WorldDef def = worldOf(scene, CollisionScheme::Pairwise, Boundary::Walls, EngineDef{});
    World original(def);
    original.setDisks(scene.disks);
    original.step(20);
    original.setMotion(0.005f, Vec2{0.0f, -1.0f});
    original.step(20);
    const Snapshot s = original.snapshot();

    def.maxTravel = 0.25f;
    World restored(def);
    restored.restore(s);
    CHECK(restored.def().dt == 0.005f);
    CHECK(restored.def().gravity.y == -1.0f);
    CHECK(restored.def().maxTravel == 0.25f);
    CHECK(restored.time() == original.time());
    CHECK(restored.measurements().steps == 0);
    CHECK(restored.measurements().collisions == 0);
    CHECK(restored.collisionCount() == original.collisionCount());
}

CAROM_OPENCL_TEST_CASE("snapshot: a CPU snapshot steps on alike on OpenCL where the engines agree bitwise") {
    const Scene scene = polydisperse(1000);
    const WorldDef cpu = worldOf(scene, CollisionScheme::Pairwise, Boundary::Walls, EngineDef{});
    World reference(cpu);
    reference.setDisks(scene.disks);
    reference.step(100);
    World device(onEngine(cpu, def));
    if (!device.bitwiseReproducible()) {
        MESSAGE("the OpenCL device lacks correctly rounded divide/sqrt: the engines do not agree bitwise");
        return;
    }
    device.restore(reference.snapshot());
    reference.step(100);
    device.step(100);
    checkSame(device.snapshot(), reference.snapshot());
}

TEST_CASE("snapshot: restore refuses a snapshot that does not fit, naming it, and leaves the world as it was") {
    const Scene scene = polydisperse(200);
    World world(worldOf(scene, CollisionScheme::Pairwise, Boundary::Walls, EngineDef{}));
    world.setDisks(scene.disks);
    world.step(10);
    const Snapshot good = world.snapshot();
    world.step(10);

    Snapshot outside = good;
    outside.disks[7].position.x = -3.0f;
    CHECK(refusalOf(world, outside).find("snapshot: particle 7: position (-3, ") != std::string::npos);

    Snapshot wider = good;
    wider.world.width *= 2;
    CHECK(refusalOf(world, wider).find("snapshot: a snapshot of another world (box ") != std::string::npos);

    Snapshot periodic = good;
    periodic.world.boundary = Boundary::Periodic;
    CHECK(refusalOf(world, periodic).find("(boundary periodic, this world's walls)") != std::string::npos);

    Snapshot simultaneous = good;
    simultaneous.world.collisions = CollisionScheme::Simultaneous;
    CHECK(refusalOf(world, simultaneous)
              .find("(collision scheme simultaneous, this world's pairwise); allowed: one of a world with this "
                    "one's box, boundary and collision scheme") != std::string::npos);

    Snapshot none = good;
    none.disks.clear();
    CHECK(refusalOf(world, none).find("snapshot: a world needs at least 1 disk, got 0") != std::string::npos);

    Snapshot time = good;
    time.time = NAN;
    CHECK(refusalOf(world, time).find("snapshot: time nan must be a finite number >= 0") != std::string::npos);

    Snapshot dt = good;
    dt.world.dt = -1.0f;
    CHECK(refusalOf(world, dt).find("snapshot: ") == 0);

    Snapshot events = good;
    events.events = EventEngineState{};
    CHECK(refusalOf(world, events).find("exactly with the events scheme (here pairwise, 0 disks in the state") !=
          std::string::npos);
}

TEST_CASE("snapshot: restore refuses an events state that does not fit, and leaves the world as it was") {
    const Scene scene = polydisperse(200);
    const WorldDef def = worldOf(scene, CollisionScheme::Events, Boundary::Walls, EngineDef{});
    World world(def);
    world.setDisks(scene.disks);
    world.step(10);
    const Snapshot good = world.snapshot();
    REQUIRE(good.events.has_value());
    world.step(10);

    // `good` with its events state changed by `change`.
    const auto changed = [&good](auto change) {
        EventEngineState state = *good.events;
        change(state);
        Snapshot s = good;
        s.events = std::move(state);
        return s;
    };
    const Snapshot partner = changed([](EventEngineState& s) {
        s.disks[3].event = 200;  // no disk 200
        s.disks[3].eventTime = s.time + 1;
    });
    CHECK(refusalOf(world, partner).find("snapshot: events state: disk 3: event code 200 is unknown") !=
          std::string::npos);

    // What only the engine's grid tells.
    const Snapshot cell = changed([](EventEngineState& s) { s.disks[5].cell = 1u << 30; });
    CHECK(refusalOf(world, cell).find("snapshot: events state: disk 5 is in cell 1073741824") != std::string::npos);

    Snapshot missing = good;
    missing.events.reset();
    CHECK(refusalOf(world, missing).find("exactly with the events scheme (here events, no state, 200 particles)") !=
          std::string::npos);

    const Snapshot fewer = changed([](EventEngineState& s) { s.disks.pop_back(); });
    CHECK(refusalOf(world, fewer).find("(here events, 199 disks in the state, 200 particles)") != std::string::npos);

    // The refusals left the world where it was: it steps on as a world that never saw them.
    World reference(def);
    reference.setDisks(scene.disks);
    reference.step(30);
    world.step(10);
    checkSame(world.snapshot(), reference.snapshot());
}

TEST_CASE("snapshot: a checkpoint file holds the snapshot bit for bit, and restores it") {
    const Scene scene = polydisperse(300);
    const std::string path = (std::filesystem::temp_directory_path() / "carom_snapshot.ckpt").string();
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Events}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        World world(worldOf(scene, scheme, Boundary::Walls, EngineDef{}));
        world.setDisks(scene.disks);
        world.step(25);
        const Snapshot taken = world.snapshot();
        io::saveCheckpoint(path, world);
        const io::CheckpointFile file = io::readCheckpoint(path);
        checkSame(file.snapshot(), taken);

        World restored(world.def());
        restored.restore(file.snapshot());
        world.step(25);
        restored.step(25);
        checkSame(restored.snapshot(), world.snapshot());
    }
    std::filesystem::remove(path);
}

// The writers read the world through its public API: their files hold what
// the engine's writers make of the world's disks and of measure().
TEST_CASE("io: trajectories and statistics hold the engine's measurements of the world's disks") {
    const Scene scene = polydisperse(300);
    const auto folder = std::filesystem::temp_directory_path() / "carom_snapshot_writers";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const auto path = [&](const char* name) { return (folder / name).string(); };
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Events}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        World world(worldOf(scene, scheme, Boundary::Walls, EngineDef{}));
        world.setDisks(scene.disks);
        io::TrajectoryWriter trajectory(path("public.xyz"));
        io::StatisticsWriter statistics(path("public.csv"));
        carom::TrajectoryWriter engineTrajectory(path("engine.xyz"));
        StatsWriter engineStatistics(path("engine.csv"));
        for (int sample = 0; sample < 3; ++sample) {
            if (sample > 0) world.step(20);
            trajectory.write(world);
            statistics.write(world);
            const std::vector<Disk> disks = world.disks();
            engineTrajectory.write(disks, world.def(), world.stepCount(), world.time());
            engineStatistics.write(world.stepCount(), world.time(),
                                   measure(particlesOf(disks.data(), disks.size()), world.def()),
                                   world.collisionCount());
        }
        trajectory.close();
        statistics.close();
        engineTrajectory.commit();
        engineStatistics.commit();
        CHECK(fileText(path("public.xyz")) == fileText(path("engine.xyz")));
        CHECK(fileText(path("public.csv")) == fileText(path("engine.csv")));
        CHECK(fileText(path("public.csv")).find("\n40,") != std::string::npos);
    }
    std::filesystem::remove_all(folder);
}
