// The event-driven scheme (--collisions events): exact hard-disk dynamics,
// checked against what can be worked out by hand to 1e-12 relative (the
// issue's bar): two-body collisions, wall periods, a parabola under
// gravity, a sequence of three disks; energy and momentum over 10^6
// collisions; round-off in a dense packing and a resting pile; periodic
// images; checkpoints bit for bit; the refusals.
//
// "Relative" means relative to the scale of the quantity: positions to the
// box side, velocities to the initial speed, energies to the energy.
// Particles are float: the analytic expectations start from the same float
// values converted to double, and use the engine's time() for the time.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "backends/event_driven.h"
#include "engine/event_state.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

constexpr double kExact = 1e-12;

std::string digits(double value) {
    std::ostringstream text;
    text << std::setprecision(17) << value;
    return text.str();
}

}  // namespace

// Passes when `got` lies within kExact x `scale` of `expected`; says both otherwise.
#define CHECK_EXACT(got, expected, scale)                                       \
    do {                                                                        \
        const double got_ = (got), expected_ = (expected);                      \
        INFO(#got " = " << digits(got_) << ", expected " << digits(expected_)); \
        CHECK(std::abs(got_ - expected_) <= kExact * (scale));                  \
    } while (0)

namespace {

WorldDef eventWorld(float width, float height, float dt, Boundary boundary = Boundary::Walls,
                    float2 gravity = float2{0, 0}) {
    WorldDef world = box(width, height, dt);
    world.boundary = boundary;
    world.gravity = gravity;
    world.collisions = CollisionScheme::Events;
    return world;
}

std::unique_ptr<EventDrivenBackend> startEvents(const WorldDef& world, const std::vector<Particle>& particles) {
    auto backend = std::make_unique<EventDrivenBackend>(world);
    backend->setParticles(particles);
    return backend;
}

// a - b, wrapped to the nearest image in a periodic box of side `side`.
double nearestImage(double a, double b, double side) {
    const double d = a - b;
    return d - side * std::round(d / side);
}

// Where a point starting at `start` with speed `v` along one axis is after
// `t`, bouncing between lo and hi; and how many bounces it made by then.
double reflected(double start, double v, double t, double lo, double hi) {
    const double width = hi - lo;
    double u = std::fmod(start + v * t - lo, 2 * width);
    if (u < 0) u += 2 * width;
    return u <= width ? lo + u : lo + 2 * width - u;
}
std::uint64_t bouncesBy(double start, double v, double t, double lo, double hi) {
    const double width = hi - lo;
    const double unfolded = (v > 0 ? start - lo : hi - start) + std::abs(v) * t;  // distance from the far wall
    return static_cast<std::uint64_t>(std::floor(unfolded / width));
}

// Splitmix64: the same numbers on every platform. Not carom::Random
// (carom/world.h, a Mersenne Twister): the dense packing below was drawn
// from this stream, and stays as it was.
struct SplitMix64 {
    std::uint64_t state;
    double uniform() {  // in [0, 1)
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    }
};

struct Totals {
    double kinetic = 0, px = 0, py = 0, momentumScale = 0;  // momentumScale = sum m |v|
};
Totals totalsOf(const std::vector<ExactDisk>& disks) {
    Totals t;
    for (const ExactDisk& d : disks) {
        t.kinetic += 0.5 * d.mass * (d.vx * d.vx + d.vy * d.vy);
        t.px += d.mass * d.vx;
        t.py += d.mass * d.vy;
        t.momentumScale += d.mass * std::hypot(d.vx, d.vy);
    }
    return t;
}
std::vector<ExactDisk> exactOf(const std::vector<Particle>& particles) {
    std::vector<ExactDisk> disks;
    for (const Particle& p : particles)
        disks.push_back(ExactDisk{p.position.x, p.position.y, p.velocity.x, p.velocity.y, p.mass, p.radius});
    return disks;
}

// The deepest overlap of any pair, relative to its contact distance (O(N^2)).
double deepestOverlap(const std::vector<ExactDisk>& disks, const WorldDef& world) {
    double deepest = -HUGE_VAL;
    for (std::size_t i = 0; i < disks.size(); ++i)
        for (std::size_t j = i + 1; j < disks.size(); ++j) {
            double dx = disks[i].x - disks[j].x, dy = disks[i].y - disks[j].y;
            if (world.boundary == Boundary::Periodic) {
                dx = nearestImage(disks[i].x, disks[j].x, world.width);
                dy = nearestImage(disks[i].y, disks[j].y, world.height);
            }
            const double sigma = disks[i].radius + disks[j].radius;
            deepest = std::max(deepest, 1.0 - std::hypot(dx, dy) / sigma);
        }
    return deepest;
}

// N disks of radii in [0.5, 1] and masses in [0.5, 2], unit speeds.
InitialState polydisperse(std::uint32_t particles, float packing) {
    SceneDef scene;
    scene.particles = particles;
    scene.packing = packing;
    scene.radiusMin = 0.5f;
    scene.massMin = 0.5f;
    scene.massMax = 2.0f;
    return makeInitialState(scene);
}

}  // namespace

TEST_CASE("events: head-on collisions with unequal masses are exact") {
    // Centres 10 apart, sigma = 2, closing speed v1: the contact quadratic
    // (10 - v1 t)^2 = 4 has the roots 8 / v1 and 12 / v1; the first is the
    // collision. Then u1 = (m1 - m2) / (m1 + m2) v1, u2 = 2 m1 / (m1 + m2) v1.
    struct Case {
        float m1, m2, v1, u1, u2;
    };
    for (const Case c : {Case{1, 3, 2, -1, 1}, Case{3, 1, 1, 0.5f, 1.5f}}) {
        CAPTURE(c.m1);
        auto events = startEvents(eventWorld(40, 20, 0.25f), {disk(10, 10, c.v1, 0, c.m1), disk(20, 10, 0, 0, c.m2)});
        const double contact = 8.0 / c.v1;
        events->step(static_cast<std::uint64_t>(contact / 0.25) - 1);  // just before
        CHECK(events->eventCounts().collisions == 0);
        CHECK_EXACT(events->exactState()[0].x, 10 + c.v1 * events->time(), 40);
        events->step(5);  // 1 after the contact: between the two roots
        const double t = events->time();
        CHECK(t == contact + 1);
        const std::vector<ExactDisk> after = events->exactState();
        CHECK_EXACT(after[0].vx, c.u1, c.v1);
        CHECK_EXACT(after[1].vx, c.u2, c.v1);
        CHECK(after[0].vy == 0.0);
        CHECK(after[1].vy == 0.0);
        CHECK_EXACT(after[0].x, 18 + c.u1 * (t - contact), 40);
        CHECK_EXACT(after[1].x, 20 + c.u2 * (t - contact), 40);
        CHECK(after[0].y == 10.0);
        CHECK(events->eventCounts().collisions == 1);
        const ContactTotals& contacts = events->contacts();
        CHECK(contacts.collisions == 1);
        // sigma J, J = 2 mu v1.
        CHECK_EXACT(contacts.virial, 2 * 2 * (c.m1 * c.m2 / (c.m1 + c.m2)) * c.v1, c.m1 * c.v1);
    }
}

TEST_CASE("events: oblique collisions at impact parameter sigma/2 are exact, with equal and unequal radii") {
    // A projectile at (10, 11) flies at (2, 0) towards a target at rest at
    // (20, 10); sigma = r1 + r2 = 2, so the impact parameter 1 is sigma/2.
    // Contact: (-10 + 2 t)^2 + 1 = 4, first root t = 5 - sqrt(3)/2; the
    // centre line is then n = (sqrt 3, -1)/2 and the normal speed v.n = sqrt 3.
    // The target gets 2 m1 / (m1 + m2) sqrt(3) n, the projectile loses
    // 2 m2 / (m1 + m2) sqrt(3) n:
    //   equal masses: target (1.5, -sqrt3/2) = 0.866 v at -30 degrees,
    //                 projectile (0.5, sqrt3/2) = 0.5 v at +60 degrees;
    //   m1 = 1, m2 = 3 (radii 0.5 and 1.5): target (0.75, -sqrt3/4),
    //                 projectile (-0.25, 3 sqrt3/4).
    const double s3 = std::sqrt(3.0);
    struct Case {
        float m1, m2, r1, r2;
        double u1x, u1y, u2x, u2y;
    };
    for (const Case c :
         {Case{1, 1, 1, 1, 0.5, s3 / 2, 1.5, -s3 / 2}, Case{1, 3, 0.5f, 1.5f, -0.25, 3 * s3 / 4, 0.75, -s3 / 4}}) {
        CAPTURE(c.m2);
        CAPTURE(c.r1);
        auto events =
            startEvents(eventWorld(40, 30, 0.25f), {disk(10, 11, 2, 0, c.m1, c.r1), disk(20, 10, 0, 0, c.m2, c.r2)});
        const double contact = 5 - s3 / 2;
        events->step(16);  // t = 4, before the contact
        CHECK(events->eventCounts().collisions == 0);
        events->step(8);  // t = 6, after it
        const double t = events->time();
        const std::vector<ExactDisk> after = events->exactState();
        CHECK_EXACT(after[0].vx, c.u1x, 2);
        CHECK_EXACT(after[0].vy, c.u1y, 2);
        CHECK_EXACT(after[1].vx, c.u2x, 2);
        CHECK_EXACT(after[1].vy, c.u2y, 2);
        CHECK_EXACT(after[0].x, 10 + 2 * contact + c.u1x * (t - contact), 40);
        CHECK_EXACT(after[0].y, 11 + c.u1y * (t - contact), 40);
        CHECK_EXACT(after[1].x, 20 + c.u2x * (t - contact), 40);
        CHECK_EXACT(after[1].y, 10 + c.u2y * (t - contact), 40);
        if (c.m1 == c.m2) {
            CHECK_EXACT(std::hypot(after[1].vx, after[1].vy), s3 / 2 * 2, 2);
            CHECK_EXACT(std::atan2(after[1].vy, after[1].vx), -kPi / 6, 1);
            CHECK_EXACT(std::hypot(after[0].vx, after[0].vy), 0.5 * 2, 2);
            CHECK_EXACT(std::atan2(after[0].vy, after[0].vx), kPi / 3, 1);
        }
        CHECK(events->contacts().collisions == 1);
        // sigma J, J = 2 mu sqrt 3.
        CHECK_EXACT(events->contacts().virial, 2 * 2 * (c.m1 * c.m2 / (c.m1 + c.m2)) * s3, 2 * c.m1);
    }
}

TEST_CASE("events: a disk between walls bounces with period 2 (L - 2r) / |v|") {
    // Box 10 x 10, r = 1: the centre moves in [1, 9], 8 wide; vx = 2 gives
    // the period 8, vy = 0.5 the period 32, so at t = 32 the disk is back
    // where it started, after 8 side bounces, one on the ceiling (t = 7.4)
    // and one on the floor (t = 23.4).
    // Each bounce gives its wall 2 m |v_n|.
    const float m = 2;
    const Particle start = disk(5.1f, 5.3f, 2, 0.5f, m);
    const double x0 = start.position.x, y0 = start.position.y;
    auto events = startEvents(eventWorld(10, 10, 0.25f), {start});
    for (int sample = 1; sample <= 128; ++sample) {
        events->step(1);
        const double t = events->time();
        CAPTURE(t);
        const ExactDisk d = events->exactState()[0];
        CHECK_EXACT(d.x, reflected(x0, 2, t, 1, 9), 10);
        CHECK_EXACT(d.y, reflected(y0, 0.5, t, 1, 9), 10);
        CHECK(std::abs(d.vx) == 2.0);
        CHECK(std::abs(d.vy) == 0.5);
        CHECK(events->eventCounts().wallBounces == bouncesBy(x0, 2, t, 1, 9) + bouncesBy(y0, 0.5, t, 1, 9));
    }
    CHECK(events->time() == 32);
    const ExactDisk end = events->exactState()[0];
    CHECK_EXACT(end.x, x0, 10);
    CHECK_EXACT(end.y, y0, 10);
    CHECK(end.vx == 2.0);
    CHECK(end.vy == 0.5);
    CHECK(events->eventCounts().wallBounces == 10);
    CHECK(events->eventCounts().collisions == 0);
    // Left, right, bottom, top: 4, 4, 1 and 1 bounces.
    const ContactTotals& contacts = events->contacts();
    CHECK_EXACT(contacts.wallImpulse[0], 4 * 2 * m * 2, 4 * 2 * m * 2);
    CHECK_EXACT(contacts.wallImpulse[1], 4 * 2 * m * 2, 4 * 2 * m * 2);
    CHECK_EXACT(contacts.wallImpulse[2], 2 * m * 0.5, 2 * m * 0.5);
    CHECK_EXACT(contacts.wallImpulse[3], 2 * m * 0.5, 2 * m * 0.5);
    CHECK(contacts.collisions == 0);

    // The float projection is the exact state rounded.
    std::vector<Particle> read;
    events->readParticles(read);
    CHECK(read[0].position.x == static_cast<float>(end.x));
    CHECK(read[0].position.y == static_cast<float>(end.y));
}

TEST_CASE("events: a disk bouncing on the floor follows the parabola and returns to its height every 2 v / g") {
    // g = (0, -2), r = 1: launched from the floor (y = 1) at vy = 4, the disk
    // flies y = 1 + 4 s - s^2 (s = time since the last bounce), tops out at
    // y = 5 at s = 2 and lands again at s = 4 = 2 v / g with vy = -4, which
    // the floor turns back to +4: period 4. Sideways vx = 0.5 between walls
    // at x = 1 and 9 (box 10 x 10): a side bounce at t = 7.8, 23.8, ...
    // The total energy 1/2 m v^2 + m |g| y = 8.125 + 2 stays.
    const Particle start = disk(5.1f, 1, 0.5f, 4);
    const double x0 = start.position.x;
    auto events = startEvents(eventWorld(10, 10, 0.25f, Boundary::Walls, float2{0, -2}), {start});
    const double energy = *events->exactTotalEnergy();
    CHECK_EXACT(energy, 0.5 * (0.25 + 16) + 2, 10);
    for (int sample = 1; sample <= 160; ++sample) {  // 10 periods
        events->step(1);
        const double t = events->time();
        CAPTURE(t);
        const double s = std::fmod(t, 4.0);
        const ExactDisk d = events->exactState()[0];
        CHECK_EXACT(d.y, 1 + 4 * s - s * s, 10);
        CHECK_EXACT(d.x, reflected(x0, 0.5, t, 1, 9), 10);
        CHECK_EXACT(*events->exactTotalEnergy(), energy, energy);
        if (s != 0) {  // not at a bounce: the velocity and the count are unambiguous
            CHECK_EXACT(d.vy, 4 - 2 * s, 4);
            CHECK(events->eventCounts().wallBounces == static_cast<std::uint64_t>(t / 4) + bouncesBy(x0, 0.5, t, 1, 9));
        }
        if (s == 2) CHECK_EXACT(d.y, 5, 10);  // the same height every period
    }
    // 10 floor bounces (t = 4 ... 40, the last at the last sample).
    CHECK_EXACT(events->contacts().wallImpulse[2], 10 * 2 * 4.0, 10 * 2 * 4.0);
    CHECK(events->contacts().wallImpulse[3] == 0.0);
}

TEST_CASE("events: three disks on a line collide in the order and at the times worked out by hand") {
    // Radii 1 (sigma 2), on y = 10 in a 40 x 20 box, so only x changes.
    //   A: x = 5, v = 2, m = 1;  B: x = 10, v = 0, m = 1;  C: x = 14, v = 0, m = 2.
    // 1. A-B: gap 10 - 5 - 2 = 3 closed at 2: t = 1.5. Equal masses swap:
    //    A stops at 8, B leaves 10 at 2.
    // 2. B-C: gap 14 - 10 - 2 = 2 closed at 2: t = 2.5, B at 12. m 1 on m 2:
    //    B gets (1 - 2)/3 2 = -2/3, C gets 2 1/3 2 = 4/3.
    // 3. B-A: gap 12 - 8 - 2 = 2 closed at 2/3: t = 5.5, B at 10. Equal masses
    //    swap: A leaves 8 at -2/3, B stops.
    // Then A runs left, C right, B rests: no more collisions (the walls are
    // reached at t = 16 and 21.25, after the last sample at 12).
    // Momentum 2 and energy 2 before and after: -2/3 + 2 4/3 = 2, 2/9 + 16/9 = 2.
    auto events =
        startEvents(eventWorld(40, 20, 0.25f), {disk(5, 10, 2, 0, 1), disk(10, 10, 0, 0, 1), disk(14, 10, 0, 0, 2)});
    struct Sample {
        int steps;  // t = steps / 4
        std::uint64_t collisions;
        double a, va, b, vb, c, vc;  // positions and velocities at t
    };
    const double third = 1.0 / 3.0;
    for (const Sample s :
         {Sample{4, 0, 7, 2, 10, 0, 14, 0},                                                           // t = 1
          Sample{8, 1, 8, 0, 11, 2, 14, 0},                                                           // t = 2
          Sample{16, 2, 8, 0, 12 - 1.5 * 2 * third, -2 * third, 14 + 1.5 * 4 * third, 4 * third},     // t = 4
          Sample{32, 3, 8 - 2.5 * 2 * third, -2 * third, 10, 0, 14 + 5.5 * 4 * third, 4 * third},     // t = 8
          Sample{48, 3, 8 - 6.5 * 2 * third, -2 * third, 10, 0, 14 + 9.5 * 4 * third, 4 * third}}) {  // t = 12
        events->step(static_cast<std::uint64_t>(s.steps) - events->contacts().steps);
        CAPTURE(events->time());
        CHECK(events->time() == s.steps / 4.0);
        CHECK(events->eventCounts().collisions == s.collisions);
        CHECK(events->eventCounts().wallBounces == 0);
        const std::vector<ExactDisk> d = events->exactState();
        CHECK_EXACT(d[0].x, s.a, 40);
        CHECK_EXACT(d[1].x, s.b, 40);
        CHECK_EXACT(d[2].x, s.c, 40);
        CHECK_EXACT(d[0].vx, s.va, 2);
        CHECK_EXACT(d[1].vx, s.vb, 2);
        CHECK_EXACT(d[2].vx, s.vc, 2);
        for (const ExactDisk& disk : d) CHECK(disk.vy == 0.0);
    }
    CHECK_EXACT(events->kineticEnergy(), 2, 2);
}

TEST_CASE("events: Newton's cradle passes the velocity down a touching row") {
    // A (x = 5, v = 2) hits B at t = 1.5; B touches C (x = 10 and 12, exactly
    // sigma apart), so B's new velocity makes B-C a collision at once: all
    // equal masses, so A and B stop and C leaves at 2, two collisions in all.
    auto events = startEvents(eventWorld(40, 20, 0.25f), {disk(5, 10, 2, 0), disk(10, 10, 0, 0), disk(12, 10, 0, 0)});
    events->step(16);  // t = 4
    const std::vector<ExactDisk> d = events->exactState();
    CHECK(events->eventCounts().collisions == 2);
    CHECK_EXACT(d[0].x, 8, 40);
    CHECK_EXACT(d[1].x, 10, 40);
    CHECK_EXACT(d[2].x, 12 + 2 * 2.5, 40);
    CHECK_EXACT(d[0].vx, 0, 2);
    CHECK_EXACT(d[1].vx, 0, 2);
    CHECK_EXACT(d[2].vx, 2, 2);
}

TEST_CASE("events: energy and momentum are conserved to 1e-12 over 10^6 collisions, polydisperse and periodic") {
    const InitialState s = polydisperse(2000, 0.5f);
    auto events = startEvents(eventWorld(s.width, s.height, 0.1f, Boundary::Periodic), s.particles);
    const Totals before = totalsOf(exactOf(s.particles));
    // About 3 300 collisions per unit time: run in slices of 1 until 10^6 (some 300).
    for (int slice = 0; slice < 1000 && events->eventCounts().collisions < 1'000'000; ++slice) events->step(10);
    REQUIRE(events->eventCounts().collisions >= 1'000'000);
    const Totals after = totalsOf(events->exactState());
    CHECK_EXACT(after.kinetic, before.kinetic, before.kinetic);
    CHECK_EXACT(events->kineticEnergy(), before.kinetic, before.kinetic);
    CHECK_EXACT(after.px, before.px, before.momentumScale);
    CHECK_EXACT(after.py, before.py, before.momentumScale);
    CHECK(events->contacts().collisions == events->eventCounts().collisions);
    CHECK(deepestOverlap(events->exactState(), events->world()) <= 1e-9);
}

TEST_CASE("events: the total energy is conserved to 1e-12 with walls and gravity") {
    const InitialState s = polydisperse(1000, 0.3f);
    auto events = startEvents(eventWorld(s.width, s.height, 0.1f, Boundary::Walls, float2{0.25f, -1}), s.particles);
    const double energy = *events->exactTotalEnergy();
    // Kinetic minus sum m g.x, worked out here from the particles.
    double expected = 0;
    for (const Particle& p : s.particles)
        expected += 0.5 * p.mass * (double(p.velocity.x) * p.velocity.x + double(p.velocity.y) * p.velocity.y) -
                    p.mass * (0.25 * p.position.x - 1.0 * p.position.y);
    CHECK_EXACT(energy, expected, std::abs(expected));
    events->step(300);  // the gas falls and piles up on the floor
    CHECK(events->eventCounts().collisions > 100'000);
    CHECK(events->eventCounts().wallBounces > 1000);
    CHECK_EXACT(*events->exactTotalEnergy(), energy, std::abs(energy));
}

TEST_CASE("events: a dense packing (eta = 0.72) runs without stalling and keeps energy and contacts") {
    // A triangular lattice of spacing a, rows a sqrt(3)/2 apart, with
    // eta = pi r^2 / (a^2 sqrt(3)/2) = 0.72; each disk jittered by up to 0.04
    // (the gaps are a - 2 = 0.245), unit speeds in random directions.
    const int columns = 20, rows = 24;
    const double a = std::sqrt(2 * kPi / (std::sqrt(3.0) * 0.72));
    const double rowHeight = a * std::sqrt(3.0) / 2;
    const float width = static_cast<float>(columns * a), height = static_cast<float>(rows * rowHeight);
    SplitMix64 random{12};
    std::vector<Particle> lattice;
    for (int row = 0; row < rows; ++row)
        for (int column = 0; column < columns; ++column) {
            const double angle = 2 * kPi * random.uniform();
            const double x = (column + 0.25 + 0.5 * (row % 2)) * a + 0.08 * (random.uniform() - 0.5);
            const double y = (row + 0.5) * rowHeight + 0.08 * (random.uniform() - 0.5);
            lattice.push_back(disk(static_cast<float>(x), static_cast<float>(y), static_cast<float>(std::cos(angle)),
                                   static_cast<float>(std::sin(angle))));
        }
    const WorldDef world = eventWorld(width, height, 0.1f, Boundary::Periodic);
    const double n = double(lattice.size());
    CHECK(n * kPi / (double(width) * height) == doctest::Approx(0.72).epsilon(1e-6));
    REQUIRE(deepestOverlap(exactOf(lattice), world) < 0);

    auto events = startEvents(world, lattice);
    const double energy = events->kineticEnergy();
    events->step(200);
    CHECK(events->time() == doctest::Approx(20.0).epsilon(1e-6));
    // The collision-rate identity gives 2 (Z - 1) sqrt(kT / (pi m)) / sigma
    // collisions per disk and unit time: 3.6 at Z = 10, about the pressure of
    // the hard-disk solid at this density (kT = 1/2). A loop of zero-time
    // collisions would exceed 5 times that by far.
    const double rate = double(events->eventCounts().collisions) / (n * events->time());
    CAPTURE(rate);
    CHECK(rate > 1.0);
    CHECK(rate < 20.0);
    CHECK(events->eventCounts().overlapping <= events->eventCounts().collisions / 100);
    CHECK_EXACT(events->kineticEnergy(), energy, energy);
    CHECK(deepestOverlap(events->exactState(), world) <= 1e-9);
}

TEST_CASE("events: a resting pile under gravity runs without stalling, inside the walls, energy conserved") {
    // 6 columns of 3 disks of radius 1, each touching its neighbours, the
    // floor and (the outer columns) the side walls, at rest, g = (0, -1).
    // Exact hard disks would stay put; the scheme lets them sink by its
    // resting depth (1e-12 of the longer box side) and bounce back, never
    // through a wall. Each disk takes some 10^5 events per unit time doing so.
    std::vector<Particle> pile;
    for (int row = 0; row < 3; ++row)
        for (int column = 0; column < 6; ++column) pile.push_back(disk(1 + 2 * column, 1 + 2 * row, 0, 0));
    const WorldDef world = eventWorld(12, 16, 0.01f, Boundary::Walls, float2{0, -1});
    auto events = startEvents(world, pile);
    const double energy = *events->exactTotalEnergy();
    events->step(50);
    CHECK(events->time() == doctest::Approx(0.5).epsilon(1e-6));
    CHECK_EXACT(*events->exactTotalEnergy(), energy, std::abs(energy));
    const std::vector<ExactDisk> end = events->exactState();
    // Ten resting depths: the floor of a pile sinks by about one.
    const double tolerance = 1e-11 * world.height;
    for (std::size_t i = 0; i < end.size(); ++i) {
        CAPTURE(i);
        CHECK(end[i].x >= 1 - tolerance);
        CHECK(end[i].x <= 11 + tolerance);
        CHECK(end[i].y >= 1 - tolerance);
        // Still a pile: no disk went anywhere.
        CHECK(std::abs(end[i].x - pile[i].position.x) <= 1e-9);
        CHECK(std::abs(end[i].y - pile[i].position.y) <= 1e-9);
    }
    CHECK(deepestOverlap(end, world) <= 1e-9);
}

TEST_CASE("events: periodic boxes collide across the edge with the nearest image") {
    // Box 20 x 20: A at x = 1 moving left at 1, B at rest at x = 18.5, whose
    // image at -1.5 is 2.5 from A: they touch at t = 0.5, A stops at 0.5 and
    // B leaves at -1 (equal masses). At t = 2, B is at 17.
    auto events =
        startEvents(eventWorld(20, 20, 0.25f, Boundary::Periodic), {disk(1, 10, -1, 0), disk(18.5f, 10, 0, 0)});
    events->step(8);
    CHECK(events->eventCounts().collisions == 1);
    const std::vector<ExactDisk> d = events->exactState();
    CHECK_EXACT(nearestImage(d[0].x, 0.5, 20), 0, 20);
    CHECK_EXACT(nearestImage(d[1].x, 17, 20), 0, 20);
    CHECK_EXACT(d[0].vx, 0, 1);
    CHECK_EXACT(d[1].vx, -1, 1);
    std::vector<Particle> read;
    events->readParticles(read);
    CHECK(read[0].position.x == 0.5f);
    CHECK(read[1].position.x == 17.0f);
}

TEST_CASE("events: a disk crossing the periodic boundary many times stays on its analytic line") {
    const Particle start = disk(3.3f, 7.9f, 3.7f, -1.3f, 1, 0.6f);
    auto events = startEvents(eventWorld(10, 8, 0.5f, Boundary::Periodic), {start});
    for (int sample = 0; sample < 20; ++sample) {
        events->step(10);  // 5 time units: 37 box widths and 16 heights in all
        const double t = events->time();
        CAPTURE(t);
        const ExactDisk d = events->exactState()[0];
        CHECK_EXACT(nearestImage(d.x, start.position.x + double(start.velocity.x) * t, 10), 0, 10);
        CHECK_EXACT(nearestImage(d.y, start.position.y + double(start.velocity.y) * t, 8), 0, 8);
        CHECK(d.vx == double(start.velocity.x));
        CHECK(d.vy == double(start.velocity.y));
        std::vector<Particle> read;
        events->readParticles(read);
        CHECK(read[0].position.x >= 0.0f);
        CHECK(read[0].position.x < 10.0f);
        CHECK(read[0].position.y >= 0.0f);
        CHECK(read[0].position.y < 8.0f);
        // The images unwrap the positions read onto the line.
        const Image image = events->images()[0];
        CHECK(std::abs(read[0].position.x + 10.0 * image[0] - (start.position.x + double(start.velocity.x) * t)) <
              1e-4);
        CHECK(std::abs(read[0].position.y + 8.0 * image[1] - (start.position.y + double(start.velocity.y) * t)) < 1e-4);
    }
    CHECK(events->images()[0] == Image{37, -16});
    CHECK(events->eventCounts().cellCrossings > 20);
    CHECK(events->eventCounts().wallBounces == 0);
}

TEST_CASE("events: a checkpoint resumes bit for bit") {
    const InitialState s = polydisperse(600, 0.4f);
    for (const WorldDef& world : {eventWorld(s.width, s.height, 0.05f, Boundary::Walls, float2{0.1f, -0.5f}),
                                  eventWorld(s.width, s.height, 0.05f, Boundary::Periodic)}) {
        const std::string boundary = boundaryName(world.boundary);
        CAPTURE(boundary);
        const std::uint64_t half = 100;
        auto straight = startEvents(world, s.particles);
        straight->step(2 * half);

        auto first = startEvents(world, s.particles);
        first->step(half);
        const EventEngineState saved = *first->saveState();
        std::vector<Particle> particles;
        first->readParticles(particles);
        EventDrivenBackend resumed(world);
        resumed.setParticles(particles, half, first->images());
        resumed.restoreState(saved);
        CHECK(resumed.time() == first->time());
        CHECK(resumed.images() == first->images());
        resumed.step(half);
        CHECK(resumed.images() == straight->images());

        const std::vector<ExactDisk> a = straight->exactState(), b = resumed.exactState();
        REQUIRE(a.size() == b.size());
        CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(ExactDisk)) == 0);
        CHECK(straight->time() == resumed.time());
        CHECK(straight->eventCounts().collisions == first->eventCounts().collisions + resumed.eventCounts().collisions);
        CHECK(straight->eventCounts().collisions > 1000);
        const EventEngineState endA = *straight->saveState(), endB = *resumed.saveState();
        CHECK(endA.time == endB.time);
        REQUIRE(endA.disks.size() == endB.disks.size());
        CHECK(std::memcmp(endA.disks.data(), endB.disks.data(), endA.disks.size() * sizeof(EventDiskState)) == 0);
    }
}

TEST_CASE("events: a state restored at another step than its own continues from its time") {
    const InitialState s = polydisperse(300, 0.4f);
    const WorldDef world = eventWorld(s.width, s.height, 0.05f, Boundary::Periodic);
    auto first = startEvents(world, s.particles);
    first->step(100);
    std::vector<Particle> particles;
    first->readParticles(particles);
    EventDrivenBackend restored(world);
    restored.setParticles(particles);  // step 0, while the state is at step 100
    restored.restoreState(*first->saveState());
    const std::uint64_t collisions = first->eventCounts().collisions;
    restored.step(100);
    first->step(100);
    CHECK(restored.time() == doctest::Approx(first->time()).epsilon(1e-12));
    CHECK(restored.eventCounts().collisions == first->eventCounts().collisions - collisions);
    CHECK(restored.eventCounts().collisions > 100);
}

TEST_CASE("events: a periodic box 3 cells wide collides with the image the cells say, directly or across the edge") {
    // 3.5 x 3.5, radius 0.5: 3 cells a side, so a disk two cells away along
    // the row is also one cell away across the edge.
    const WorldDef world = eventWorld(3.5f, 3.5f, 0.125f, Boundary::Periodic);
    struct Case {
        float xa, va, xb, vb;  // head-on along y = 1.75, radius 0.5, |v| = 1
        int steps;             // of 0.125, after the contact and before the next one
        bool acrossEdge;
    };
    // Directly: xb - xa = 2.25 apart, contact at (2.25 - 1) / 2 = 0.625, the
    // next across the edge at 1.375; checked at t = 1.
    // Across the edge: xa + 3.5 - xb = 1.4 apart, contact at 0.2, the next
    // directly at 0.95; checked at t = 0.5.
    for (const Case c : {Case{0.05f, 1, 2.3f, -1, 8, false}, Case{0.1f, -1, 2.2f, 1, 4, true}}) {
        CAPTURE(c.xa);
        const double separation = c.acrossEdge ? double(c.xa) + 3.5 - c.xb : double(c.xb) - c.xa;
        const double contact = (separation - 1) / 2, t = c.steps * 0.125;
        // Each runs to the contact and back: x + v (2 contact - t) ... as seen from its start.
        double xa1 = c.xa + c.va * (2 * contact - t), xb1 = c.xb + c.vb * (2 * contact - t);
        if (xa1 < 0) xa1 += 3.5;
        auto events =
            startEvents(world, {disk(c.xa, 1.75f, c.va, 0, 1.0f, 0.5f), disk(c.xb, 1.75f, c.vb, 0, 1.0f, 0.5f)});
        REQUIRE(events->columns() == 3);
        events->step(c.steps);
        CHECK(events->eventCounts().collisions == 1);
        CHECK(events->eventCounts().overlapping == 0);
        const std::vector<ExactDisk> state = events->exactState();
        CHECK(state[0].x == doctest::Approx(xa1).epsilon(1e-12));
        CHECK(state[1].x == doctest::Approx(xb1).epsilon(1e-12));
        CHECK(state[0].vx == doctest::Approx(-c.va).epsilon(1e-12));
    }
}

TEST_CASE("events: disks with nothing ahead (at rest) save and restore") {
    const WorldDef world = eventWorld(20, 20, 0.1f);
    auto events = startEvents(world, {disk(5, 5, 0, 0, 1.0f), disk(15, 15, 0, 0, 1.0f)});
    events->step(3);
    const EventEngineState saved = *events->saveState();
    CHECK(saved.disks[0].event == kEventNone);
    CHECK(eventStateProblem(saved, world.boundary).empty());
    std::vector<Particle> particles;
    events->readParticles(particles);
    EventDrivenBackend resumed(world);
    resumed.setParticles(particles, 3);
    resumed.restoreState(saved);
    resumed.step(3);
    CHECK(resumed.time() == doctest::Approx(6 * double(0.1f)).epsilon(1e-12));
}

TEST_CASE("events: restore refuses a state that does not fit, naming the value") {
    std::vector<Particle> seven;
    for (int i = 0; i < 7; ++i) seven.push_back(disk(3 + 5 * i, 5, i % 2 ? 1.0f : -1.0f, 0.5f));
    auto events = startEvents(eventWorld(40, 10, 0.1f), seven);
    events->step(5);
    const EventEngineState saved = *events->saveState();
    REQUIRE(saved.disks.size() == 7);
    const auto refusal = [&](const EventEngineState& state, const std::string& named) {
        CAPTURE(named);
        CHECK_THROWS_WITH_AS(events->restoreState(state), doctest::Contains(named.c_str()), Error);
    };

    EventEngineState fewer = saved;
    fewer.disks.resize(5);
    refusal(fewer, "5");
    refusal(fewer, "7");

    EventEngineState outside = saved;
    const std::uint32_t cells = events->columns() * events->rows();
    outside.disks[1].cell = cells + 7;
    refusal(outside, std::to_string(cells + 7));

    EventEngineState negative = saved;
    negative.time = -1;
    refusal(negative, "time -1 must be");

    EventEngineState infinite = saved;
    infinite.disks[2].vy = HUGE_VAL;
    refusal(infinite, "disk 2");

    EventEngineState later = saved;
    later.disks[3].time = saved.time + 1;
    refusal(later, "disk 3");

    EventEngineState partner = saved;
    partner.disks[4].event = 7;  // no disk 7
    refusal(partner, "event code 7");

    EventEngineState past = saved;
    past.disks[5].eventTime = saved.time - 0.25;
    refusal(past, std::to_string(saved.time - 0.25));

    EventEngineState none = saved;  // no event, yet a time for it
    none.disks[0].event = kEventNone;
    none.disks[0].eventTime = saved.time + 1;
    refusal(none, "must be +infinity for event code -1");

    EventEngineState throughWall = saved;  // a crossing out of the leftmost column of the walled box
    const std::uint32_t leftmost = saved.disks[0].cell - saved.disks[0].cell % events->columns();
    throughWall.disks[0].cell = leftmost;
    throughWall.disks[0].event = kEventCrossLeft;
    refusal(throughWall, "a crossing out of cell " + std::to_string(leftmost) + " through the box's wall");

    EventEngineState wandered = saved;  // in its cell at its own time, far away at the state's
    wandered.disks[0].time = 0;
    wandered.disks[0].vx = 1e6;
    wandered.disks[0].eventTime = saved.time + 1;
    refusal(wandered, "at the state's time, is not in its cell");

    EventEngineState misplaced = saved;  // a cell that is not the one its centre lies in
    misplaced.disks[6].cell = misplaced.disks[0].cell;
    refusal(misplaced, "is not in its cell " + std::to_string(saved.disks[0].cell));

    // The refusals left the backend as it was: it continues as one that
    // restored the saved state.
    auto reference = startEvents(eventWorld(40, 10, 0.1f), seven);
    reference->step(10);
    events->step(5);
    const std::vector<ExactDisk> a = reference->exactState(), b = events->exactState();
    CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(ExactDisk)) == 0);
}

TEST_CASE("events: the event-driven scheme runs on the CPU backend only") {
    WorldDef world = eventWorld(20, 20, 0.1f);
    auto cpu = makeBackend(EngineDef{}, world);
    CHECK(dynamic_cast<EventDrivenBackend*>(cpu.get()) != nullptr);
    CHECK(cpu->exactArithmetic());
    // The same refusal with or without OpenCL in the build: the scheme is checked first.
    for (ComputeEngine opencl : {ComputeEngine::OpenClHostGrid, ComputeEngine::OpenClResident})
        CHECK_THROWS_WITH_AS(makeBackend(EngineDef{opencl, ""}, world),
                             doctest::Contains("CollisionScheme::Events runs on ComputeEngine::Cpu only"), Error);
}
