// The pairwise scheme (kernels/pairwise.h), once per backend and pipeline:
// exact two-body collisions at their contact times, energy conserved at any
// density and under gravity, bounded rounds on a resting pile, and the
// rounds' bookkeeping against a naive reference.
#include <algorithm>
#include <cmath>
#include <cstring>

#include <carom/types.h>

#include "backends/cpu.h"
#include "engine/diagnostics.h"
#include "kernels/pairwise.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

constexpr double kEps = 1e-5;

WorldDef pairwiseWorld(float width, float height, float dt = 0.01f, float2 gravity = {0, 0},
                       Boundary boundary = Boundary::Walls) {
    WorldDef world = box(width, height, dt);
    world.collisions = CollisionScheme::Pairwise;
    world.gravity = gravity;
    world.boundary = boundary;
    return world;
}

double speed(const Particle& p) { return std::hypot(p.velocity.x, p.velocity.y); }
double angleDegrees(const Particle& p) { return std::atan2(p.velocity.y, p.velocity.x) * 180.0 / kPi; }

// The pairwise step, as kernels/pairwise.h describes it, without the grid,
// the lists and their bookkeeping: in each round every disk searches all
// others, then the mutual pairs and the walls are resolved.
std::vector<Particle> naivePairwise(std::vector<Particle> disks, const WorldDef& world, std::uint64_t steps,
                                    ContactTotals& totals) {
    CaromStepParams step{};
    step.grid.cols = step.grid.rows = 1;  // every wall is within reach
    step.box = caromBoxOf(world);
    step.gravityX = world.gravity.x;
    step.gravityY = world.gravity.y;
    step.duration = world.dt;
    step.tolerance = carom_rounding_tolerance(step.box);
    const auto n = static_cast<unsigned int>(disks.size());
    std::vector<ContactTally> tallies(n);
    std::vector<CaromEvent> events(n);
    std::vector<unsigned int> ids(n);  // a disk's "sorted position" here is its id
    for (unsigned int i = 0; i < n; ++i) ids[i] = i;
    for (std::uint64_t s = 0; s < steps; ++s) {
        unsigned int rounds = 0;
        for (unsigned int round = 1; round <= kMaxPairwiseRounds; ++round) {
            for (unsigned int i = 0; i < n; ++i) {
                CaromEvent best = carom_wall_event(disks[i], 0, 0, step);
                for (unsigned int j = 0; j < n; ++j) {
                    if (j == i) continue;
                    const float t = carom_pair_event_time(disks[i], i, disks[j], j, step);
                    if (t == CAROM_NEVER) continue;
                    if (carom_pair_event_before(t, i, j, best, i, ids.data())) best = CaromEvent{t, j};
                }
                events[i] = best;
            }
            bool resolved = false;
            for (unsigned int i = 0; i < n; ++i) {
                const CaromEvent e = events[i];
                if (e.time == CAROM_NEVER) continue;
                if (e.partner >= CAROM_WALL) {
                    disks[i] = carom_bounce(disks[i], int(e.partner - CAROM_WALL), e.time, step, &tallies[i]);
                    resolved = true;
                } else if (events[e.partner].partner == i && i < e.partner) {
                    carom_collide_pair(&disks[i], i, &disks[e.partner], e.partner, e.time, step, &tallies[i]);
                    resolved = true;
                }
            }
            if (!resolved) break;
            rounds = round;
        }
        totals.maxRounds = std::max(totals.maxRounds, rounds);
        for (unsigned int i = 0; i < n; ++i) disks[i] = carom_finish_step(disks[i], step, &tallies[i]);
    }
    std::vector<Image> images(n);
    drainTallyArray(tallies.data(), n, totals, images.data());
    return disks;
}

}  // namespace

CAROM_BACKEND_TEST_CASE("pairwise: head-on collisions at dt = 0.01 happen at the contact time, exactly") {
    struct Case {
        float m1, m2, v1, v2, x2, expected1, expected2;
    };
    // Contact at t = 0.5, mid-step; after t = 1 the positions follow from the
    // exact velocities: a time-stepped impulse would be off by up to v dt.
    for (const Case c : {Case{1, 3, 2, 0, 13.0f, -1, 1}, Case{3, 1, 1, 0, 12.5f, 0.5f, 1.5f}}) {
        CAPTURE(c.m1);
        const std::vector<Particle> start = {disk(10, 10, c.v1, 0, c.m1), disk(c.x2, 10, c.v2, 0, c.m2)};
        const Run r = run(def, pairwiseWorld(40, 20), start, 100);
        const double contact = 10 + 0.5 * c.v1;  // disk 0's centre at the contact
        CHECK(r.particles[0].velocity.x == doctest::Approx(c.expected1).epsilon(kEps));
        CHECK(r.particles[1].velocity.x == doctest::Approx(c.expected2).epsilon(kEps));
        CHECK(r.particles[0].position.x == doctest::Approx(contact + 0.5 * c.expected1).epsilon(kEps));
        CHECK(r.particles[1].position.x == doctest::Approx(contact + 2 + 0.5 * c.expected2).epsilon(kEps));
        CHECK(r.contacts.collisions == 1);
        CHECK(r.contacts.lateContacts == 0);
    }
}

CAROM_BACKEND_TEST_CASE("pairwise: equal masses, impact parameter sigma/2, from apart at dt = 0.01") {
    // The target sits 1 below the line of flight: at contact the line of
    // centres points 30 degrees down, so the target leaves at 0.866 v at -30
    // degrees and the projectile at 0.5 v at +60.
    const std::vector<Particle> start = {disk(10, 10, 1, 0), disk(15, 9, 0, 0)};
    const Run r = run(def, pairwiseWorld(40, 20), start, 500);
    CHECK(speed(r.particles[1]) == doctest::Approx(std::sqrt(3.0) / 2).epsilon(kEps));
    CHECK(angleDegrees(r.particles[1]) == doctest::Approx(-30.0).epsilon(kEps));
    CHECK(speed(r.particles[0]) == doctest::Approx(0.5).epsilon(kEps));
    CHECK(angleDegrees(r.particles[0]) == doctest::Approx(60.0).epsilon(kEps));
    // Contact at x = 15 - sqrt(3), t = 5 - sqrt(3); the target then flies for sqrt(3).
    const double flight = std::sqrt(3.0);
    CHECK(r.particles[1].position.x == doctest::Approx(15 + 0.75 * flight).epsilon(kEps));
    CHECK(r.particles[1].position.y == doctest::Approx(9 - std::sqrt(3.0) / 4 * flight).epsilon(kEps));
}

CAROM_BACKEND_TEST_CASE("pairwise: a disk between walls bounces with period 2 (L - 2r) / |v|") {
    // L = 8, r = 1, v = 3: period 4 = 400 steps, back where it started
    // (to the rounding of 400 float steps of 0.03 each, about 1e-4).
    const Run r = run(def, pairwiseWorld(8, 4), {disk(2, 2, 3, 0)}, 400);
    CHECK(r.particles[0].velocity.x == 3.0f);
    CHECK(r.particles[0].position.x == doctest::Approx(2.0).epsilon(1e-4));
    // Half a period in, it has bounced off the right wall (at x = 7) and
    // is at x = 6, moving left.
    const Run half = run(def, pairwiseWorld(8, 4), {disk(2, 2, 3, 0)}, 200);
    CHECK(half.particles[0].velocity.x == -3.0f);
    CHECK(half.particles[0].position.x == doctest::Approx(6.0).epsilon(1e-4));
    CHECK(half.contacts.wallImpulse[1] == doctest::Approx(6.0));  // one bounce off the right wall: 2 m v
}

CAROM_BACKEND_TEST_CASE("pairwise: Newton's cradle at dt = 0.01: the striker stops and the last disk leaves") {
    std::vector<Particle> start = {disk(16, 5, 2, 0)};
    for (float x : {20.0f, 22.0f, 24.0f, 26.0f, 28.0f}) start.push_back(disk(x, 5, 0, 0));
    const Run r = run(def, pairwiseWorld(60, 10), start, 200);
    for (std::size_t i = 0; i + 1 < start.size(); ++i) CHECK(std::abs(r.particles[i].velocity.x) < kEps);
    CHECK(r.particles.back().velocity.x == doctest::Approx(2.0).epsilon(kEps));
    CHECK(r.contacts.collisions == 5);
}

CAROM_BACKEND_TEST_CASE(
    "pairwise: an overlapping, approaching pair is a late contact: impulse, pushed to contact, counted") {
    const Run r = run(def, pairwiseWorld(40, 20), {disk(10, 10, 1, 0), disk(11.5f, 10, -1, 0)}, 1);
    CHECK(r.contacts.lateContacts == 1);
    CHECK(r.contacts.collisions == 1);
    CHECK(r.particles[0].velocity.x == -1.0f);
    CHECK(r.particles[1].velocity.x == 1.0f);
    // Pushed to contact (2 apart), then flown apart for the whole step.
    CHECK(r.particles[1].position.x - r.particles[0].position.x == doctest::Approx(2.02).epsilon(kEps));
}

CAROM_BACKEND_TEST_CASE("pairwise: kinetic energy is conserved to rounding in a dense gas (packing 0.7)") {
    SceneDef scene;
    scene.particles = 2000;
    scene.packing = 0.7f;
    scene.seed = 3;
    const InitialState s = makeInitialState(scene);
    for (Boundary boundary : {Boundary::Walls, Boundary::Periodic}) {
        CAPTURE(std::string(boundaryName(boundary)));
        const WorldDef world = pairwiseWorld(s.width, s.height, 0.01f, {0, 0}, boundary);
        const Run r = run(def, world, s.particles, 300);
        const double before = measure(s.particles, world).kineticEnergy;
        const Diagnostics after = measure(r.particles, world);
        // The seed's simultaneous scheme gains several percent here.
        CHECK(std::abs(after.kineticEnergy - before) / before < 1e-6);
        CHECK(after.escaped == 0);
        CHECK(r.contacts.collisions > 2000);
        CHECK(r.contacts.lateContacts * 1000 < r.contacts.collisions);
    }
}

TEST_CASE("pairwise: momentum is conserved to rounding in a periodic box") {
    SceneDef scene;
    scene.particles = 1000;
    scene.packing = 0.5f;
    scene.radiusMin = 0.5f;
    scene.radiusMax = 1.0f;
    scene.massMin = 0.5f;
    scene.massMax = 3.0f;
    scene.seed = 4;
    const InitialState s = makeInitialState(scene);
    const WorldDef world = pairwiseWorld(s.width, s.height, 0.01f, {0, 0}, Boundary::Periodic);
    const Run r = run(testEngine(ComputeEngine::Cpu), world, s.particles, 500);
    const Diagnostics before = measure(s.particles, world), after = measure(r.particles, world);
    double scale = 0;  // sum of m |v|: the momentum a rounding error is relative to
    for (const Particle& p : s.particles) scale += p.mass * speed(p);
    CHECK(std::abs(after.momentum[0] - before.momentum[0]) / scale < 1e-6);
    CHECK(std::abs(after.momentum[1] - before.momentum[1]) / scale < 1e-6);
    CHECK(std::abs(after.kineticEnergy - before.kineticEnergy) / before.kineticEnergy < 1e-6);
}

CAROM_BACKEND_TEST_CASE("pairwise: kinetic plus potential energy is conserved as polydisperse disks fall into a pile") {
    SceneDef scene;
    scene.particles = 600;
    scene.packing = 0.4f;
    scene.radiusMin = 0.4f;
    scene.radiusMax = 1.0f;
    scene.massMin = 0.2f;
    scene.massMax = 5.0f;
    scene.seed = 8;
    const InitialState s = makeInitialState(scene);
    const WorldDef world = pairwiseWorld(s.width, s.height, 0.01f, {0.0f, -10.0f});
    const Run r = run(def, world, s.particles, 300);
    const Diagnostics before = measure(s.particles, world), after = measure(r.particles, world);
    CHECK(after.kineticEnergy > 10 * before.kineticEnergy);  // they fell
    CHECK(std::abs(after.totalEnergy() - before.totalEnergy()) / before.totalEnergy() < 1e-4);
    CHECK(after.escaped == 0);
    CHECK(r.contacts.maxRounds <= kMaxPairwiseRounds);
}

CAROM_BACKEND_TEST_CASE("pairwise: a stack resting on the floor under gravity stays put, with bounded rounds") {
    // Touching disks at rest, pressed down by gravity: no impact to resolve,
    // and no round may loop on the contacts.
    std::vector<Particle> start;
    for (int row = 0; row < 5; ++row)
        for (int column = 0; column < 8; ++column) start.push_back(disk(1.0f + 2.0f * column, 1.0f + 2.0f * row, 0, 0));
    const WorldDef world = pairwiseWorld(16, 40, 0.01f, {0.0f, -10.0f});
    const Run r = run(def, world, start, 100);
    const Diagnostics before = measure(start, world), after = measure(r.particles, world);
    CHECK(r.contacts.maxRounds <= kMaxPairwiseRounds);
    CHECK(after.escaped == 0);
    CHECK(std::abs(after.totalEnergy() - before.totalEnergy()) / before.totalEnergy() < 1e-4);
    for (std::size_t i = 0; i < start.size(); ++i) {
        CHECK(std::abs(r.particles[i].position.y - start[i].position.y) < 0.01f);
        CHECK(std::abs(r.particles[i].position.x - start[i].position.x) < 0.01f);
    }
}

TEST_CASE("pairwise: the backend's rounds equal a naive reference bit for bit") {
    // The reference searches every pair in every round: the grid, the lists,
    // the dirty marks and the forward first search must change nothing.
    SceneDef scene;
    scene.particles = 400;
    scene.packing = 0.5f;
    scene.radiusMin = 0.6f;
    scene.radiusMax = 1.0f;
    scene.massMin = 0.5f;
    scene.massMax = 2.0f;
    scene.speed = 2.0f;
    scene.seed = 9;
    const InitialState s = makeInitialState(scene);
    for (Boundary boundary : {Boundary::Walls, Boundary::Periodic}) {
        CAPTURE(std::string(boundaryName(boundary)));
        const float2 gravity = boundary == Boundary::Walls ? float2{0.0f, -1.0f} : float2{0.0f, 0.0f};
        const WorldDef world = pairwiseWorld(s.width, s.height, 0.01f, gravity, boundary);
        const Run r = run(testEngine(ComputeEngine::Cpu), world, s.particles, 200);
        REQUIRE(r.contacts.substeps == 200);  // the reference takes no substeps
        ContactTotals reference;
        const std::vector<Particle> expected = naivePairwise(s.particles, world, 200, reference);
        std::size_t differing = 0;
        for (std::size_t i = 0; i < expected.size(); ++i)
            if (std::memcmp(&expected[i], &r.particles[i], sizeof(Particle)) != 0) ++differing;
        CHECK(differing == 0);
        CHECK(r.contacts.collisions == reference.collisions);
        CHECK(r.contacts.lateContacts == reference.lateContacts);
        CHECK(r.contacts.maxRounds == reference.maxRounds);
        CHECK(r.contacts.virial == reference.virial);
        CHECK(reference.collisions > 1000);
    }
}

// The CPU backend's pairwise substeps search neighbour lists with a skin
// while they hold, and the grid's 3 x 3 cells otherwise: the earliest events
// are minima, so the trajectories, tallies and images must be the same bits,
// across many rebuilds of the lists, with walls, periodic edges, gravity,
// mixed radii and masses, and substeps.
TEST_CASE("pairwise: the CPU's neighbour lists give the bits of the grid search") {
    struct Case {
        const char* name;
        SceneDef scene;
        WorldDef rules;
        std::uint64_t steps;
    };
    WorldDef walls = pairwiseWorld(0, 0);
    WorldDef periodic = pairwiseWorld(0, 0, 0.01f, {0, 0}, Boundary::Periodic);
    WorldDef falling = pairwiseWorld(0, 0, 0.01f, {0.0f, -4.0f});
    WorldDef substeps = pairwiseWorld(0, 0, 0.2f);
    substeps.maxTravel = 0.1f;
    const Case cases[] = {
        // SceneDef: particles, packing, width, height, radii, masses, speed, seed.
        {"walls", SceneDef{3000, 0.5f, 0, 0, 1, 1, 1, 1, 1, 17}, walls, 400},
        {"periodic, mixed radii and masses", SceneDef{3000, 0.4f, 0, 0, 0.5f, 1.5f, 1, 4, 2, 17}, periodic, 400},
        {"gravity, dense", SceneDef{3000, 0.6f, 0, 0, 1, 1, 1, 1, 1, 17}, falling, 400},
        {"substeps", SceneDef{2000, 0.3f, 0, 0, 0.7f, 1, 1, 2, 1, 17}, substeps, 60},
    };
    for (const Case& c : cases) {
        CAPTURE(c.name);
        const InitialState s = makeInitialState(c.scene);
        WorldDef world = c.rules;
        world.width = s.width;
        world.height = s.height;
        CpuBackend listed(world), grid(world);
        grid.useNeighbourLists(false);
        std::vector<Particle> fromLists, fromGrid;
        for (CpuBackend* backend : {&listed, &grid}) {
            backend->setParticles(s.particles);
            backend->step(c.steps);
        }
        listed.readParticles(fromLists);
        grid.readParticles(fromGrid);
        CHECK(listed.neighbourListBuilds() > 2);  // rebuilt as the disks moved
        CHECK(grid.neighbourListBuilds() == 0);
        REQUIRE(fromLists.size() == fromGrid.size());
        CHECK(std::memcmp(fromLists.data(), fromGrid.data(), fromLists.size() * sizeof(Particle)) == 0);
        CHECK(listed.contacts().collisions == grid.contacts().collisions);
        CHECK(listed.contacts().collisions > fromLists.size());
        CHECK(listed.contacts().virial == grid.contacts().virial);
        CHECK(listed.contacts().wallImpulse == grid.contacts().wallImpulse);
        CHECK(listed.contacts().substeps == grid.contacts().substeps);
        CHECK(listed.contacts().lateContacts == grid.contacts().lateContacts);
        CHECK(listed.contacts().maxRounds == grid.contacts().maxRounds);
        CHECK(listed.images() == grid.images());
    }
}

// WorldDef::skin sets how far the lists reach: a larger skin builds them
// less often; one that a substep's travel alone would close leaves every
// substep to the grid. The bits are the grid's whatever the skin.
TEST_CASE("pairwise: the CPU's neighbour lists give the grid's bits with any skin") {
    const InitialState s = makeInitialState(SceneDef{3000, 0.4f, 0, 0, 0.5f, 1.0f, 1, 2, 2, 23});
    WorldDef world = pairwiseWorld(s.width, s.height, 0.01f, {0, 0}, Boundary::Periodic);
    CpuBackend grid(world);
    grid.useNeighbourLists(false);
    grid.setParticles(s.particles);
    grid.step(300);
    std::vector<Particle> expected;
    grid.readParticles(expected);
    std::uint64_t builds[4] = {};
    const float skins[4] = {0.01f, 0.3f, 1.5f, 7.5f};  // radii just under 1: about 8 is the largest allowed
    for (int i = 0; i < 4; ++i) {
        CAPTURE(skins[i]);
        world.skin = skins[i];
        CpuBackend listed(world);
        listed.setParticles(s.particles);
        listed.step(300);
        std::vector<Particle> got;
        listed.readParticles(got);
        REQUIRE(got.size() == expected.size());
        CHECK(std::memcmp(got.data(), expected.data(), got.size() * sizeof(Particle)) == 0);
        CHECK(listed.contacts().collisions == grid.contacts().collisions);
        builds[i] = listed.neighbourListBuilds();
    }
    CHECK(builds[0] == 0);  // 0.01 is less than two substeps' travel: the grid every substep
    CHECK(builds[1] > builds[2]);
    CHECK(builds[2] > builds[3]);
    CHECK(builds[3] > 0);
}
