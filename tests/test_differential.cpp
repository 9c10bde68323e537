// CPU vs OpenCL, a test case for each OpenCL pipeline (host-grid, resident) and
// scene, for both collision schemes: bitwise identical trajectories,
// periodic images and contact totals (collisions, virial, wall impulses,
// substeps, late contacts, rounds) where the OpenCL device divides and takes square roots correctly
// rounded (PoCL and NVIDIA do), with walls and periodic boundaries, fixed and
// adaptive steps, under gravity.
//
// Fallback: on a device without correctly rounded divide/sqrt, rounding
// differences grow chaotically, so the comparison drops to a tolerance of
// 1e-3 (relative to the box) on positions over a horizon of 20 steps, and the
// test says so.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/diagnostics.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

// The scene on the CPU and on OpenCL pipeline `def`, compared. `rules` gives
// dt, gravity, boundary and maxTravel; the box comes from the scene.
void compareWithCpu(const EngineDef& def, const SceneDef& scene, WorldDef rules, std::uint64_t steps) {
    const InitialState s = makeInitialState(scene);
    WorldDef world = rules;
    world.width = s.width;
    world.height = s.height;
    auto opencl = makeBackend(def, world);
    MESSAGE("OpenCL device: " << opencl->device());
    if (!opencl->exactArithmetic()) {
        MESSAGE("the device lacks correctly rounded divide/sqrt: comparing within 1e-3 over 20 steps, not bitwise");
        steps = 20;
    }
    ContactTotals cpuContacts;
    std::vector<Image> cpuImages;
    const std::vector<Particle> cpu =
        simulate(testEngine(ComputeEngine::Cpu), world, s.particles, steps, nullptr, &cpuContacts, &cpuImages);
    REQUIRE_MESSAGE(measure(cpu, world).escaped == 0,
                    "the CPU run itself went unstable: nothing meaningful to compare");

    opencl->setParticles(s.particles);
    opencl->step(steps);
    std::vector<Particle> gpu;
    opencl->readParticles(gpu);
    REQUIRE(cpu.size() == gpu.size());
    if (opencl->exactArithmetic()) {
        std::size_t differing = 0;
        for (std::size_t i = 0; i < cpu.size(); ++i)
            if (std::memcmp(&cpu[i], &gpu[i], sizeof(Particle)) != 0) ++differing;
        CHECK_MESSAGE(differing == 0, differing << " of " << cpu.size() << " particles differ after " << steps
                                                << " steps on " << computeEngineName(def.engine));
        // Each particle's float tally sums in the same order on both, and the
        // host adds them up in id order: the totals agree exactly.
        const ContactTotals& contacts = opencl->contacts();
        CHECK(contacts.collisions == cpuContacts.collisions);
        CHECK(contacts.virial == cpuContacts.virial);
        CHECK(contacts.wallImpulse == cpuContacts.wallImpulse);
        CHECK(contacts.substeps == cpuContacts.substeps);
        CHECK(contacts.lateContacts == cpuContacts.lateContacts);
        CHECK(contacts.maxRounds == cpuContacts.maxRounds);
        CHECK(cpuContacts.collisions > cpu.size());  // the comparison covered real collisions
        CHECK(opencl->images() == cpuImages);
        if (world.boundary == Boundary::Periodic)  // the comparison covered disks crossing the box
            CHECK(std::count(cpuImages.begin(), cpuImages.end(), Image{0, 0}) < std::ptrdiff_t(cpuImages.size()));
    } else {
        for (std::size_t i = 0; i < cpu.size(); ++i) {
            CHECK(std::abs(cpu[i].position.x - gpu[i].position.x) < 1e-3f * world.width);
            CHECK(std::abs(cpu[i].position.y - gpu[i].position.y) < 1e-3f * world.height);
        }
    }
}

WorldDef rules(CollisionScheme scheme, float dt, float2 gravity = {0, 0}, Boundary boundary = Boundary::Walls,
               float maxTravel = 0.0f) {
    WorldDef world;
    world.collisions = scheme;
    world.dt = dt;
    world.gravity = gravity;
    world.boundary = boundary;
    world.maxTravel = maxTravel;
    return world;
}

}  // namespace

constexpr CollisionScheme kSimultaneous = CollisionScheme::Simultaneous;
constexpr CollisionScheme kPairwise = CollisionScheme::Pairwise;

// Equal disks at this packing, speed 1.
SceneDef gas(std::uint32_t particles, float packing, std::uint64_t seed) {
    SceneDef scene;
    scene.particles = particles;
    scene.packing = packing;
    scene.seed = seed;
    return scene;
}

CAROM_OPENCL_TEST_CASE(
    "differential, simultaneous: CPU and OpenCL agree bitwise, N = 10000 at packing 0.5 over 1000 steps") {
    compareWithCpu(def, gas(10000, 0.5f, 42), rules(kSimultaneous, 0.01f), 1000);
}

CAROM_OPENCL_TEST_CASE("differential, simultaneous: a periodic box, N = 10000 at packing 0.5 over 1000 steps") {
    compareWithCpu(def, gas(10000, 0.5f, 43), rules(kSimultaneous, 0.01f, {0, 0}, Boundary::Periodic), 1000);
}

// Fast polydisperse disks in a periodic box, split into substeps.
SceneDef fastPolydisperse() {
    SceneDef scene;
    scene.particles = 2000;
    scene.packing = 0.3f;
    scene.radiusMin = 0.5f;
    scene.radiusMax = 1.0f;
    scene.massMin = 0.5f;
    scene.massMax = 4.0f;
    scene.speed = 20.0f;
    scene.seed = 5;
    return scene;
}

CAROM_OPENCL_TEST_CASE(
    "differential, simultaneous: adaptive substeps (max travel 0.2), fast polydisperse disks in a periodic box") {
    compareWithCpu(def, fastPolydisperse(), rules(kSimultaneous, 0.02f, {0, 0}, Boundary::Periodic, 0.2f), 100);
}

// Polydisperse disks with unequal masses falling into a pile.
SceneDef polydisperseUnderGravity() {
    SceneDef scene;
    scene.particles = 3000;
    scene.packing = 0.35f;
    scene.radiusMin = 0.3f;
    scene.radiusMax = 1.2f;
    scene.massMin = 0.1f;
    scene.massMax = 10.0f;
    scene.speed = 2.0f;
    scene.seed = 7;
    return scene;
}

CAROM_OPENCL_TEST_CASE("differential, simultaneous: polydisperse disks with unequal masses under gravity") {
    // dt small enough that the pile forming at the floor stays stable (at
    // dt = 0.01 the simultaneous scheme blows up here: ARCHITECTURE.md).
    compareWithCpu(def, polydisperseUnderGravity(), rules(kSimultaneous, 0.002f, float2{0.5f, -3.0f}), 2000);
}

CAROM_OPENCL_TEST_CASE(
    "differential, pairwise: CPU and OpenCL agree bitwise, N = 10000 at packing 0.5 over 500 steps") {
    compareWithCpu(def, gas(10000, 0.5f, 42), rules(kPairwise, 0.01f), 500);
}

CAROM_OPENCL_TEST_CASE("differential, pairwise: a dense periodic box, N = 4000 at packing 0.7 over 500 steps") {
    compareWithCpu(def, gas(4000, 0.7f, 44), rules(kPairwise, 0.01f, {0, 0}, Boundary::Periodic), 500);
}

CAROM_OPENCL_TEST_CASE("differential, pairwise: fast polydisperse disks in a periodic box, with the grid's substeps") {
    compareWithCpu(def, fastPolydisperse(), rules(kPairwise, 0.02f, {0, 0}, Boundary::Periodic), 100);
}

CAROM_OPENCL_TEST_CASE(
    "differential, pairwise: polydisperse disks with unequal masses piling up under gravity at dt 0.01") {
    compareWithCpu(def, polydisperseUnderGravity(), rules(kPairwise, 0.01f, float2{0.5f, -3.0f}), 1000);
}
