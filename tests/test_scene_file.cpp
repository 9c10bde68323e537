// Scene files: parsing, the refusal of every bad value with file, line, key,
// value and what is allowed, placement of groups and disks, and every scene
// in scenes/ run on the CPU and compared with each OpenCL pipeline.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/diagnostics.h"
#include <carom/io.h>

#include "engine/scene.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

std::string parseError(const std::string& text) {
    try {
        makeInitialState(io::parseSceneFile(text, "s.toml"));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

WorldDef worldOf(const SceneFileDef& scene, const InitialState& s) {
    WorldDef w = scene.world;
    w.width = s.width;
    w.height = s.height;
    return w;
}

bool inside(const Particle& p, const Region& r) {
    return p.position.x - p.radius >= r.xMin && p.position.x + p.radius <= r.xMax &&
           p.position.y - p.radius >= r.yMin && p.position.y + p.radius <= r.yMax;
}

// A scene of scenes/, read and placed.
struct ShippedScene {
    SceneFileDef file;
    InitialState initial;
    WorldDef world;
};

// Every scene in scenes/, in name order.
std::vector<ShippedScene> shippedScenes() {
    std::vector<std::filesystem::path> paths;
    for (const auto& entry : std::filesystem::directory_iterator(CAROM_SCENES_DIR))
        if (entry.path().extension() == ".toml") paths.push_back(entry.path());
    std::sort(paths.begin(), paths.end());
    std::vector<ShippedScene> scenes;
    for (const auto& path : paths) {
        ShippedScene scene{io::readSceneFile(path.string()), {}, {}};
        scene.initial = makeInitialState(scene.file);
        scene.world = worldOf(scene.file, scene.initial);
        scenes.push_back(std::move(scene));
    }
    return scenes;
}

}  // namespace

TEST_CASE("scene file: every key is read") {
    const SceneFileDef s = io::parseSceneFile(R"(
box = [100, 60.5]
boundary = "walls"
collisions = "pairwise"
dt = 0.005
steps = 250
gravity = [0, -9.81]
seed = 42

[[group]]
name = "heavy"
count = 20
radius = [0.5, 1.5]
mass = 10
temperature = 2.5
region = [0, 0, 50, 60.5]

[[group]]
count = 30
speed = 3
region = [50, 0, 100, 30]

[[disk]]
position = [80, 45]
velocity = [-1, 0.5]
mass = 4
radius = 2

[output]
trajectory = "t.xyz"
stats = "s.csv"
checkpoint = "c.ckpt"
state = "f.csv"
every = 25
)",
                                              "s.toml");
    CHECK(s.world.width == 100.0f);
    CHECK(s.world.height == 60.5f);
    CHECK(s.world.dt == 0.005f);
    CHECK(s.world.gravity.y == -9.81f);
    CHECK(s.world.collisions == CollisionScheme::Pairwise);
    CHECK(s.steps == 250);
    CHECK(s.seed == 42);
    REQUIRE(s.groups.size() == 2);
    CHECK(s.groups[0].name == "group[1] 'heavy'");
    CHECK(s.groups[0].line == 10);
    CHECK(s.groups[0].count == 20);
    CHECK(s.groups[0].radiusMin == 0.5f);
    CHECK(s.groups[0].radiusMax == 1.5f);
    CHECK(s.groups[0].massMin == 10.0f);
    CHECK(s.groups[0].massMax == 10.0f);
    CHECK(s.groups[0].temperature == 2.5f);
    REQUIRE(s.groups[0].region);
    CHECK(s.groups[0].region->yMax == 60.5f);
    CHECK(s.groups[1].name == "group[2]");
    CHECK(s.groups[1].speed == 3.0f);
    CHECK(s.groups[1].region->xMin == 50.0f);
    REQUIRE(s.disks.size() == 1);
    CHECK(s.disks[0].position.y == 45.0f);
    CHECK(s.disks[0].velocity.y == 0.5f);
    CHECK(s.disks[0].mass == 4.0f);
    CHECK(s.disks[0].radius == 2.0f);
    CHECK(s.output.trajectory == "t.xyz");
    CHECK(s.output.stats == "s.csv");
    CHECK(s.output.checkpoint == "c.ckpt");
    CHECK(s.output.state == "f.csv");
    CHECK(s.output.every == 25);

    const InitialState placed = makeInitialState(s);
    REQUIRE(placed.particles.size() == 51);
    for (std::size_t i = 0; i < 20; ++i) CHECK(inside(placed.particles[i], *s.groups[0].region));
    CHECK(placed.particles[50].position.x == 80.0f);
    CHECK(placed.particles[50].radius == 2.0f);
    CHECK_NOTHROW(validateParticles(placed.particles, worldOf(s, placed), "scene"));
    CHECK(measure(placed.particles, worldOf(s, placed)).maxOverlap == 0.0);
}

TEST_CASE("scene file: defaults") {
    const SceneFileDef s = io::parseSceneFile("box = [10, 10]\n[[disk]]\nposition = [5, 5]\n", "s.toml");
    CHECK(s.world.dt == 0.01f);
    CHECK(s.world.gravity.x == 0.0f);
    CHECK(s.world.gravity.y == 0.0f);
    CHECK(s.world.collisions == WorldDef{}.collisions);
    CHECK(s.steps == 1000);
    CHECK(s.seed == 1);
    CHECK(s.output.every == 100);
    CHECK(s.output.trajectory.empty());
    REQUIRE(s.disks.size() == 1);
    CHECK(s.disks[0].mass == 1.0f);
    CHECK(s.disks[0].radius == 1.0f);
    CHECK(s.disks[0].velocity.x == 0.0f);
}

TEST_CASE("scene file: bad input is refused with file, line, key, value and what is allowed") {
    struct Case {
        std::string text;
        const char* message;
    };
    const std::string g = "box = [60, 40]\n[[group]]\n";
    for (const Case& c : std::vector<Case>{
             // TOML syntax
             Case{"box = [60, 40\n", "s.toml:1:"},
             Case{"box = [60, 40]\nbox = [1, 1]\n", "s.toml:2:"},
             Case{"box = [60, 40]\ndt = \n", "not valid TOML"},
             Case{"\xff\xfe = 1\n", "not valid TOML"},
             // unknown keys, at every level
             Case{"box = [60, 40]\nradious = 2\n",
                  "s.toml:2: unknown key 'radious'; allowed: boundary, box, collisions, disk"},
             Case{"box = [60, 40]\n[[group]]\ncount = 3\nradious = 2\n",
                  "s.toml:4: unknown key 'group[1].radious'; allowed in group[1]: count, mass, name"},
             Case{"box = [60, 40]\n[[disk]]\nposition = [5, 5]\nspeed = 2\n",
                  "s.toml:4: unknown key 'disk[1].speed'; allowed in disk[1]: mass, position, radius, velocity"},
             Case{"box = [60, 40]\n[[disk]]\nposition = [5, 5]\n[output]\neverry = 2\n",
                  "s.toml:5: unknown key 'output.everry'"},
             Case{"box = [60, 40]\n[groups]\ncount = 3\n", "unknown key 'groups'"},
             // the box
             Case{"dt = 0.1\n[[disk]]\nposition = [5, 5]\n", "s.toml:1: the scene needs box = [W, H]"},
             Case{"box = [60, 40]\npacking = 0.3\n", "s.toml:2: packing = 0.3: give box or packing, not both"},
             Case{"box = [60]\n", "s.toml:1: box = [60]: must be [x, y], two numbers, each a finite number > 0"},
             Case{"box = [60, -4]\n", "s.toml:1: box[1] = -4: must be a finite number > 0"},
             Case{"box = [60, \"wide\"]\n", "box[1] = \"wide\": must be a finite number > 0"},
             Case{"box = [60, inf]\n", "box[1] = inf: must be a finite number > 0"},
             // numbers in decimal only, as on the command line
             Case{"box = [0x3c, 40]\n",
                  "s.toml:1: box[0] = 0x3C: must be written in decimal (0x, 0o and 0b numbers are not read)"},
             Case{"box = [60, 40]\nseed = 0o17\n", "s.toml:2: seed = 0o17: must be written in decimal"},
             Case{"box = [60, 40]\n[[group]]\ncount = 0b11\n", "s.toml:3: group[1].count = 0b11: must be written"},
             Case{"box = [60, 1e39]\n", "s.toml:1: box[1] = 1e+39 is too large for a 32-bit float"},
             Case{"box = [60, 1e-50]\n", "box[1] = 1e-50 is too small for a 32-bit float"},
             Case{"packing = 0.8\n", "s.toml:1: packing = 0.8: must be in (0, 0.7]"},
             Case{"packing = 0.1\n[[group]]\ncount = 2\nradius = 3e38\n",
                  "group[1]: radius 3e+38 is outside [1e-18, 1e+18]"},
             Case{"packing = 0\n", "packing = 0: must be a finite number > 0"},
             Case{"box = [60, 40]\nboundary = \"toroidal\"\n",
                  "s.toml:2: boundary = \"toroidal\": allowed: \"walls\" (reflective) or \"periodic\""},
             Case{"box = [60, 40]\ndt = \"fast\"\n",
                  "s.toml:2: dt = \"fast\": must be a finite number > 0 or \"auto\""},
             Case{"box = [60, 40]\nmax_travel = -1\n", "s.toml:2: max_travel = -1"},
             Case{"box = [60, 40]\ndt = \"auto\"\nmax_travel = 0\n",
                  "s.toml:3: max_travel = 0: dt = \"auto\" splits each step so that no disk moves more than "
                  "max_travel radii, and 0 turns that off"},
             // a value a 32-bit float turns into 0 would change its meaning
             Case{"box = [60, 40]\nmax_travel = 1e-50\n",
                  "s.toml:2: max_travel = 1e-50 is too small for a 32-bit float and would read as 0"},
             Case{"box = [60, 40]\ngravity = [0, -1e-50]\n", "s.toml:2: gravity[1] = -1e-50 is too small"},
             Case{"box = [60, 40]\nboundary = 3\n", "boundary = 3: must be a non-empty string"},
             Case{"box = [60, 40]\ncollisions = \"elastic\"\n",
                  "s.toml:2: collisions = \"elastic\": allowed: \"pairwise\", \"simultaneous\" or \"events\""},
             Case{"box = [60, 40]\ncollisions = true\n", "s.toml:2: collisions = true: must be a non-empty string"},
             // motion and run
             Case{"box = [60, 40]\ndt = -0.01\n", "s.toml:2: dt = -0.01: must be a finite number > 0"},
             Case{"box = [60, 40]\ndt = nan\n", "dt = nan: must be a finite number > 0"},
             Case{"box = [60, 40]\ndt = \"fast\"\n", "dt = \"fast\": must be a finite number > 0"},
             Case{"box = [60, 40]\ngravity = [0, -inf]\n", "gravity[1] = -inf: must be a finite number"},
             Case{"box = [60, 40]\ngravity = 9.81\n", "gravity = 9.81: must be [x, y]"},
             Case{"box = [60, 40]\nsteps = -1\n", "s.toml:2: steps = -1: must be an integer in [0, "},
             Case{"box = [60, 40]\nsteps = 1.5\n", "steps = 1.5: must be an integer"},
             Case{"box = [60, 40]\nseed = -7\n", "seed = -7: must be an integer in [0, "},
             // groups
             Case{"box = [60, 40]\ngroup = 3\n", "group = 3: must be tables: write each as [[group]]"},
             Case{"box = [60, 40]\ngroup = []\n", "group = []: must be tables"},
             Case{g + "name = \"x\"\n", "s.toml:2: group[1] needs 'count'"},
             Case{g + "count = 0\n", "s.toml:3: group[1].count = 0: must be an integer in [1, 1000000000]"},
             Case{g + "count = 1100000000\n", "group[1].count = 1100000000: must be an integer in [1, 1000000000]"},
             Case{g + "count = 2.0\n", "group[1].count = 2.0: must be an integer"},
             Case{g + "count = 3\nradius = 0\n", "s.toml:4: group[1].radius = 0: must be a finite number > 0"},
             Case{g + "count = 3\nradius = [2, 1]\n",
                  "group[1].radius = [2, 1]: the range [min, max] must have min <= max"},
             Case{g + "count = 3\nradius = [1, 2, 3]\n", "must be a number > 0 or a range [min, max]"},
             Case{g + "count = 3\nmass = [1, -2]\n", "group[1].mass[1] = -2: must be a finite number > 0"},
             Case{g + "count = 3\nspeed = -1\n", "group[1].speed = -1: must be a finite number >= 0"},
             Case{g + "count = 3\nspeed = 1e-50\n", "s.toml:4: group[1].speed = 1e-50 is too small"},
             Case{g + "count = 3\ntemperature = 0\n", "group[1].temperature = 0: must be a finite number > 0"},
             Case{g + "count = 3\nspeed = 1\ntemperature = 1\n", "give speed or temperature, not both"},
             Case{g + "count = 3\nname = \"\"\n", "group[1].name = \"\": must be a non-empty string"},
             Case{g + "count = 3\nregion = [0, 0, 10]\n", "must be [x_min, y_min, x_max, y_max]"},
             Case{g + "count = 3\nregion = [10, 0, 5, 40]\n", "needs x_min < x_max and y_min < y_max"},
             Case{g + "count = 3\nregion = [0, 0, 70, 40]\n",
                  "s.toml:2: group[1]: region [0, 0, 70, 40] extends past the 60 x 40 box"},
             Case{"packing = 0.3\n[[group]]\ncount = 3\nregion = [0, 0, 5, 5]\n",
                  "group[1]: a region needs a known box"},
             Case{g + "count = 3\nregion = [0, 0, 30, 40]\n[[group]]\ncount = 3\nregion = [20, 0, 60, 40]\n",
                  "s.toml:5: group[2]: region [20, 0, 60, 40] overlaps region [0, 0, 30, 40] of group[1] (line 2)"},
             Case{g + "count = 3000\n", "s.toml:2: group[1]: cannot place 3000 disks"},
             Case{g + "count = 3\nradius = 30\n", "group[1]: a disk of radius 30 does not fit"},
             Case{"box = [60, 40]\n" +
                      [] {
                          std::string many;
                          for (int k = 0; k < 10001; ++k) many += "[[group]]\ncount = 1\n";
                          return many;
                      }(),
                  "s.toml:2: 10001 [[group]] tables; allowed: at most 10000"},
             // disks
             Case{"box = [60, 40]\n[[disk]]\nvelocity = [1, 0]\n", "s.toml:2: disk[1] needs 'position'"},
             Case{"box = [60, 40]\n[[disk]]\nposition = [0.5, 5]\n",
                  "s.toml:2: disk[1]: position (0.5, 5) with radius 1 puts the disk outside the 60 x 40 box"},
             Case{"box = [60, 40]\n[[disk]]\nposition = [5, 5]\nvelocity = [nan, 0]\n",
                  "disk[1].velocity[0] = nan: must be a finite number"},
             Case{"box = [60, 40]\n[[disk]]\nposition = [5, 5]\n[[disk]]\nposition = [6, 5]\n",
                  "s.toml:4: disk[2] (line 4) at (6, 5) overlaps disk[1] (line 2) at (5, 5)"},
             Case{"box = [10, 10]\n[[group]]\ncount = 20\n[[disk]]\nposition = [5, 5]\n", "overlaps particle"},
             Case{"packing = 0.3\n[[disk]]\nposition = [5, 5]\n", "disk[1]: a disk needs a known box"},
             // outputs
             Case{"box = [60, 40]\noutput = 3\n", "output = 3: must be a table"},
             Case{"box = [60, 40]\n[output]\nevery = 0\n", "s.toml:3: output.every = 0: must be an integer in [1, "},
             Case{"box = [60, 40]\n[output]\ntrajectory = 7\n", "output.trajectory = 7: must be a non-empty string"},
             // nothing to simulate
             Case{"box = [60, 40]\n", "s.toml: the scene has no particles"},
         }) {
        CAPTURE(c.text);
        const std::string message = parseError(c.text);
        CHECK_MESSAGE(message.find(c.message) != std::string::npos, message);
    }
}

TEST_CASE("scene file: values in messages are cut short and made printable") {
    const std::string message = parseError("box = [60, 40]\nboundary = \"" + std::string(200, 'w') + "\\u0007\"\n");
    CHECK(message.find(std::string(30, 'w')) != std::string::npos);
    CHECK(message.find(std::string(60, 'w')) == std::string::npos);
    CHECK(message.find("...") != std::string::npos);
}

TEST_CASE("scene file: max_travel = 0 turns substeps off, as --max-travel 0 does") {
    const SceneFileDef s =
        io::parseSceneFile("box = [60, 40]\nmax_travel = 0\n[[disk]]\nposition = [5, 5]\n", "s.toml");
    CHECK(s.world.maxTravel == 0.0f);
    CHECK(io::parseSceneFile("box = [60, 40]\ndt = \"auto\"\nmax_travel = 0.5\n[[disk]]\nposition = [5, 5]\n", "s.toml")
              .world.maxTravel == 0.5f);
}

TEST_CASE("scene file: a binary file is refused at its first NUL byte") {
    { std::ofstream("nul.toml", std::ios::binary) << std::string("box = [60, 40]\n\0\0\0", 18); }
    CHECK_THROWS_WITH_AS(io::readSceneFile("nul.toml"),
                         "scene file 'nul.toml': a NUL byte, which no text file has (is it a scene file?)", Error);
    std::remove("nul.toml");
}

TEST_CASE("scene file: a missing or oversized file is refused") {
    CHECK_THROWS_WITH_AS(io::readSceneFile("no-such-scene.toml"), doctest::Contains("cannot read scene file"), Error);
    CHECK_THROWS_WITH_AS(io::readSceneFile("."), doctest::Contains("cannot read scene file '.'"), Error);
}

TEST_CASE("scene file: one group filling the box is makeInitialState(SceneDef)") {
    SceneFileDef file = io::parseSceneFile(
        "packing = 0.45\n[[group]]\ncount = 700\nradius = [0.5, 1]\nmass = [1, 3]\n"
        "speed = 2\n",
        "s.toml");
    SceneDef def;
    def.particles = 700;
    def.packing = 0.45f;
    def.radiusMin = 0.5f;
    def.massMax = 3.0f;
    def.speed = 2.0f;
    const InitialState a = makeInitialState(file), b = makeInitialState(def);
    CHECK(a.width == b.width);
    REQUIRE(a.particles.size() == b.particles.size());
    CHECK(std::memcmp(a.particles.data(), b.particles.data(), a.particles.size() * sizeof(Particle)) == 0);

    const SceneFileDef demo = io::readSceneFile(std::string(CAROM_SCENES_DIR) + "/demo.toml");
    const InitialState c = makeInitialState(demo), d = makeInitialState(SceneDef{});
    REQUIRE(c.particles.size() == d.particles.size());
    CHECK(std::memcmp(c.particles.data(), d.particles.data(), c.particles.size() * sizeof(Particle)) == 0);
}

TEST_CASE("scene file: groups sharing a region are mixed; each stays in its region") {
    const SceneFileDef s = io::parseSceneFile(R"(
box = [120, 40]
[[group]]
count = 300
mass = 1
region = [0, 0, 60, 40]
[[group]]
count = 300
mass = 10
radius = 0.5
region = [0, 0, 60, 40]
[[group]]
count = 100
radius = [0.5, 2]
region = [60, 0, 120, 40]
)",
                                              "s.toml");
    const InitialState placed = makeInitialState(s);
    REQUIRE(placed.particles.size() == 700);
    const Diagnostics d = measure(placed.particles, worldOf(s, placed));
    CHECK(d.maxOverlap == 0.0);
    CHECK(d.escaped == 0);
    int heavyOnLeft = 0, heavyOnRight = 0;
    for (std::size_t i = 0; i < 700; ++i) {
        const Particle& p = placed.particles[i];
        const GroupDef& g = s.groups[i < 300 ? 0 : i < 600 ? 1 : 2];
        CHECK(inside(p, *g.region));
        CHECK(p.mass == (i < 300 ? 1.0f : i < 600 ? 10.0f : 1.0f));
        if (i >= 300 && i < 600) (p.position.x < 30 ? heavyOnLeft : heavyOnRight)++;
    }
    // Shuffled over one lattice: both halves of the shared region hold heavy disks.
    CHECK(heavyOnLeft > 100);
    CHECK(heavyOnRight > 100);
}

// Found by the scene-file fuzzer: disks of groups in regions side by side
// touch across the common edge, where rounding makes a hair of overlap; the
// check of the [[disk]]s took such a pair for a [[disk]]'s and read past
// the disks' list.
TEST_CASE("scene file: groups in regions side by side may touch across the edge") {
    const SceneFileDef file = io::parseSceneFile(R"(
box = [100, 60.5]
seed = 42
[[group]]
count = 81
radius = [0.5, 1.5]
mass = 10
temperature = 2.5
region = [0, 0, 50, 60.5]
[[group]]
count = 30
speed = 3
region = [50, 0, 100, 30]
[[group]]
count = 99
mass = [1, 2]
region = [50, 0, 100, 30]
[[disk]]
position = [80, 45]
radius = 3
)",
                                                 "s.toml");
    const InitialState placed = makeInitialState(file);
    REQUIRE(placed.particles.size() == 211);
    // The pair that touches: a disk of the first group against the region's edge, one of the others beside it.
    CHECK(placed.particles[13].position.x + placed.particles[13].radius <= 50.0f);
    CHECK(placed.particles[190].position.x - placed.particles[190].radius >= 50.0f);
    CHECK(overlapOf(placed.particles[13], placed.particles[190], worldOf(file, placed)) > 0.0);
    CHECK(parseError(R"(
box = [100, 60.5]
[[group]]
count = 30
region = [50, 0, 100, 30]
[[disk]]
position = [51, 1]
)") == "s.toml:6: disk[1] (line 6) at (51, 1) overlaps particle 0 of the groups at (51.7692, 1.86016); disks may touch "
       "but not overlap");
}

TEST_CASE("scene file: temperature gives Maxwell-Boltzmann velocities") {
    const SceneFileDef s = io::parseSceneFile(R"(
box = [300, 300]
[[group]]
count = 4000
mass = 2
temperature = 1.5
[[group]]
count = 4000
mass = 8
temperature = 1.5
)",
                                              "s.toml");
    const InitialState placed = makeInitialState(s);
    // Equipartition in 2D: each disk's mean kinetic energy is k_B T, for either mass.
    for (int group = 0; group < 2; ++group) {
        double energy = 0.0, momentumX = 0.0;
        for (int i = 0; i < 4000; ++i) {
            const Particle& p = placed.particles[group * 4000 + i];
            energy += 0.5 * p.mass * (double(p.velocity.x) * p.velocity.x + double(p.velocity.y) * p.velocity.y);
            momentumX += p.mass * p.velocity.x;
        }
        CAPTURE(group);
        CHECK(energy / 4000 == doctest::Approx(1.5).epsilon(0.05));
        CHECK(std::fabs(momentumX / 4000) < 0.1);
    }
}

TEST_CASE("scene file: the seed decides, bit for bit") {
    const char* text = "box = [80, 80]\n[[group]]\ncount = 200\ntemperature = 1\n[[group]]\ncount = 100\nmass = 3\n";
    SceneFileDef s = io::parseSceneFile(text, "s.toml");
    const InitialState a = makeInitialState(s), b = makeInitialState(s);
    CHECK(std::memcmp(a.particles.data(), b.particles.data(), a.particles.size() * sizeof(Particle)) == 0);
    s.seed = 2;
    const InitialState c = makeInitialState(s);
    CHECK(std::memcmp(a.particles.data(), c.particles.data(), a.particles.size() * sizeof(Particle)) != 0);
}

TEST_CASE("scenes/: every shipped scene runs on the CPU and stays in its box") {
    const auto scenes = shippedScenes();
    CHECK(scenes.size() >= 6);
    for (const ShippedScene& scene : scenes) {
        CAPTURE(scene.file.path);
        const std::vector<Particle> end =
            simulate(testEngine(ComputeEngine::Cpu), scene.world, scene.initial.particles, scene.file.steps);
        const Diagnostics d = measure(end, scene.world);
        CHECK(d.escaped == 0);
        CHECK(std::isfinite(d.kineticEnergy));
        CHECK(d.maxOverlap < 0.1);
    }
}

CAROM_OPENCL_TEST_CASE("scenes/: every shipped scene agrees with the CPU bit for bit over its first 200 steps") {
    const auto scenes = shippedScenes();
    CHECK(scenes.size() >= 6);
    for (const ShippedScene& scene : scenes) {
        CAPTURE(scene.file.path);
        if (!makeBackend(def, scene.world)->exactArithmetic()) {
            MESSAGE("the OpenCL device lacks correctly rounded divide/sqrt: the backends do not agree bitwise");
            return;
        }
        const std::uint64_t steps = std::min<std::uint64_t>(scene.file.steps, 200);
        const auto a = simulate(testEngine(ComputeEngine::Cpu), scene.world, scene.initial.particles, steps);
        const auto b = simulate(def, scene.world, scene.initial.particles, steps);
        CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(Particle)) == 0);
    }
}

CAROM_BACKEND_TEST_CASE("scenes/newtons_cradle.toml: the striker stops and the last disk leaves") {
    const SceneFileDef scene = io::readSceneFile(std::string(CAROM_SCENES_DIR) + "/newtons_cradle.toml");
    const InitialState initial = makeInitialState(scene);
    const auto end = simulate(def, worldOf(scene, initial), initial.particles, scene.steps);
    REQUIRE(end.size() == 6);
    CHECK(std::fabs(end[0].velocity.x) < 1e-3);
    for (int i = 1; i < 5; ++i) CHECK(std::fabs(end[i].velocity.x) < 1e-3);
    CHECK(end[5].velocity.x == doctest::Approx(2.0).epsilon(1e-4));
}
