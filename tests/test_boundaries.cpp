// Periodic boxes, contact statistics (collisions, virial, wall impulses) and
// adaptive substeps, registered once per backend and pipeline.
#include <cmath>
#include <cstdint>
#include <limits>

#include "io/checkpoint.h"
#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

WorldDef periodicBox(float width, float height, float dt = 0.01f) {
    WorldDef world = box(width, height, dt);
    world.boundary = Boundary::Periodic;
    return world;
}

double momentumError(const std::vector<Particle>& before, const std::vector<Particle>& after, double* scale) {
    double px = 0, py = 0;
    *scale = 0;
    for (const Particle& p : before) {
        px -= double(p.mass) * p.velocity.x;
        py -= double(p.mass) * p.velocity.y;
        *scale += double(p.mass) * std::hypot(double(p.velocity.x), double(p.velocity.y));
    }
    for (const Particle& p : after) {
        px += double(p.mass) * p.velocity.x;
        py += double(p.mass) * p.velocity.y;
    }
    return std::hypot(px, py);
}

}  // namespace

CAROM_BACKEND_TEST_CASE("periodic: a disk leaving one side enters the opposite one") {
    const auto after = simulate(def, periodicBox(20, 10, 0.125f), {disk(19.5f, 9.75f, 1, 1)}, 8);
    // Moved by (1, 1) to (20.5, 10.75): wrapped to (0.5, 0.75).
    CHECK(after[0].position.x == doctest::Approx(0.5f).epsilon(1e-5));
    CHECK(after[0].position.y == doctest::Approx(0.75f).epsilon(1e-5));
    CHECK(after[0].velocity.x == 1.0f);
    CHECK(after[0].velocity.y == 1.0f);
}

CAROM_BACKEND_TEST_CASE("periodic: images count the box lengths crossed, so positions unwrap onto the line") {
    // (5, 5) moving at (7, -3) for 10 time units: at (75, -25), 3 widths right and 3 heights down.
    for (const CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Pairwise}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef world = periodicBox(20, 10, 0.01f);
        world.collisions = scheme;
        const Run r = run(def, world, {disk(5, 5, 7, -3, 1, 0.5f)}, 1000);
        REQUIRE(r.images.size() == 1);
        CHECK(r.images[0] == Image{3, -3});
        CHECK(r.particles[0].position.x + 20.0 * r.images[0][0] == doctest::Approx(75).epsilon(1e-4));
        CHECK(r.particles[0].position.y + 10.0 * r.images[0][1] == doctest::Approx(-25).epsilon(1e-4));
        world.boundary = Boundary::Walls;  // walls reflect: no images
        CHECK(run(def, world, {disk(5, 5, 7, -3, 1, 0.5f)}, 1000).images[0] == Image{0, 0});
    }
}

CAROM_BACKEND_TEST_CASE("periodic: image counts wrap around modulo 2^32 instead of overflowing") {
    for (const CollisionScheme scheme :
         {CollisionScheme::Simultaneous, CollisionScheme::Pairwise, CollisionScheme::Events}) {
        if (scheme == CollisionScheme::Events && def.engine != ComputeEngine::Cpu) continue;
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef world = periodicBox(20, 10, 0.01f);
        world.collisions = scheme;
        auto backend = makeBackend(def, world);
        const std::int32_t most = std::numeric_limits<std::int32_t>::max();
        backend->setParticles({disk(19.5f, 0.5f, 100, -100, 1, 0.25f)}, 0, {Image{most, -most - 1}});
        backend->step(1);  // to (20.5, -0.5): across the right and the bottom side
        CHECK(backend->images()[0] == Image{-most - 1, most});
    }
}

CAROM_BACKEND_TEST_CASE("periodic: disks collide with the nearest image across the edge") {
    // 3 apart across x = 0, closing at speed 2: they touch after 0.5.
    const Run r = run(def, periodicBox(20, 20, 0.001f), {disk(1.5f, 10, -1, 0), disk(18.5f, 10, 1, 0)}, 1000);
    CHECK(r.contacts.collisions == 1);
    CHECK(r.particles[0].velocity.x == doctest::Approx(1.0f).epsilon(1e-5));
    CHECK(r.particles[1].velocity.x == doctest::Approx(-1.0f).epsilon(1e-5));
    // Bounced back: both are on their own side of the edge again.
    CHECK(r.particles[0].position.x > 1.0f);
    CHECK(r.particles[1].position.x < 19.0f);
}

CAROM_BACKEND_TEST_CASE("periodic: momentum is conserved to rounding, and with walls it is not") {
    SceneDef scene;
    scene.particles = 3000;
    scene.packing = 0.45f;
    scene.radiusMin = 0.5f;
    scene.radiusMax = 1.0f;
    scene.massMin = 0.2f;
    scene.massMax = 5.0f;
    scene.speed = 1.5f;
    scene.seed = 11;
    const InitialState s = makeInitialState(scene);
    double scale = 0;
    const Run periodic = run(def, periodicBox(s.width, s.height), s.particles, 2000);
    const double periodicError = momentumError(s.particles, periodic.particles, &scale);
    REQUIRE(periodic.contacts.collisions > 10 * s.particles.size());
    CHECK_MESSAGE(periodicError < 1e-5 * scale, "momentum changed by " << periodicError << " of " << scale);

    // The same check on walls, which do push the gas around, fails by far.
    const Run walls = run(def, box(s.width, s.height), s.particles, 2000);
    CHECK(momentumError(s.particles, walls.particles, &scale) > 1e-3 * scale);
}

TEST_CASE("periodic: a box under 3 diameters wide is refused, naming the sizes") {
    auto backend = makeBackend(EngineDef{}, periodicBox(5, 50));
    CHECK_THROWS_WITH_AS(backend->setParticles({disk(2.5f, 25, 0, 0)}),
                         doctest::Contains("a periodic box must be at least 3 largest diameters"), Error);
}

TEST_CASE("periodic: positions must lie inside the box, from 0 up to but not on the far edge") {
    CHECK_NOTHROW(validateParticles({disk(0.0f, 0.5f, 0, 0)}, periodicBox(10, 10), "state"));
    CHECK_THROWS_WITH_AS(validateParticles({disk(10.0f, 5, 0, 0)}, periodicBox(10, 10), "state"),
                         doctest::Contains("outside the periodic box"), Error);
    CHECK_THROWS_AS(validateParticles({disk(0.0f, 5, 0, 0)}, box(10, 10), "state"), Error);
}

TEST_CASE("periodic: checkpoints keep the boundary") {
    Snapshot c;
    c.world = periodicBox(30, 20);
    c.disks = disksOf({disk(0.25f, 19.5f, 1, -1)});
    const Snapshot back = decodeCheckpoint(encodeCheckpoint(c), "test");
    CHECK(back.world.boundary == Boundary::Periodic);
    c.world.boundary = Boundary::Walls;
    c.disks = disksOf({disk(5, 5, 1, -1)});
    CHECK(decodeCheckpoint(encodeCheckpoint(c), "test").world.boundary == Boundary::Walls);
}

CAROM_BACKEND_TEST_CASE("contacts: one head-on collision has the virial 2 mu v_n r") {
    // Masses 1 and 3 (mu = 3/4), closing at 2: r.J = 2 mu |v_n| r = 3 r, r a hair under 2.
    const Run r = run(def, periodicBox(40, 20, 1e-3f), {disk(15, 10, 1, 0, 1), disk(25, 10, -1, 0, 3)}, 5000);
    CHECK(r.contacts.collisions == 1);
    CHECK(r.contacts.virial <= 6.0);
    CHECK(r.contacts.virial > 6.0 * (1 - 2e-3));  // the overlap at the impulse is below v dt
    CHECK(r.contacts.time == doctest::Approx(5.0).epsilon(1e-6));
    CHECK(r.contacts.steps == 5000);
}

CAROM_BACKEND_TEST_CASE("contacts: a disk bouncing between walls gives each wall 2 m v per bounce") {
    // Period 2 (L - 2r) / |v| = 16; from the middle moving right, 10
    // bounces on each side wall in 160 time units.
    const Run r = run(def, box(10, 10, 0.01f), {disk(5, 5, 1, 0, 2)}, 16000);
    CHECK(r.contacts.wallImpulse[0] == 40.0);  // left: 10 x 2 x 2 x 1
    CHECK(r.contacts.wallImpulse[1] == 40.0);  // right
    CHECK(r.contacts.wallImpulse[2] == 0.0);
    CHECK(r.contacts.wallImpulse[3] == 0.0);
    CHECK(r.contacts.collisions == 0);
}

CAROM_BACKEND_TEST_CASE("contacts: a dilute gas pushes on the walls with P A = N kT") {
    SceneDef scene;
    scene.particles = 2000;
    scene.packing = 0.005f;
    scene.radiusMin = scene.radiusMax = 0.05f;
    scene.speed = 1.0f;
    const InitialState s = makeInitialState(scene);
    const WorldDef world = box(s.width, s.height, 0.05f);
    const Run r = run(def, world, s.particles, 4000);
    const double kT = temperature(r.particles, Boundary::Walls);
    const Thermodynamics t = thermodynamics(r.contacts, kT, s.particles.size(), world);
    // Hard disks at packing 0.005: Z = 1.01. Every disk crosses the box
    // about 5 times, so the wall impulse averages well.
    CHECK(t.wallZ == doctest::Approx(1.01).epsilon(0.03));
    CHECK(t.wallPressure[0] == doctest::Approx(t.wallPressureMean).epsilon(0.1));
    CHECK(t.wallPressure[3] == doctest::Approx(t.wallPressureMean).epsilon(0.1));
}

CAROM_BACKEND_TEST_CASE(
    "substeps: a fast head-on pair tunnels through the simultaneous scheme with a fixed dt, and "
    "collides with max travel or the pairwise scheme") {
    // Closing at 50 with dt 0.1: 2.5 apart, then passed through. With max
    // travel 0.2 each step takes ceil(25 x 0.1 / 0.2) = 13 substeps.
    const std::vector<Particle> pair = {disk(40, 10, 25, 0), disk(47.5f, 10, -25, 0)};
    // The pairwise scheme finds the contact within the step: no tunnelling at any dt.
    const Run pairwise = run(def, box(100, 20, 0.1f), pair, 2);
    CHECK(pairwise.contacts.collisions == 1);
    CHECK(pairwise.particles[0].velocity.x == doctest::Approx(-25.0f).epsilon(1e-5));
    CHECK(pairwise.particles[0].position.x == doctest::Approx(40.5f).epsilon(1e-5));  // met at 42.75, t = 0.11

    WorldDef world = box(100, 20, 0.1f);
    world.collisions = CollisionScheme::Simultaneous;
    const Run fixed = run(def, world, pair, 2);
    CHECK(fixed.contacts.collisions == 0);
    CHECK(fixed.particles[0].position.x > fixed.particles[1].position.x);  // passed through each other
    CHECK(fixed.particles[0].velocity.x == 25.0f);

    world.maxTravel = 0.2f;
    const Run adaptive = run(def, world, pair, 2);
    CHECK(adaptive.contacts.collisions == 1);
    CHECK(adaptive.contacts.substeps == 26);
    CHECK(adaptive.contacts.time == doctest::Approx(0.2).epsilon(1e-6));
    CHECK(adaptive.particles[0].position.x < adaptive.particles[1].position.x);
    CHECK(adaptive.particles[0].velocity.x == doctest::Approx(-25.0f).epsilon(1e-5));
    CHECK(adaptive.particles[1].velocity.x == doctest::Approx(25.0f).epsilon(1e-5));
}

CAROM_BACKEND_TEST_CASE("substeps: gravity counts towards the travel, and a runaway step is refused") {
    WorldDef world = box(100, 100, 0.1f);
    world.collisions = CollisionScheme::Simultaneous;  // the pairwise grid adds its own substeps
    world.gravity = float2{0, -30};
    world.maxTravel = 0.5f;
    // Gravity adds 30 x 0.1 = 3 to the speed over the step: ceil((10 + 3) x 0.1 / 0.5) = 3.
    const Run r = run(def, world, {disk(50, 50, 10, 0)}, 1);
    CHECK(r.contacts.substeps == 3);

    auto backend = makeBackend(def, world);
    backend->setParticles({disk(50, 50, 1e30f, 0)});
    CHECK_THROWS_WITH_AS(backend->step(1), doctest::Contains("substeps to keep each move within maxTravel"), Error);
}

CAROM_BACKEND_TEST_CASE("maxSpeed: the largest speed of the state, exactly") {
    std::vector<Particle> ps;
    for (int i = 0; i < 5000; ++i)
        ps.push_back(disk(1.0f + (i % 70) * 2.5f, 1.0f + (i / 70) * 2.5f, 0.0005f * i, -0.5f));
    ps[4321].velocity = float2{3, -4};
    auto backend = makeBackend(def, box(180, 180));
    backend->setParticles(ps);
    CHECK(backend->maxSpeed() == 5.0f);
}
