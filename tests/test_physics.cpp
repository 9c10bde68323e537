// The physics of a step, once per backend and pipeline: exact two-body
// collisions (shared/physics/hard-disks.md), walls, gravity and conservation
// laws.
#include <cmath>
#include <cstring>

#include <carom/types.h>

#include "engine/diagnostics.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

constexpr double kEps = 1e-5;

double speed(const Particle& p) { return std::hypot(p.velocity.x, p.velocity.y); }
double angleDegrees(const Particle& p) { return std::atan2(p.velocity.y, p.velocity.x) * 180.0 / kPi; }

}  // namespace

CAROM_BACKEND_TEST_CASE("head-on collisions with unequal masses match the analytic result") {
    struct Case {
        float m1, m2, v1, v2, expected1, expected2;
    };
    for (const Case c : {Case{1, 3, 2, 0, -1, 1}, Case{3, 1, 1, 0, 0.5f, 1.5f}}) {
        CAPTURE(c.m1);
        // Overlapping by 0.01 and approaching: one step applies the impulse.
        const std::vector<Particle> start = {disk(10, 10, c.v1, 0, c.m1), disk(11.99f, 10, c.v2, 0, c.m2)};
        std::uint64_t collisions = 0;
        const auto after = simulate(def, box(40, 20, 1e-3f), start, 1, &collisions);
        CHECK(after[0].velocity.x == doctest::Approx(c.expected1).epsilon(kEps));
        CHECK(after[1].velocity.x == doctest::Approx(c.expected2).epsilon(kEps));
        CHECK(after[0].velocity.y == 0.0f);
        CHECK(collisions == 1);

        // Separating afterwards: no second impulse, and the overlap is gone.
        const auto later = simulate(def, box(40, 20, 1e-3f), start, 200, &collisions);
        CHECK(collisions == 1);
        CHECK(later[1].position.x - later[0].position.x >= 2.0f);
    }
}

CAROM_BACKEND_TEST_CASE("oblique collision, equal masses, impact parameter sigma/2") {
    // The target sits 30 degrees below the line of flight: it leaves at 0.866 v
    // along the line of centres (-30 degrees), the projectile at 0.5 v at +60.
    const float d = 1.999f;
    const float angle = float(kPi / 6);
    const std::vector<Particle> start = {disk(10, 10, 1, 0),
                                         disk(10 + d * std::cos(angle), 10 - d * std::sin(angle), 0, 0)};
    const auto after = simulate(def, box(40, 20, 1e-3f), start, 1);
    CHECK(speed(after[1]) == doctest::Approx(std::sqrt(3.0) / 2).epsilon(kEps));
    CHECK(angleDegrees(after[1]) == doctest::Approx(-30.0).epsilon(kEps));
    CHECK(speed(after[0]) == doctest::Approx(0.5).epsilon(kEps));
    CHECK(angleDegrees(after[0]) == doctest::Approx(60.0).epsilon(kEps));
}

CAROM_BACKEND_TEST_CASE("oblique collision with unequal masses conserves momentum and energy") {
    const std::vector<Particle> start = {disk(10, 10, 1.5f, 0.25f, 2.0f, 1.0f),
                                         disk(11.2f, 10.9f, -0.5f, 0.1f, 0.5f, 0.5f)};
    const auto after = simulate(def, box(40, 20, 1e-3f), start, 1);
    // The analytic response, in double, for the normal at the moment of impact.
    const double nx = 10 - 11.2, ny = 10 - 10.9, n2 = nx * nx + ny * ny;
    const double approach = (1.5 + 0.5) * nx + (0.25 - 0.1) * ny;
    const double m1 = 2.0, m2 = 0.5;
    CHECK(after[0].velocity.x == doctest::Approx(1.5 - 2 * m2 / (m1 + m2) * approach / n2 * nx).epsilon(kEps));
    CHECK(after[0].velocity.y == doctest::Approx(0.25 - 2 * m2 / (m1 + m2) * approach / n2 * ny).epsilon(kEps));
    CHECK(after[1].velocity.x == doctest::Approx(-0.5 + 2 * m1 / (m1 + m2) * approach / n2 * nx).epsilon(kEps));
    CHECK(after[1].velocity.y == doctest::Approx(0.1 + 2 * m1 / (m1 + m2) * approach / n2 * ny).epsilon(kEps));
    const auto before = measure(start, box(40, 20));
    const auto now = measure(after, box(40, 20));
    CHECK(now.kineticEnergy == doctest::Approx(before.kineticEnergy).epsilon(kEps));
    CHECK(now.momentum[0] == doctest::Approx(before.momentum[0]).epsilon(kEps));
    CHECK(now.momentum[1] == doctest::Approx(before.momentum[1]).epsilon(kEps));
}

CAROM_BACKEND_TEST_CASE("walls clamp the disk to the boundary and reflect the velocity (simultaneous scheme)") {
    WorldDef world = box(40, 20);
    world.collisions = CollisionScheme::Simultaneous;  // the pairwise walls: test_pairwise.cpp
    // Each disk crosses one wall within the step (dt 0.01, speed 1).
    const std::vector<Particle> start = {disk(1.005f, 10, -1, 0), disk(38.995f, 10, 1, 0), disk(20, 1.005f, 0, -1),
                                         disk(10, 18.995f, 0, 1)};
    const auto after = simulate(def, world, start, 1);
    CHECK(after[0].position.x == 1.0f);
    CHECK(after[0].velocity.x == 1.0f);
    CHECK(after[1].position.x == 39.0f);
    CHECK(after[1].velocity.x == -1.0f);
    CHECK(after[2].position.y == 1.0f);
    CHECK(after[2].velocity.y == 1.0f);
    CHECK(after[3].position.y == 19.0f);
    CHECK(after[3].velocity.y == -1.0f);

    // A disk pushed into the wall by a neighbour while moving away from it
    // is clamped but keeps its velocity (negating it would send it back out).
    const std::vector<Particle> pushed = {disk(1, 10, 0.5f, 0), disk(2.9f, 10, 2, 0)};
    const auto afterPush = simulate(def, world, pushed, 1);
    CHECK(afterPush[0].position.x == 1.0f);
    CHECK(afterPush[0].velocity.x == 0.5f);

    // After many bounces nothing has left the box.
    const auto longRun = simulate(def, world, start, 5000);
    CHECK(measure(longRun, box(40, 20)).escaped == 0);
}

CAROM_BACKEND_TEST_CASE("gravity is off by default and accelerates when set") {
    CHECK(WorldDef{}.gravity.x == 0.0f);
    CHECK(WorldDef{}.gravity.y == 0.0f);
    WorldDef world = box(40, 40, 0.01f);
    world.gravity = float2{0, -2};
    // The pairwise scheme flies the exact parabola: y = y0 + g t^2 / 2.
    const auto after = simulate(def, world, {disk(20, 30, 0, 0)}, 100);
    CHECK(after[0].velocity.y == doctest::Approx(-2.0).epsilon(1e-4));
    CHECK(after[0].position.y == doctest::Approx(29.0).epsilon(1e-5));
    // Semi-implicit Euler: y = y0 + g dt^2 (1 + 2 + ... + 100) = 30 - 2e-4 * 5050.
    world.collisions = CollisionScheme::Simultaneous;
    const auto euler = simulate(def, world, {disk(20, 30, 0, 0)}, 100);
    CHECK(euler[0].velocity.y == doctest::Approx(-2.0).epsilon(1e-4));
    CHECK(euler[0].position.y == doctest::Approx(30 - 2e-4 * 5050).epsilon(1e-4));
}

CAROM_BACKEND_TEST_CASE("momentum is conserved for disks away from the walls") {
    SceneDef scene;
    scene.particles = 400;
    scene.width = scene.height = 50;
    scene.speed = 1;
    InitialState cluster = makeInitialState(scene);
    for (Particle& p : cluster.particles) {  // into the middle of a box far larger than the travel
        p.position.x += 475;
        p.position.y += 475;
    }
    const WorldDef world = box(1000, 1000, 0.01f);
    const Diagnostics before = measure(cluster.particles, world);
    std::uint64_t collisions = 0;
    const auto after = simulate(def, world, cluster.particles, 500, &collisions);
    const Diagnostics now = measure(after, world);
    CHECK(collisions > 100);
    // Impulses are equal and opposite up to float rounding; the scale is
    // the sum of |m v| = 400.
    CHECK(std::abs(now.momentum[0] - before.momentum[0]) < 1e-3);
    CHECK(std::abs(now.momentum[1] - before.momentum[1]) < 1e-3);
}

CAROM_BACKEND_TEST_CASE("a dilute gas keeps its kinetic energy within 1% over 10^4 steps") {
    SceneDef scene;
    scene.particles = 500;
    scene.packing = 0.05f;
    const InitialState gas = makeInitialState(scene);
    const WorldDef world = box(gas.width, gas.height, 0.01f);
    const double initialEnergy = measure(gas.particles, world).kineticEnergy;
    std::uint64_t collisions = 0;
    const auto after = simulate(def, world, gas.particles, 10000, &collisions);
    const Diagnostics now = measure(after, world);
    CHECK(collisions > 1000);  // the gas did collide
    CHECK(now.escaped == 0);
    CHECK(std::abs(now.kineticEnergy - initialEnergy) / initialEnergy < 0.01);
}

CAROM_BACKEND_TEST_CASE("determinism: the same input gives the same bytes") {
    SceneDef scene;
    scene.particles = 2000;
    scene.packing = 0.45f;
    scene.radiusMin = 0.5f;
    scene.radiusMax = 1.0f;
    scene.massMin = 1.0f;
    scene.massMax = 4.0f;
    const InitialState s = makeInitialState(scene);
    WorldDef world = box(s.width, s.height);
    world.gravity = float2{0.1f, -0.3f};
    std::uint64_t collisionsA = 0, collisionsB = 0;
    const auto a = simulate(def, world, s.particles, 300, &collisionsA);
    const auto b = simulate(def, world, s.particles, 300, &collisionsB);
    CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(Particle)) == 0);
    CHECK(collisionsA == collisionsB);
}
