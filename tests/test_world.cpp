// The public API (include/carom/): World and carom::io, each engine this
// build has registered as its own case. A World must step exactly as the
// engine's backend does, report the observables the command line reports,
// and refuse bad input in library terms.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <carom/carom.h>
#include <carom/io.h>

#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include "engine/observables.h"
#include "engine/scene.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

// A polydisperse gas under gravity, in a box with the given boundary.
Scene gas(std::uint32_t count, float packing) {
    SceneDef def;
    def.particles = count;
    def.packing = packing;
    def.radiusMin = 0.5f;
    def.radiusMax = 1.0f;
    def.massMin = 1.0f;
    def.massMax = 3.0f;
    def.seed = 7;
    return makeScene(def);
}

WorldDef worldFor(const Scene& scene, ComputeEngine engine, Boundary boundary) {
    WorldDef def;
    def.width = scene.width;
    def.height = scene.height;
    def.boundary = boundary;
    def.gravity = boundary == Boundary::Walls ? Vec2{0.0f, -0.05f} : Vec2{0.0f, 0.0f};
    def.engine = engine;
    if (const char* device = std::getenv("CAROM_TEST_DEVICE")) def.device = device;
    return def;
}

bool sameBits(const Disk& a, const Particle& b) {
    return std::memcmp(&a.position, &b.position, 8) == 0 && std::memcmp(&a.velocity, &b.velocity, 8) == 0 &&
           a.mass == b.mass && a.radius == b.radius;
}

}  // namespace

// Both schemes that step, both boundaries: the World's disks, collisions and
// observables equal a backend's run of the same particles, bit for bit.
CAROM_BACKEND_TEST_CASE("world: steps bit for bit as its backend, with the same observables") {
    const ComputeEngine engine = def.engine;
    const Scene scene = gas(2000, 0.45f);
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous}) {
        for (Boundary boundary : {Boundary::Walls, Boundary::Periodic}) {
            WorldDef spec = worldFor(scene, engine, boundary);
            spec.collisions = scheme;
            CAPTURE(std::string(collisionSchemeName(scheme)));
            CAPTURE(std::string(boundaryName(boundary)));
            World world(spec);
            world.setDisks(scene.disks);
            world.step(60);
            const Run expected = run(def, spec, particlesOf(scene.disks.data(), scene.disks.size()), 60);

            const std::vector<Disk> disks = world.disks();
            REQUIRE(disks.size() == expected.particles.size());
            std::size_t differing = 0;
            for (std::size_t i = 0; i < disks.size(); ++i) differing += !sameBits(disks[i], expected.particles[i]);
            CHECK(differing == 0);
            CHECK(world.stepCount() == 60);
            CHECK(world.time() == 60 * double(spec.dt));

            const Measurements m = world.measurements();
            CHECK(m.collisions == expected.contacts.collisions);
            CHECK(m.collisions > 0);
            CHECK(m.steps == 60);
            const Diagnostics d = measure(expected.particles, spec);
            CHECK(world.kineticEnergy() == d.kineticEnergy);
            CHECK(world.potentialEnergy() == d.potentialEnergy);
            CHECK(world.momentum() == d.momentum);
            CHECK(world.maxOverlap() == d.maxOverlap);
            CHECK(world.escapedCount() == d.escaped);
            const double startT = temperature(particlesOf(scene.disks.data(), scene.disks.size()), boundary);
            const double endT = temperature(expected.particles, boundary);
            CHECK(world.temperature() == endT);
            const Thermodynamics t = thermodynamics(expected.contacts, 0.5 * (startT + endT), disks.size(), spec);
            CHECK(m.temperature == 0.5 * (startT + endT));
            CHECK(m.collisionRate == t.collisionRate);
            CHECK(m.pressure == (boundary == Boundary::Periodic ? t.virialPressure : t.wallPressureMean));
            CHECK(m.compressibility == (boundary == Boundary::Periodic ? t.virialZ : t.wallZ));
            CHECK(m.pressure > 0.0);
        }
    }
}

TEST_CASE("world: the events scheme runs exactly and reports its collisions [cpu]") {
    const Scene scene = gas(500, 0.4f);
    WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Periodic);
    def.collisions = CollisionScheme::Events;
    World world(def);
    world.setDisks(scene.disks);
    const double before = world.kineticEnergy();
    world.step(20);
    CHECK(world.measurements().collisions > 0);
    CHECK(world.time() == 20 * double(def.dt));
    // The float32 samples of an exact double state: rounding only.
    CHECK(std::fabs(world.kineticEnergy() - before) < 1e-5 * before);
    CHECK(world.bitwiseReproducible());
}

TEST_CASE("world: disks go in and come out in id order") {
    const Scene scene = gas(300, 0.3f);
    World world(worldFor(scene, ComputeEngine::Cpu, Boundary::Walls));
    CHECK(world.diskCount() == 0);
    world.setDisks(scene.disks.data(), scene.disks.size());
    REQUIRE(world.diskCount() == scene.disks.size());
    std::vector<Disk> out(world.diskCount());
    world.getDisks(out.data(), out.size());
    CHECK_THROWS_AS(world.getDisks(out.data(), out.size() - 1), Error);
    CHECK(std::memcmp(out.data(), scene.disks.data(), out.size() * sizeof(Disk)) == 0);
    // A range, as the writers read a large state a piece at a time.
    std::vector<Disk> piece(7);
    world.getDisks(100, piece.size(), piece.data());
    CHECK(std::memcmp(piece.data(), scene.disks.data() + 100, piece.size() * sizeof(Disk)) == 0);
    world.getDisks(out.size() - 7, 7, piece.data());
    CHECK(std::memcmp(piece.data(), scene.disks.data() + out.size() - 7, piece.size() * sizeof(Disk)) == 0);
    world.getDisks(out.size(), 0, nullptr);  // nothing to copy
    CHECK(std::memcmp(world.disks().data(), scene.disks.data(), out.size() * sizeof(Disk)) == 0);
    CHECK(world.warnings().empty());

    World moved = std::move(world);
    CHECK(moved.diskCount() == scene.disks.size());
}

TEST_CASE("world: the events scheme's exact centres round to its disks and views, and the virial makes the pressure") {
    const Scene scene = gas(400, 0.4f);
    WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Periodic);
    def.collisions = CollisionScheme::Events;
    World world(def);
    world.setDisks(scene.disks);
    world.step(30);
    const std::vector<std::array<double, 2>> exact = world.exactPositions();
    const std::vector<Disk> disks = world.disks();
    REQUIRE(exact.size() == disks.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < disks.size(); ++i)
        differing += float(exact[i][0]) != disks[i].position.x || float(exact[i][1]) != disks[i].position.y;
    CHECK(differing == 0);

    // Its view: the float copy's disks, with the sums of the double state,
    // whose total is totalEnergy() bit for bit.
    std::vector<DiskView> views(disks.size());
    const ViewSums sums = world.readView(ViewValue::Id, views.data(), views.size());
    CHECK(sums.kineticEnergy + sums.potentialEnergy == world.totalEnergy());
    std::size_t wrongViews = 0;
    for (std::size_t i = 0; i < views.size(); ++i)
        wrongViews += views[i].value != float(i) || std::memcmp(&views[i].position, &disks[i].position, 8) != 0;
    CHECK(wrongViews == 0);

    const Measurements m = world.measurements();
    REQUIRE(m.collisions > 0);
    const double n = double(disks.size()), area = double(def.width) * def.height;
    CHECK(m.pressure * area ==
          doctest::Approx((n - 1) * m.temperature + m.collisionVirial / (2 * m.time)).epsilon(1e-12));

    def.collisions = CollisionScheme::Pairwise;
    World stepped(def);
    stepped.setDisks(scene.disks);
    CHECK(stepped.exactPositions().empty());
}

TEST_CASE("world: the deepest overlap of two disks, and none escaped") {
    WorldDef def;
    def.width = def.height = 20.0f;
    World world(def);
    // Radius 1, centres 1.5 apart: they overlap by 0.5 (every value exact in float).
    const Disk pair[] = {{{5.0f, 5.0f}, {0, 0}, 1, 1}, {{6.5f, 5.0f}, {0, 0}, 1, 1}};
    world.setDisks(pair, 2);
    CHECK(world.maxOverlap() == 0.5);
    CHECK(world.escapedCount() == 0);
    world.setDisk(1, Disk{{9.0f, 5.0f}, {0, 0}, 1, 1});
    CHECK(world.maxOverlap() == 0.0);
}

TEST_CASE("world: deep overlaps are warned of, or refused on request, keeping the disks") {
    WorldDef def;
    def.width = def.height = 20.0f;
    World world(def);
    const Disk apart[] = {{{5.0f, 5.0f}, {0, 0}, 1, 1}, {{9.0f, 5.0f}, {0, 0}, 1, 1}};
    const Disk deep[] = {{{5.0f, 5.0f}, {0, 0}, 1, 1}, {{6.5f, 5.0f}, {0, 0}, 1, 1}};
    world.setDisks(deep, 2);
    REQUIRE(world.warnings().size() == 1);
    CHECK(world.warnings()[0].find("particles 0 and 1 by 0.5") != std::string::npos);
    world.setDisks(apart, 2);
    CHECK_THROWS_WITH_AS(world.setDisks(deep, 2, "mine", DeepOverlaps::Refuse),
                         doctest::Contains("mine: 1 pair(s) of disks overlap, the deepest particles 0 and 1 by 0.5"),
                         Error);
    CHECK(world.disks()[1].position.x == 9.0f);
}

// The CPU engine's memory, read without a copy, follows the world through
// steps (both schemes: the simultaneous one writes into the viewed buffer)
// and stays alive, unchanged, when the world replaces its disks by another number.
CAROM_BACKEND_TEST_CASE("world: disk memory follows the steps and outlives a new set of disks") {
    const Scene scene = gas(300, 0.3f);
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef spec = worldFor(scene, def.engine, Boundary::Walls);
        spec.collisions = scheme;
        World world(spec);
        world.setDisks(scene.disks);
        const DiskMemory memory = world.diskMemory();
        if (def.engine != ComputeEngine::Cpu) {
            CHECK(memory.base == nullptr);
            continue;
        }
        REQUIRE(memory.base != nullptr);
        REQUIRE(memory.count == scene.disks.size());
        for (int step = 0; step < 3; ++step) {
            world.step(1);
            CHECK(world.diskMemory().base == memory.base);
            const std::vector<Disk> disks = world.disks();
            for (std::size_t i = 0; i < disks.size(); ++i) {
                const float* record = memory.base + i * memory.stride;
                REQUIRE(std::memcmp(record + DiskMemory::kPosition, &disks[i].position, 8) == 0);
                REQUIRE(std::memcmp(record + DiskMemory::kVelocity, &disks[i].velocity, 8) == 0);
                REQUIRE(record[DiskMemory::kMass] == disks[i].mass);
                REQUIRE(record[DiskMemory::kRadius] == disks[i].radius);
            }
        }
        const std::vector<Disk> before = world.disks();
        world.setDisks(std::vector<Disk>(scene.disks.begin(), scene.disks.begin() + 10));
        CHECK(world.diskMemory().base != memory.base);
        CHECK(std::memcmp(memory.base + (before.size() - 1) * memory.stride, &before.back().position, 8) == 0);
    }
}

// One process owns every disk: ownDisks() is the world's disks and images,
// with ids 0..N-1, and gather() has nothing to do.
CAROM_BACKEND_TEST_CASE("world: one process's own disks are every disk") {
    const Scene scene = gas(300, 0.3f);
    World world(worldFor(scene, def.engine, Boundary::Periodic));
    world.setDisks(scene.disks);
    world.step(20);
    const OwnDisks own = world.ownDisks();
    const std::vector<Disk> disks = world.disks();
    const std::vector<Image> images = world.images();
    REQUIRE(own.ids.size() == disks.size());
    REQUIRE(own.disks.size() == disks.size());
    for (std::size_t i = 0; i < disks.size(); ++i) {
        REQUIRE(own.ids[i] == i);
        REQUIRE(std::memcmp(&own.disks[i], &disks[i], sizeof(Disk)) == 0);
    }
    CHECK(own.images == images);
    world.gather();
    CHECK(world.disks().size() == disks.size());
}

// The device's buffers, counted as they are made and freed: on OpenCL at
// least the two states and the tallies of every disk, more for more disks,
// less again once fewer replace them; nothing on the CPU.
CAROM_BACKEND_TEST_CASE("world: device memory counts the engine's buffers on the device") {
    const Scene scene = gas(4000, 0.3f);
    const std::vector<Disk> few(scene.disks.begin(), scene.disks.begin() + 1000);
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef spec = worldFor(scene, def.engine, Boundary::Walls);
        spec.collisions = scheme;
        World world(spec);
        world.setDisks(few);
        world.step(2);
        const DeviceMemoryUse small = world.deviceMemory();
        if (def.engine == ComputeEngine::Cpu) {
            CHECK(small.bytes == 0);
            CHECK(small.peakBytes == 0);
            continue;
        }
        const std::uint64_t perDisk = 2 * sizeof(Particle) + sizeof(ContactTally);
        CHECK(small.bytes >= few.size() * perDisk);
        CHECK(small.peakBytes >= small.bytes);
        world.setDisks(scene.disks);
        world.step(2);
        const DeviceMemoryUse large = world.deviceMemory();
        CHECK(large.bytes >= scene.disks.size() * perDisk);
        CHECK(large.bytes > small.bytes + (scene.disks.size() - few.size()) * perDisk);
        CHECK(large.peakBytes >= large.bytes);
        world.setDisks(few);
        world.step(2);
        const DeviceMemoryUse again = world.deviceMemory();
        CHECK(again.bytes == small.bytes);
        CHECK(again.peakBytes == large.peakBytes);
    }
}

namespace {

// Every disk of `world` appears once in a view read first (before anything
// else waits for the steps), with its own position and radius, and the sums
// equal the exact double ones (the CPU's) within the rounding of each disk's
// float terms, up to about 1e-7 of each, where the float-float sums add next
// to nothing.
void checkView(const World& world, ComputeEngine engine) {
    const std::size_t n = world.diskCount();
    std::vector<DiskView> views(n);
    const ViewSums sums = world.readView(ViewValue::Id, views.data(), n);
    const std::vector<Disk> disks = world.disks();
    std::vector<int> seen(n, 0);
    std::size_t wrong = 0;
    for (const DiskView& view : views) {
        const auto id = std::size_t(view.value);
        REQUIRE(id < n);
        ++seen[id];
        wrong += std::memcmp(&view.position, &disks[id].position, 8) != 0 || view.radius != disks[id].radius;
    }
    CHECK(wrong == 0);
    CHECK(std::count(seen.begin(), seen.end(), 1) == std::ptrdiff_t(n));
    CHECK(sums.minValue == 0.0f);
    CHECK(sums.maxValue == float(n - 1));

    const double relative = engine == ComputeEngine::Cpu ? 0.0 : 3e-7;
    const double kinetic = world.kineticEnergy(), potential = world.potentialEnergy();
    CHECK(std::abs(sums.kineticEnergy - kinetic) <= relative * kinetic);
    CHECK(std::abs(sums.potentialEnergy - potential) <= relative * std::abs(potential));
    double mass = 0.0, speedSquared = 0.0;
    for (const Disk& d : disks) {
        mass += d.mass;
        speedSquared += double(d.velocity.x) * d.velocity.x + double(d.velocity.y) * d.velocity.y;
    }
    const double momentumScale = std::sqrt(2.0 * kinetic * mass);  // sum of m |v| at most
    CHECK(std::abs(sums.momentum[0] - world.momentum()[0]) <= relative * momentumScale);
    CHECK(std::abs(sums.momentum[1] - world.momentum()[1]) <= relative * momentumScale);
    CHECK(std::abs(sums.mass - mass) <= relative * mass);
    CHECK(std::abs(sums.speedSquared - speedSquared) <= relative * speedSquared);
}

}  // namespace

// A frame's view (issue 16), on every pipeline: after steps that reorder the
// resident one's storage, after disks are added, and for more disks than one
// launch of the view kernel has work-items (256 groups of up to 256).
CAROM_BACKEND_TEST_CASE("world: a view holds every disk once, and its sums are the state's") {
    const auto stepped = [&](const Scene& scene, std::uint64_t steps) {
        World world(worldFor(scene, def.engine, Boundary::Walls));
        world.setDisks(scene.disks);
        world.step(steps);
        return world;
    };
    const Scene scene = gas(3000, 0.4f);
    World world = stepped(scene, 30);
    {
        CAPTURE("after 30 steps");
        checkView(world, def.engine);
    }
    std::vector<DiskView> views(world.diskCount());
    CHECK_THROWS_WITH_AS(world.readView(ViewValue::Id, views.data(), views.size() - 1),
                         doctest::Contains("room for 2999 views is less than diskCount() 3000"), Error);

    // Each value: speeds, masses and radii as the disks have them.
    const std::vector<Disk> disks = world.disks();
    world.readView(ViewValue::Id, views.data(), views.size());
    for (ViewValue value : {ViewValue::Speed, ViewValue::Mass, ViewValue::Radius}) {
        CAPTURE(int(value));
        std::vector<DiskView> values(views.size());
        const ViewSums valued = world.readView(value, values.data(), values.size());
        float lowest = HUGE_VALF, highest = -HUGE_VALF;
        std::size_t wrong = 0;
        for (std::size_t s = 0; s < values.size(); ++s) {
            const Disk& d = disks[std::size_t(views[s].value)];
            const float expected = value == ViewValue::Mass     ? d.mass
                                   : value == ViewValue::Radius ? d.radius
                                                                : std::hypot(d.velocity.x, d.velocity.y);
            wrong += std::abs(values[s].value - expected) > 1e-6f * expected;
            lowest = std::min(lowest, values[s].value);
            highest = std::max(highest, values[s].value);
        }
        CHECK(wrong == 0);
        CHECK(valued.minValue == lowest);
        CHECK(valued.maxValue == highest);
    }

    const std::vector<Disk> added(scene.disks.begin(), scene.disks.begin() + 12);
    world.addDisks(added.data(), added.size());  // overlapping: the steps push them apart
    world.step(2);
    {
        CAPTURE("after addDisks");
        checkView(world, def.engine);
    }

    CAPTURE("70 000 disks");
    checkView(stepped(gas(70000, 0.4f), 2), def.engine);
}

TEST_CASE("world: bad input is refused in library terms, naming the value") {
    WorldDef def;
    CHECK_THROWS_WITH_AS(World{def}, "box width must be a finite number > 0, got 0", Error);
    def.width = def.height = 20.0f;
    def.dt = -1.0f;
    CHECK_THROWS_WITH_AS(World{def}, "dt must be a finite number > 0, got -1", Error);
    def.dt = 0.01f;
    def.engine = ComputeEngine::OpenClResident;
    def.collisions = CollisionScheme::Events;
    CHECK_THROWS_WITH_AS(World{def},
                         "CollisionScheme::Events runs on ComputeEngine::Cpu only (one thread, double precision); "
                         "got ComputeEngine opencl-resident",
                         Error);
    def.engine = ComputeEngine::Cpu;
    World world(def);
    CHECK_THROWS_WITH_AS(world.step(1), "step: the world has no disks yet; call setDisks first", Error);
    CHECK_THROWS_WITH_AS(world.setDisks(nullptr, 0), "setDisks: a world needs at least 1 disk, got 0", Error);
    Disk outside;
    outside.position = {25.0f, 5.0f};
    CHECK_THROWS_AS(world.setDisks(&outside, 1), Error);
    CHECK(world.diskCount() == 0);
}

TEST_CASE("io: a scene file loads as the command line places it") {
    const std::string path = std::string(CAROM_SCENES_DIR) + "/mixture.toml";
    const io::SceneFile loaded = io::loadScene(path);
    const carom::SceneFileDef scene = io::readSceneFile(path);
    const InitialState placed = makeInitialState(scene);
    CHECK(loaded.world.width == placed.width);
    CHECK(loaded.world.height == placed.height);
    CHECK(loaded.world.collisions == scene.world.collisions);
    CHECK(loaded.steps == scene.steps);
    REQUIRE(loaded.disks.size() == placed.particles.size());
    for (std::size_t i = 0; i < placed.particles.size(); ++i) REQUIRE(sameBits(loaded.disks[i], placed.particles[i]));
    CHECK_THROWS_AS(io::loadScene(std::string(CAROM_SCENES_DIR) + "/no_such_scene.toml"), Error);
}

TEST_CASE("io: a scene file changed by its reader loads with the changes, and refuses what cannot fit") {
    const std::string path = std::string(CAROM_SCENES_DIR) + "/mixture.toml";
    carom::SceneFileDef scene = io::readSceneFile(path);
    scene.seed += 1;
    scene.world.collisions = CollisionScheme::Simultaneous;
    scene.world.maxTravel = 0.25f;
    const io::SceneFile loaded = io::loadScene(scene);
    const InitialState placed = makeInitialState(scene);
    CHECK(loaded.world.collisions == CollisionScheme::Simultaneous);
    CHECK(loaded.world.maxTravel == 0.25f);
    REQUIRE(loaded.disks.size() == placed.particles.size());
    for (std::size_t i = 0; i < placed.particles.size(); ++i) REQUIRE(sameBits(loaded.disks[i], placed.particles[i]));
    CHECK_FALSE(sameBits(loaded.disks[0], makeInitialState(io::readSceneFile(path)).particles[0]));

    // Counted before any disk is placed: more disks than kMaxParticles.
    scene.groups.resize(2);
    scene.groups[0].count = scene.groups[1].count = kMaxParticles / 2 + 1;
    CHECK_THROWS_WITH_AS(
        io::loadScene(scene),
        (path + ": " + std::to_string(kMaxParticles + 2) + " particles; allowed: 1 to " + std::to_string(kMaxParticles))
            .c_str(),
        Error);
}

TEST_CASE("io: a state written and read back is bit for bit the same") {
    const Scene scene = gas(200, 0.3f);
    const std::string path = (std::filesystem::temp_directory_path() / "carom_world_state.csv").string();
    io::writeState(path, scene.disks);
    const std::vector<Disk> back = io::readState(path);
    std::remove(path.c_str());
    REQUIRE(back.size() == scene.disks.size());
    CHECK(std::memcmp(back.data(), scene.disks.data(), back.size() * sizeof(Disk)) == 0);
}

TEST_CASE("io: writeState and TrajectoryWriter refuse what would not read back, and write nothing") {
    const std::string path = (std::filesystem::temp_directory_path() / "carom_refused_state.csv").string();
    std::remove(path.c_str());
    CHECK_THROWS_WITH_AS(io::writeState(path, {}),
                         doctest::Contains("0 disks; allowed: at least 1 (a state file holds a world's disks)"), Error);
    std::vector<Disk> disks = gas(20, 0.3f).disks;
    disks[7].velocity.y = NAN;
    CHECK_THROWS_WITH_AS(io::writeState(path, disks), doctest::Contains("disk 7's vy is nan; allowed: finite numbers"),
                         Error);
    disks[7].velocity.y = 0;
    disks[3].mass = -INFINITY;
    CHECK_THROWS_WITH_AS(io::writeState(path, disks), doctest::Contains("disk 3's mass is -inf"), Error);
    CHECK_FALSE(std::filesystem::exists(path));
    // Nor a trajectory frame of no disks.
    const World empty(box(10, 10));
    io::TrajectoryWriter trajectory(path);
    CHECK_THROWS_WITH_AS(trajectory.write(empty), "TrajectoryWriter::write: the world has no disks yet", Error);
}

TEST_CASE("io: a world resumed from its checkpoint continues bit for bit, events included") {
    const Scene scene = gas(400, 0.4f);
    const std::string path = (std::filesystem::temp_directory_path() / "carom_world.ckpt").string();
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Events}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Walls);
        def.collisions = scheme;
        World straight(def);
        straight.setDisks(scene.disks);
        straight.step(30);
        io::saveCheckpoint(path, straight);
        straight.step(30);

        World resumed = io::loadCheckpoint(path);
        CHECK(resumed.stepCount() == 30);
        CHECK(resumed.def().collisions == scheme);
        CHECK(resumed.def().gravity.y == def.gravity.y);
        resumed.step(30);
        CHECK(resumed.stepCount() == straight.stepCount());
        CHECK(resumed.collisionCount() == straight.collisionCount());
        CHECK(resumed.collisionCount() > 0);
        const std::vector<Disk> a = straight.disks(), b = resumed.disks();
        REQUIRE(a.size() == b.size());
        CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(Disk)) == 0);
    }
    std::remove(path.c_str());
    CHECK_THROWS_AS(io::loadCheckpoint(path), Error);
}

CAROM_BACKEND_TEST_CASE("world: periodic images go through edits, snapshots and checkpoints") {
    const std::string path = (std::filesystem::temp_directory_path() /
                              (std::string("carom_images_") + computeEngineName(def.engine) + ".ckpt"))
                                 .string();
    // Two disks flying side by side, 8 apart: they never meet.
    const std::vector<Disk> disks = disksOf({disk(5, 5, 7, -2.6f, 1, 0.5f), disk(13, 5, 7, -2.6f, 1, 0.5f)});
    for (const CollisionScheme scheme :
         {CollisionScheme::Simultaneous, CollisionScheme::Pairwise, CollisionScheme::Events}) {
        if (scheme == CollisionScheme::Events && def.engine != ComputeEngine::Cpu) continue;
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef world = box(20, 10, 0.01f);
        world.boundary = Boundary::Periodic;
        world.collisions = scheme;
        world.engine = def.engine;
        world.device = def.device;
        World straight(world);
        straight.setDisks(disks);
        straight.step(1000);
        // After 10 time units at (75, -21) and (83, -21).
        CHECK(straight.images() == std::vector<Image>{Image{3, -3}, Image{4, -3}});
        io::saveCheckpoint(path, straight);
        World resumed = io::loadCheckpoint(path, world);
        CHECK(resumed.images() == straight.images());
        World restored(world);
        restored.restore(straight.snapshot());
        CHECK(restored.images() == straight.images());
        straight.step(500);
        resumed.step(500);
        CHECK(resumed.images() == straight.images());
        CHECK(resumed.images() == std::vector<Image>{Image{5, -4}, Image{5, -4}});  // (110, -34), (118, -34)
        // A drag keeps a disk's image, a drop starts at {0, 0}, a new scene at {0, 0} throughout.
        resumed.setDisk(0, disks[1]);
        resumed.addDisks(&disks[0], 1);
        CHECK(resumed.images() == std::vector<Image>{Image{5, -4}, Image{5, -4}, Image{0, 0}});
        resumed.setDisks(disks);
        CHECK(resumed.images() == std::vector<Image>(2, Image{0, 0}));
    }
    std::remove(path.c_str());

    // Images that do not fit the disks are refused, naming them.
    World walls(box(20, 10));
    Snapshot snapshot;
    snapshot.world = box(20, 10);
    snapshot.disks = disks;
    snapshot.images = {Image{1, 0}, Image{0, 0}};
    CHECK_THROWS_WITH_AS(walls.restore(snapshot),
                         "snapshot: disk 0 has image {1, 0} in a box with walls; allowed: {0, 0} (only a periodic "
                         "box has images)",
                         Error);
    snapshot.images.pop_back();
    CHECK_THROWS_WITH_AS(walls.restore(snapshot),
                         "snapshot: 1 images for 2 disks; allowed: one per disk, or none (all {0, 0})", Error);
}

TEST_CASE("world: dt and gravity change between steps, and the collision count outlives a reset") {
    const Scene scene = gas(300, 0.3f);
    World world(worldFor(scene, ComputeEngine::Cpu, Boundary::Walls));
    world.setDisks(scene.disks);
    world.step(20);
    const std::uint64_t before = world.collisionCount();
    CHECK(before == world.measurements().collisions);
    world.resetMeasurements();
    CHECK(world.measurements().collisions == 0);
    CHECK(world.collisionCount() == before);
    world.setMotion(0.005f, Vec2{0.0f, -1.0f});
    CHECK(world.def().dt == 0.005f);
    world.step(20);
    CHECK(world.collisionCount() == before + world.measurements().collisions);
    CHECK(world.potentialEnergy() != 0.0);
    CHECK_THROWS_AS(world.setMotion(-1.0f, Vec2{0.0f, 0.0f}), Error);
    CHECK(world.def().dt == 0.005f);
    WorldDef events = worldFor(scene, ComputeEngine::Cpu, Boundary::Walls);
    events.collisions = CollisionScheme::Events;
    events.maxTravel = 0.2f;
    CHECK_THROWS_WITH_AS(World{events},
                         "WorldDef::maxTravel must be 0 with CollisionScheme::Events, which has no steps to split; "
                         "got 0.200000",
                         Error);
}

TEST_CASE("world: a skin is refused where no neighbour lists take it, and beyond 8 largest radii") {
    const Scene scene = gas(300, 0.3f);  // radii up to 1 (0.9989)
    WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Walls);
    const std::string elsewhere =
        "WorldDef::skin (--skin) sizes the CPU engine's neighbour lists, which only the pairwise scheme keeps: it "
        "must be 0 on the OpenCL engines and with the simultaneous and events schemes; got 0.5";
    def.skin = 0.5f;
    for (CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Events}) {
        WorldDef other = def;
        other.collisions = scheme;
        CHECK_THROWS_WITH_AS(World{other}, elsewhere.c_str(), Error);
    }
    if (engineAvailable(ComputeEngine::OpenClResident)) {
        WorldDef opencl = def;
        opencl.engine = ComputeEngine::OpenClResident;
        CHECK_THROWS_WITH_AS(World{opencl}, elsewhere.c_str(), Error);
    }
    for (float bad : {-1.0f, NAN, INFINITY}) {
        def.skin = bad;
        CHECK_THROWS_WITH_AS(World{def}, doctest::Contains("skin must be a finite number >= 0 (0 = automatic)"), Error);
    }
    def.skin = 8.5f;
    World tooWide(def);
    CHECK_THROWS_WITH_AS(tooWide.setDisks(scene.disks),
                         doctest::Contains("skin 8.5 is more than 8 times the largest radius 0.99"), Error);
    def.skin = 7.5f;
    World widest(def);
    widest.setDisks(scene.disks);
    widest.step(5);
    CHECK(widest.def().skin == 7.5f);
}

TEST_CASE("world: a disk dragged and disks dropped keep the step and collision counts") {
    const Scene scene = gas(300, 0.3f);
    WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Walls);
    World world(def);
    world.setDisks(scene.disks);
    world.step(40);
    const std::uint64_t collisions = world.collisionCount();
    Disk dragged = world.disks()[5];
    dragged.velocity = {3.0f, -2.0f};
    world.setDisk(5, dragged);
    CHECK(world.stepCount() == 40);
    CHECK(world.collisionCount() == collisions);
    CHECK(world.measurements().collisions == 0);
    CHECK(world.disks()[5].velocity.x == 3.0f);
    Disk dropped;
    dropped.position = {def.width / 2, def.height / 2};
    world.addDisks(&dropped, 1);
    CHECK(world.diskCount() == scene.disks.size() + 1);
    world.step(10);
    CHECK(world.stepCount() == 50);
    CHECK(world.collisionCount() >= collisions);
    CHECK_THROWS_WITH_AS(world.setDisk(world.diskCount(), dropped),
                         "setDisk: id 301 is not a disk; allowed: 0..300 (diskCount() - 1)", Error);
    dropped.mass = -1.0f;
    CHECK_THROWS_AS(world.setDisk(0, dropped), Error);
    CHECK(world.diskCount() == scene.disks.size() + 1);
}

TEST_CASE("world: an edit of every disk keeps the step and collision counts, and the number of disks") {
    const Scene scene = gas(200, 0.3f);
    World world(worldFor(scene, ComputeEngine::Cpu, Boundary::Periodic));
    world.setDisks(scene.disks);
    world.step(20);
    const std::uint64_t collisions = world.collisionCount();
    std::vector<Disk> faster = world.disks();
    for (Disk& d : faster) d.velocity = {2 * d.velocity.x, 2 * d.velocity.y};
    world.editDisks(faster.data(), faster.size());
    CHECK(world.stepCount() == 20);
    CHECK(world.collisionCount() == collisions);
    CHECK(world.disks()[7].velocity.x == faster[7].velocity.x);
    CHECK_THROWS_WITH_AS(world.editDisks(faster.data(), 5),
                         "editDisks: 5 disks; allowed: 200 (diskCount(): an edit keeps the number of disks)", Error);
}

TEST_CASE("world: time sums the steps' dt across a change of dt") {
    const Scene scene = gas(200, 0.3f);
    World world(worldFor(scene, ComputeEngine::Cpu, Boundary::Periodic));
    world.setDisks(scene.disks);
    world.step(10);
    world.setMotion(0.02f, Vec2{0.0f, 0.0f});
    world.step(10);
    CHECK(world.time() == doctest::Approx(10 * double(0.01f) + 10 * double(0.02f)).epsilon(1e-12));
    CHECK(world.measurements().time == doctest::Approx(world.time()).epsilon(1e-12));
    // A dt that moves the fastest disk across the box is refused, as at the start.
    CHECK_THROWS_AS(world.setMotion(1e6f, Vec2{0.0f, 0.0f}), Error);
    CHECK(world.def().dt == 0.02f);
}

TEST_CASE("world: the events scheme's counts and exact total energy") {
    const Scene scene = gas(300, 0.3f);
    WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Walls);
    def.collisions = CollisionScheme::Events;
    World world(def);
    world.setDisks(scene.disks);
    const double before = world.totalEnergy();
    world.step(50);
    const EventCounts counts = world.eventCounts();
    CHECK(counts.collisions == world.collisionCount());
    CHECK(counts.wallBounces > 0);
    CHECK(std::fabs(world.totalEnergy() - before) <= 1e-12 * std::fabs(before));
    def.collisions = CollisionScheme::Pairwise;
    World pairwise(def);
    pairwise.setDisks(scene.disks);
    CHECK(pairwise.eventCounts().collisions == 0);
    CHECK(pairwise.totalEnergy() == pairwise.kineticEnergy() + pairwise.potentialEnergy());
}

TEST_CASE("world: the library's version is the headers'") { CHECK(std::string(version()) == CAROM_VERSION); }

TEST_CASE("world: compute engines by name, and which this build has") {
    for (ComputeEngine engine : {ComputeEngine::Cpu, ComputeEngine::OpenClHostGrid, ComputeEngine::OpenClResident})
        CHECK(parseComputeEngine(computeEngineName(engine)) == engine);
    CHECK_THROWS_WITH_AS(parseComputeEngine("cuda"),
                         "unknown compute engine 'cuda'; allowed: cpu, opencl-host-grid, opencl-resident", Error);
    CHECK(engineAvailable(ComputeEngine::Cpu));
#ifdef CAROM_HAVE_OPENCL
    CHECK(engineAvailable(ComputeEngine::OpenClResident));
#else
    CHECK_FALSE(engineAvailable(ComputeEngine::OpenClResident));
#endif
    WorldDef def;
    def.width = def.height = 20.0f;
    World empty(def);
    CHECK(empty.disks().empty());
    CHECK(empty.kineticEnergy() == 0.0);
}

TEST_CASE("world: the OpenCL engine for a device is resident on a GPU, host-grid on the others") {
    Device device;
    device.type = "GPU";
    CHECK(openClEngineFor(device) == ComputeEngine::OpenClResident);
    for (const char* other : {"CPU", "accelerator", "custom"}) {
        CAPTURE(other);
        device.type = other;
        CHECK(openClEngineFor(device) == ComputeEngine::OpenClHostGrid);
    }
}

namespace {

std::string fileText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("io: trajectories and statistics of a resumed world continue the files bit for bit") {
    const Scene scene = gas(200, 0.3f);
    const auto folder = std::filesystem::temp_directory_path() / "carom_world_outputs";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const auto path = [&](const char* name) { return (folder / name).string(); };
    const WorldDef def = worldFor(scene, ComputeEngine::Cpu, Boundary::Walls);

    // One run of 100 steps, sampled every 25.
    World whole(def);
    whole.setDisks(scene.disks);
    io::TrajectoryWriter trajectory(path("whole.xyz"));
    io::StatisticsWriter statistics(path("whole.csv"));
    for (int sample = 0; sample <= 4; ++sample) {
        if (sample > 0) whole.step(25);
        trajectory.write(whole);
        statistics.write(whole);
    }
    CHECK(trajectory.frames() == 5);
    CHECK(statistics.rows() == 5);
    CHECK_FALSE(std::filesystem::exists(path("whole.xyz")));  // not before close()
    trajectory.close();
    statistics.close();

    // The same in two runs, the second resumed from the first's checkpoint.
    {
        World first(def);
        first.setDisks(scene.disks);
        io::TrajectoryWriter t(path("split.xyz"));
        io::StatisticsWriter s(path("split.csv"));
        for (int sample = 0; sample <= 2; ++sample) {
            if (sample > 0) first.step(25);
            t.write(first);
            s.write(first);
        }
        io::saveCheckpoint(path("split.ckpt"), first);
        t.close();
        s.close();
    }
    World second = io::loadCheckpoint(path("split.ckpt"));
    io::TrajectoryWriter t(path("split.xyz"), second);
    io::StatisticsWriter s(path("split.csv"), second);
    for (int sample = 3; sample <= 4; ++sample) {
        second.step(25);
        t.write(second);
        s.write(second);
    }
    t.close();
    s.close();
    CHECK(fileText(path("split.xyz")) == fileText(path("whole.xyz")));
    CHECK(fileText(path("split.csv")) == fileText(path("whole.csv")));
    CHECK(fileText(path("whole.xyz")).rfind("200\n", 0) == 0);

    // A writer dropped without close() leaves no file; a trajectory that ran
    // past the resumed step is refused.
    { io::TrajectoryWriter dropped(path("dropped.xyz")); }
    CHECK_FALSE(std::filesystem::exists(path("dropped.xyz")));
    World early(def);
    early.setDisks(scene.disks);
    CHECK_THROWS_AS(io::TrajectoryWriter(path("whole.xyz"), early), Error);
    std::filesystem::remove_all(folder);
}

// The default engine was OpenCL wherever there was an OpenCL device, PoCL on
// a CPU too, 2.3 times slower than the CPU engine there.
TEST_CASE("world: chooseEngine picks OpenCL on a GPU, the CPU engine otherwise") {
    const Device pocl{0, "pthread-skylake", "Portable Computing Language", "CPU", "OpenCL 3.0", 1u << 30, true};
    const Device gpu{1, "NVIDIA H200", "NVIDIA CUDA", "GPU", "OpenCL 3.0", 1u << 30, false};
    EngineChoice choice = chooseEngine({pocl, gpu});
    CHECK(choice.engine.engine == ComputeEngine::OpenClResident);
    CHECK(choice.engine.device == "1");
    CHECK(choice.reason == "the OpenCL GPU [1] NVIDIA H200");
    choice = chooseEngine({pocl});
    CHECK(choice.engine.engine == ComputeEngine::Cpu);
    CHECK(choice.reason == "no OpenCL GPU, and OpenCL on pthread-skylake (CPU) runs slower than the CPU engine");
    choice = chooseEngine({});
    CHECK(choice.engine.engine == ComputeEngine::Cpu);
    CHECK(choice.reason == "no OpenCL device");
    // This machine: what its own devices give (the CPU engine in CI, which has no GPU).
    const EngineChoice here = chooseEngine(), listed = chooseEngine(listDevices());
    CHECK(here.engine.engine == listed.engine.engine);
    CHECK(here.engine.device == listed.engine.device);
    CHECK(here.reason == listed.reason);
}
