// Checkpoints of the events scheme (format version 3 and later): the engine's exact
// state is written and read back bit for bit, every damaged or forged value
// is refused with a message naming it, and a run resumed from it continues
// bit for bit. Also the changes the viewer makes between steps (new
// particles, gravity switched on) on the engine.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "backends/event_driven.h"
#include "checkpoint_support.h"
#include "engine/disk_conversion.h"
#include "io/checkpoint.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Three disks in a 10 x 10 box and an engine state for them whose every
// field is set, with values that round-trip only bit for bit (-0, a
// subnormal, +infinity for no event).
Snapshot threeDisks(Boundary boundary = Boundary::Walls) {
    Snapshot c;
    c.world = box(10, 10);
    c.world.boundary = boundary;
    c.world.collisions = CollisionScheme::Events;
    c.step = 12;
    c.time = 0.12;
    c.collisions = 4;
    c.disks = disksOf({disk(2, 2, 1, 0), disk(5, 5, 0, -1, 2, 0.5f), disk(8, 8, 0.25f, 0.5f, 3, 1.5f)});
    EventEngineState state;
    state.time = 0.12000000000000001;
    state.disks = {
        {2.0, 2.0, 1.0, -0.0, 0.1, 0.5, 1, 7, 3, 0},
        {5.0000000000000009, 5.0, 4.9406564584124654e-324, -1.0, 0.12, 0.5, 0, 3, 7, 4},
        {8.0, 8.0, 0.25, 0.5, 0.0, kInfinity, kEventNone, 0, 0, 8},
    };
    state.disks[0].event = 1;
    state.disks[1].event = boundary == Boundary::Walls ? kEventWallTop : kEventCrossUp;
    c.events = state;
    return c;
}

// The refusal of threeDisks() changed by `change` and written with a valid checksum.
template <class Change>
std::string refusalOf(Change change, Boundary boundary = Boundary::Walls) {
    Snapshot c = threeDisks(boundary);
    change(*c.events);
    return errorOf(encodeCheckpoint(c));
}

// A few hundred polydisperse disks of unequal masses under the events scheme.
Scenario eventsScenario(Boundary boundary, float2 gravity) {
    Scenario scenario = polydisperseDisks(300, 0.01f);
    scenario.world.boundary = boundary;
    scenario.world.gravity = gravity;
    scenario.world.collisions = CollisionScheme::Events;
    return scenario;
}

std::unique_ptr<EventDrivenBackend> makeEngine(const WorldDef& world) {
    std::unique_ptr<Backend> backend = makeBackend(EngineDef{}, world);
    REQUIRE(dynamic_cast<EventDrivenBackend*>(backend.get()) != nullptr);
    return std::unique_ptr<EventDrivenBackend>(static_cast<EventDrivenBackend*>(backend.release()));
}

// What the engine holds now, as a checkpoint at `step` would keep it.
Snapshot checkpointOf(EventDrivenBackend& engine, std::uint64_t step, std::uint64_t collisions) {
    Snapshot c;
    c.world = engine.world();
    c.step = step;
    c.time = double(step) * c.world.dt;
    c.collisions = collisions;
    std::vector<Particle> particles;
    engine.readParticles(particles);
    c.disks = disksOf(particles);
    c.events = engine.saveState();
    return c;
}

}  // namespace

TEST_CASE("events checkpoint: the engine's state is written and read back bit for bit") {
    const Snapshot c = threeDisks();
    const std::string bytes = encodeCheckpoint(c);
    REQUIRE(bytes.size() == 76 + 32 * 3 + 8 + 64 * 3 + 4);  // the layout of checkpoint.h
    CHECK(bytes[12] == 4);
    CHECK(bytes[72] == 2);  // the events scheme
    double time;
    std::memcpy(&time, bytes.data() + 76 + 32 * 3, sizeof time);  // little-endian, as this machine
    CHECK(time == c.events->time);

    const Snapshot read = decodeCheckpoint(bytes, "c.ckpt");
    CHECK(read.world.collisions == CollisionScheme::Events);
    REQUIRE(read.events.has_value());
    REQUIRE(read.events->disks.size() == 3);
    CHECK(std::memcmp(read.events->disks.data(), c.events->disks.data(), 3 * sizeof(EventDiskState)) == 0);
    CHECK(std::signbit(read.events->disks[0].vy));
    CHECK(read.events->disks[2].eventTime == kInfinity);
    CHECK(encodeCheckpoint(read) == bytes);

    const Snapshot periodic = threeDisks(Boundary::Periodic);
    CHECK(encodeCheckpoint(decodeCheckpoint(encodeCheckpoint(periodic), "p.ckpt")) == encodeCheckpoint(periodic));
}

TEST_CASE("events checkpoint: sizes are checked against the file before anything is allocated") {
    const std::string bytes = encodeCheckpoint(threeDisks());
    for (std::size_t length = 76; length < bytes.size(); ++length) {
        CAPTURE(length);
        CHECK(errorOf(bytes.substr(0, length)).find("3 particles and their events state need 376") !=
              std::string::npos);
    }
    CHECK(errorOf(bytes + "x").find("377 bytes, but 3 particles and their events state need 376: trailing bytes") !=
          std::string::npos);
    std::string forged = bytes;
    putU32(forged, 16, 100'000'000);  // 100 million disks in a 376-byte file
    CHECK(errorOf(forged).find("truncated: 376 bytes, but 100000000 particles and their events state need "
                               "9600000088") != std::string::npos);
}

TEST_CASE("events checkpoint: every invalid value is refused, naming it") {
    CHECK(refusalOf([](EventEngineState& s) {
              s.time = NAN;
          }).find("checkpoint 'c.ckpt': events state: time nan must be a finite number >= 0") != std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) { s.time = -1; }).find("events state: time -1 must be") !=
          std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) {
              s.disks[1].x = kInfinity;
          }).find("events state: disk 1: x inf must be finite") != std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) { s.disks[2].vy = NAN; }).find("disk 2: vy nan must be finite") !=
          std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) {
              s.disks[0].time = -kInfinity;
          }).find("disk 0: time -inf must be finite") != std::string::npos);
    CHECK(
        refusalOf([](EventEngineState& s) {
            s.disks[0].event = -10;
        }).find("disk 0: event code -10 is unknown; allowed: -9 to -1 (kinds of event) or a partner id from 0 to 2") !=
        std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) { s.disks[0].event = 3; }).find("disk 0: event code 3 is unknown") !=
          std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) {
              s.disks[2].event = 2;
          }).find("disk 2: its event is a collision with itself (event code 2)") != std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) { s.disks[1].event = kEventWallRight; }, Boundary::Periodic)
              .find("disk 1: event code -3 is a wall bounce, but the box is periodic") != std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) {
              s.disks[2].eventTime = 5;
          }).find("disk 2: event time 5 must be +infinity for event code -1 (no event)") != std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) {
              s.disks[2].eventTime = -kInfinity;
          }).find("event time -inf must be +infinity") != std::string::npos);
    CHECK(refusalOf([](EventEngineState& s) {
              s.disks[0].eventTime = kInfinity;
          }).find("disk 0: event time inf must be finite for event code 1") != std::string::npos);
    CHECK(refusalOf([](EventEngineState&) {}).empty());
}

TEST_CASE("events checkpoint: version 2 still reads, and never held the events scheme") {
    Snapshot pairwise = threeDisks();
    pairwise.world.collisions = CollisionScheme::Pairwise;
    pairwise.events.reset();
    const std::string current = encodeCheckpoint(pairwise);
    std::string version2 = asVersion(current, 2, 3);
    const Snapshot read = decodeCheckpoint(version2, "v2.ckpt");
    CHECK(read.world.collisions == CollisionScheme::Pairwise);
    CHECK_FALSE(read.events.has_value());
    CHECK(encodeCheckpoint(read) == current);  // written again as version 4

    putU32(version2, 72, 2);
    reseal(version2);
    CHECK(errorOf(version2).find(
              "collision scheme code 2 is unknown in format version 2; allowed: 0 (simultaneous), 1 (pairwise)") !=
          std::string::npos);
}

TEST_CASE("events checkpoint: the engine's state goes with the events scheme and no other") {
    Snapshot c = threeDisks();
    c.events.reset();
    CHECK_THROWS_WITH_AS(encodeCheckpoint(c),
                         doctest::Contains("exactly with the events scheme (here events, no state"), Error);
    c = threeDisks();
    c.world.collisions = CollisionScheme::Pairwise;
    CHECK_THROWS_WITH_AS(encodeCheckpoint(c), doctest::Contains("(here pairwise, 3 disks in the state"), Error);
    c = threeDisks();
    c.events->disks.pop_back();
    CHECK_THROWS_WITH_AS(encodeCheckpoint(c), doctest::Contains("(here events, 2 disks in the state, 3 particles)"),
                         Error);
}

TEST_CASE("events checkpoint: a run resumed from the saved state continues bit for bit") {
    for (const auto& [boundary, gravity] :
         {std::pair{Boundary::Periodic, float2{0, 0}}, std::pair{Boundary::Walls, float2{0.0f, -0.5f}}}) {
        const std::string boundaryText = boundaryName(boundary);
        CAPTURE(boundaryText);
        const Scenario scenario = eventsScenario(boundary, gravity);
        constexpr std::uint64_t kHalf = 150;
        auto whole = makeEngine(scenario.world);
        whole->setParticles(scenario.particles);
        whole->step(2 * kHalf);
        const Snapshot wholeEnd = checkpointOf(*whole, 2 * kHalf, whole->collisions());

        auto first = makeEngine(scenario.world);
        first->setParticles(scenario.particles);
        first->step(kHalf);
        writeCheckpoint("events-half.ckpt", checkpointOf(*first, kHalf, first->collisions()));
        const Snapshot halfway = readCheckpoint("events-half.ckpt");
        std::remove("events-half.ckpt");
        REQUIRE(halfway.events.has_value());

        auto second = makeEngine(halfway.world);
        second->setParticles(particlesOf(halfway.disks.data(), halfway.disks.size()), halfway.step);
        second->restoreState(*halfway.events);
        second->step(kHalf);
        const Snapshot resumedEnd = checkpointOf(*second, 2 * kHalf, halfway.collisions + second->collisions());
        CHECK(wholeEnd.collisions > 0);
        CHECK(resumedEnd.collisions == wholeEnd.collisions);
        // Every bit of the particles and of the engine's state.
        CHECK(encodeCheckpoint(resumedEnd) == encodeCheckpoint(wholeEnd));
    }
}

TEST_CASE("events: the viewer's changes between steps, new particles and gravity switched on, keep it exact") {
    const Scenario scenario = eventsScenario(Boundary::Walls, float2{0, 0});
    auto engine = makeEngine(scenario.world);
    engine->setParticles(scenario.particles);
    engine->step(50);
    // A flick: the state read back, one disk's velocity changed, loaded again.
    std::vector<Particle> particles;
    engine->readParticles(particles);
    particles[3].velocity = float2{4.0f, 3.0f};
    engine->setParticles(particles);
    CHECK(engine->time() == 0.0);
    const double afterFlick = *engine->exactTotalEnergy();
    engine->step(50);
    CHECK(std::fabs(*engine->exactTotalEnergy() - afterFlick) <= 1e-12 * afterFlick);
    // Gravity switched on (the G key): the engine schedules every disk again.
    engine->setMotion(scenario.world.dt, float2{0.0f, -1.0f});
    const double afterGravity = *engine->exactTotalEnergy();
    const std::uint64_t bouncesBefore = engine->eventCounts().wallBounces;
    engine->step(200);
    CHECK(std::fabs(*engine->exactTotalEnergy() - afterGravity) <= 1e-12 * std::fabs(afterGravity));
    CHECK(engine->eventCounts().wallBounces > bouncesBefore);
    engine->readParticles(particles);
    const WorldDef& w = engine->world();
    for (const Particle& p : particles) {
        CHECK(p.position.x >= 0.0f);
        CHECK(p.position.x <= w.width);
        CHECK(p.position.y >= 0.0f);
        CHECK(p.position.y <= w.height);
    }
}
