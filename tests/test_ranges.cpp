// The ranges in which float32 results are valid (README, "Limits"): values
// outside them are refused with the value and the range named, a step lost
// in the float spacing of the positions is refused or warned about, and
// coincident or overlapping disks are refused or reported.
#include <chrono>
#include <cmath>
#include <string>

#include "engine/diagnostics.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

template <class Check>
std::string errorOf(Check&& check) {
    try {
        check();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The seconds `work` takes.
template <class Work>
double secondsOf(Work&& work) {
    const auto start = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string joined(const std::vector<std::string>& lines) {
    std::string all;
    for (const std::string& line : lines) all += line + "\n";
    return all;
}

// A row of n disks of radius 1 along y = 2 starting at x, every one moving at `speed` along -x.
std::vector<Particle> row(int n, float x, float speed) {
    std::vector<Particle> disks;
    for (int k = 0; k < n; ++k) disks.push_back(disk(x + 3.0f * k, 2.0f, -speed, 0.0f));
    return disks;
}

}  // namespace

TEST_CASE("ranges: world values outside the valid ranges are refused with the value and the range") {
    WorldDef w = box(100, 100);
    CHECK(errorOf([&] { validate(w); }).empty());
    w.dt = 1e30f;
    CHECK(mentions(errorOf([&] { validate(w); }), "dt 1e+30 is outside [1e-18, 1e+18]"));
    w.dt = 1e-30f;
    CHECK(mentions(errorOf([&] { validate(w); }), "dt 1e-30 is outside [1e-18, 1e+18]"));
    w = box(1e19f, 100);
    CHECK(mentions(errorOf([&] { validate(w); }), "box width 1e+19 is outside [1e-18, 1e+18]"));
    w = box(100, 100);
    w.gravity = float2{1e38f, 0.0f};
    CHECK(mentions(errorOf([&] { validate(w); }), "gravity (1e+38, 0) is stronger than 1e+18"));
}

TEST_CASE("ranges: scene masses, radii, speeds and packings outside the ranges are refused, subnormals too") {
    const auto sceneError = [](auto change) {
        SceneDef scene;
        scene.particles = 10;
        change(scene);
        return errorOf([&] { makeInitialState(scene); });
    };
    CHECK(mentions(sceneError([](SceneDef& s) { s.massMin = s.massMax = 2e38f; }),
                   "mass 2e+38 is outside [1e-15, 1e+15]"));
    CHECK(mentions(sceneError([](SceneDef& s) { s.massMin = s.massMax = 1e-40f; }), "is outside [1e-15, 1e+15]"));
    CHECK(mentions(sceneError([](SceneDef& s) { s.radiusMin = s.radiusMax = 1e-40f; }), "is outside [1e-18, 1e+18]"));
    CHECK(mentions(sceneError([](SceneDef& s) { s.speed = 1e30f; }), "speed 1e+30 is outside [0, 1e+18]"));
    CHECK(mentions(sceneError([](SceneDef& s) { s.packing = 1e-45f; }), "boxes up to 1e+18 are valid"));
}

TEST_CASE("ranges: particles with subnormal radii or masses are refused") {
    const WorldDef w = box(10, 10);
    CHECK(mentions(errorOf([&] { validateParticles({disk(5, 5, 0, 0, 1.0f, 1e-40f)}, w, "s.csv"); }),
                   "s.csv: particle 0: radius"));
    CHECK(mentions(errorOf([&] { validateParticles({disk(5, 5, 0, 0, 1e-40f)}, w, "s.csv"); }),
                   "s.csv: particle 0: mass"));
    CHECK(mentions(errorOf([&] { validateParticles({disk(5, 5, 0, 0, 2e38f)}, w, "s.csv"); }),
                   "is outside [1e-15, 1e+15]"));
}

TEST_CASE("ranges: a step below the float spacing of the positions is refused with the largest box") {
    // Speed 1, dt 0.01: a step of 0.01 against a spacing of 2^-6 beyond
    // x = 131072 (the disk would move 56 % too fast), 2^-10 below 16384.
    const auto far = row(2, 140000.0f, 1.0f);
    const std::string refused = errorOf([&] { validateStart(far, box(150000, 10), "s.csv"); });
    CHECK(mentions(refused, "less than the float32 spacing 0.015625"));
    CHECK(mentions(refused, "the largest box is 131072"));
    CHECK(mentions(errorOf([&] { validateStart(row(2, 9e6f, 1.0f), box(1e7f, 10), "s.csv"); }), "float32 spacing 1 "));

    const std::string warned = joined(validateStart(row(2, 19000.0f, 1.0f), box(20000, 10), "s.csv"));
    CHECK(mentions(warned, "5.12 float32 spacings"));
    CHECK(mentions(warned, "boxes up to 16384 keep it within 5 %"));
    CHECK(validateStart(row(2, 900.0f, 1.0f), box(1000, 10), "s.csv").empty());
    // Faster disks or a longer step move enough again.
    CHECK(validateStart(row(2, 140000.0f, 100.0f), box(150000, 10), "s.csv").empty());
}

TEST_CASE("ranges: disks at rest are judged by the speed gravity gives them, and need nothing without it") {
    const auto resting = row(2, 140000.0f, 0.0f);
    CHECK(validateStart(resting, box(150000, 10), "s.csv").empty());  // nothing moves: nothing is lost
    WorldDef falling = box(150000, 100);
    falling.gravity = float2{0.0f, -10.0f};  // sqrt(g H) = 31.6: 0.316 per step, 20 spacings
    CHECK(validateStart(resting, falling, "s.csv").empty());
    falling.gravity = float2{0.0f, -1e-6f};  // sqrt(g H) = 0.01: 1e-4 per step
    CHECK(mentions(errorOf([&] { validateStart(resting, falling, "s.csv"); }), "less than the float32 spacing"));
}

TEST_CASE("ranges: a step that moves the fastest disk across the box is refused unless it is split") {
    WorldDef w = box(100, 100, 1e4f);
    const auto disks = row(2, 50.0f, 1.0f);
    CHECK(
        mentions(errorOf([&] { validateStart(disks, w, "s.csv"); }),
                 "moves the fastest disk (speed up to 1) by 10000, more than the box side 100; the largest dt is 100"));
    w.maxTravel = 0.2f;  // substeps of at most 0.2 radii: the step is only a sampling interval
    CHECK(errorOf([&] { validateStart(disks, w, "s.csv"); }).empty());
}

TEST_CASE("ranges: box diagonal times speed beyond 1e18 is refused, where collision times would overflow") {
    // The scale of 1e19 (box, radius, speed) that went NaN, and 1e17 that overflows the squares.
    std::vector<Particle> disks = {disk(2e16f, 5e16f, 1e17f, 0, 1, 1e16f), disk(6e16f, 5e16f, -1e17f, 0, 1, 1e16f)};
    CHECK(
        mentions(errorOf([&] { validateStart(disks, box(1e17f, 1e17f), "s.csv"); }), "results are valid up to 1e+18"));
}

CAROM_BACKEND_TEST_CASE("ranges: results at the edges of the ranges stay finite") {
    // Masses 1e-15 and 1e15 colliding at a speed and in a box whose product
    // (7e17) is near the limit, with each scheme: no NaN, no
    // infinite tally.
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        WorldDef w = box(1e10f, 1e10f, 0.1f);
        w.collisions = scheme;
        std::vector<Particle> disks;
        for (int k = 0; k < 50; ++k)
            disks.push_back(disk(1e8f + 1.9e8f * k, 5e9f + 3e7f * (k % 3), k % 2 ? -5e7f : 5e7f, 1e7f,
                                 k % 2 ? 1e15f : 1e-15f, 5e7f));
        REQUIRE(validateStart(disks, w, "edge").empty());
        const Run r = run(def, w, disks, 50);
        CHECK(r.contacts.collisions > 0);
        CHECK(std::isfinite(r.contacts.virial));
        for (double impulse : r.contacts.wallImpulse) CHECK(std::isfinite(impulse));
        const Diagnostics d = measureMotion(r.particles, w);
        CHECK(std::isfinite(d.kineticEnergy));
        CHECK(d.escaped == 0);
    }
}

TEST_CASE("ranges: coincident disks are refused with the pair; overlapping ones are reported") {
    const WorldDef w = box(20, 20);
    std::vector<Particle> disks = {disk(5, 5, 1, 0), disk(10, 10, 0, 1), disk(15, 5, 0, 0), disk(10, 10, 1, 1)};
    CHECK(mentions(errorOf([&] { validateStart(disks, w, "s.csv"); }),
                   "s.csv: particles 1 and 3 have the same centre (10, 10)"));
    disks[3].position = float2{11.5f, 10.0f};  // 0.5 deep, far more than a step of 0.01 closes
    const std::string warned = joined(validateStart(disks, w, "s.csv"));
    CHECK(mentions(warned, "1 pair(s) of disks overlap, the deepest particles 1 and 3 by 0.5 (25 % of"));
    disks[3].position = float2{11.99f, 10.0f};  // what a step leaves behind: not reported
    CHECK(validateStart(disks, w, "s.csv").empty());
}

TEST_CASE("ranges: the overlap search over a million disks uses the grid") {
    SceneDef scene;
    scene.particles = 1'000'000;
    scene.packing = 0.5f;
    InitialState s = makeInitialState(scene);
    s.particles.back().position = s.particles.front().position;
    const WorldDef w = box(s.width, s.height);
    CHECK(mentions(errorOf([&] { validateStart(s.particles, w, "big"); }),
                   "particles 0 and 999999 have the same centre"));
}

// A grid capped at ~4 cells per disk put a pile of disks into one cell and
// checked all N^2 / 2 pairs: 10^5 coincident disks took 40 s to refuse.
TEST_CASE("ranges: the checks of piled-up disks cost O(N log N), not N^2") {
    const int n = 100'000;
    const WorldDef w = box(1000, 1000);
    std::vector<Particle> same(n, disk(500, 500, 1, 0));
    std::string refused;
    CHECK(secondsOf([&] { refused = errorOf([&] { validateStart(same, w, "s.csv"); }); }) < 5.0);
    CHECK(mentions(refused, "s.csv: particles 0 and 1 have the same centre (500, 500)"));
    CHECK(mentions(refused, "4999950000 such pair(s) in all"));

    // A heap of distinct centres, every pair overlapping: counting stops.
    std::vector<Particle> heap;
    for (int k = 0; k < n; ++k) heap.push_back(disk(500.0f + 0.001f * (k % 300), 500.0f + 0.001f * (k / 300), 1, 0));
    Overlaps overlaps;
    CHECK(secondsOf([&] { overlaps = findOverlaps(heap, w); }) < 5.0);
    CHECK_FALSE(overlaps.allCounted);
    CHECK(overlaps.pairs == kOverlapsCountedPerDisk * n);
    CHECK(mentions(joined(validateStart(heap, w, "s.csv")), "more than 800000 pair(s) of disks overlap"));

    // Tiny disks that do not overlap, heaped in a corner of a large box.
    std::vector<Particle> dust = heap;
    for (Particle& p : dust) p.radius = 0.0004f;
    CHECK(secondsOf([&] { overlaps = findOverlaps(dust, w); }) < 5.0);
    CHECK(overlaps.pairs == 0);
    CHECK(overlaps.allCounted);
}

// The typical speed came from the total energy alone: one fast disk holding
// most of it hid that 199 slow disks far out in a wide box could not move.
TEST_CASE("ranges: slow disks are judged at their own speed, not at a fast disk's share of the energy") {
    std::vector<Particle> disks = row(199, 900000.0f, 1.0f);  // 0.01 a step; positions there are 0.0625 apart
    disks.push_back(disk(10, 10, 10000, 0));
    const WorldDef w = box(1e6f, 1000);
    CHECK(mentions(errorOf([&] { validateStart(disks, w, "s.csv"); }),
                   "s.csv: a step moves a typical disk (speed 1, step 0.01) by 0.01, less than the float32 spacing "
                   "0.0625"));
    for (std::size_t k = 0; k + 1 < disks.size(); ++k) disks[k].velocity.x *= 20;  // 0.2 a step: up to 16 % off
    CHECK(mentions(joined(validateStart(disks, w, "s.csv")), "a step moves a typical disk by 0.2, only 3.2"));
    for (std::size_t k = 0; k + 1 < disks.size(); ++k) disks[k].velocity = float2{0.0f, 0.0f};  // at rest: nothing lost
    CHECK(validateStart(disks, w, "s.csv").empty());
}

// Nothing said that two disks closing by more than their contact distance in
// a step can pass through each other under the simultaneous scheme.
TEST_CASE("ranges: the simultaneous scheme warns when a step can carry two disks through each other") {
    const std::vector<Particle> headOn = {disk(10, 10, 150, 0), disk(18.5f, 10, -150, 0)};
    WorldDef w = box(60, 40);
    w.collisions = CollisionScheme::Simultaneous;
    const std::string warned = joined(validateStart(headOn, w, "s.csv"));
    CHECK(mentions(warned,
                   "a step moves the fastest disk (speed 150, step 0.01) by 1.5, more than the smallest "
                   "radius 1: two disks meeting head-on"));
    CHECK(mentions(warned, "can let them pass through each other; steps up to 0.00666667 avoid it"));
    w.maxTravel = 1.0f;  // substeps of at most a radius
    CHECK(validateStart(headOn, w, "s.csv").empty());
    w.maxTravel = 0.0f;
    w.collisions = CollisionScheme::Pairwise;  // finds the contact within the step
    CHECK(validateStart(headOn, w, "s.csv").empty());
}

// The events scheme never leaves overlaps but rounding's, yet it was allowed
// the depth a step of dt closes, and said nothing of shallower ones.
TEST_CASE("ranges: the events scheme reports any overlap deeper than rounding") {
    const std::vector<Particle> disks = {disk(10, 10, 0, 0), disk(11.999f, 10, 1, 0)};
    WorldDef w = box(60, 40);
    w.collisions = CollisionScheme::Events;
    CHECK(mentions(joined(validateStart(disks, w, "s.csv")),
                   "1 pair(s) of disks overlap, the deepest particles 0 and 1 by 0.0010"));
    CHECK(mentions(joined(validateStart(disks, w, "s.csv")), "more than rounding leaves (0.0001)"));
    w.collisions = CollisionScheme::Pairwise;  // what a step of 0.01 leaves behind
    CHECK(validateStart(disks, w, "s.csv").empty());
}
