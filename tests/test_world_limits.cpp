// The World's refusals at the edges of its counts and arguments: null
// arrays, a step count past 2^64 - 1, and snapshots (checkpoints) whose
// time, collision count or events state no run can reach.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <carom/carom.h>
#include <carom/io.h>

#include "io/checkpoint.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

constexpr std::uint64_t kLargest = std::numeric_limits<std::uint64_t>::max();

World twoDisks(CollisionScheme scheme = CollisionScheme::Pairwise, float dt = 0.01f) {
    WorldDef def;
    def.width = def.height = 10.0f;
    def.dt = dt;
    def.collisions = scheme;
    World world(def);
    world.setDisks({Disk{{2, 2}, {1, 0.5f}, 1, 1}, Disk{{7, 6}, {-1, 0}, 1, 1}});
    return world;
}

std::string refusalOf(World& world, const Snapshot& snapshot) {
    try {
        world.restore(snapshot);
    } catch (const Error& e) {
        return e.what();
    }
    return "(accepted)";
}

template <class Call>
std::string refusalOf(Call call) {
    try {
        call();
    } catch (const Error& e) {
        return e.what();
    }
    return "(accepted)";
}

}  // namespace

TEST_CASE("world: a null array with a count is refused, naming the argument, and the world keeps its disks") {
    World empty(box(10, 10));
    CHECK(refusalOf([&] { empty.setDisks(nullptr, 5); }) ==
          "setDisks: disks is null, for 5 disks; allowed: a pointer to 5 disks");
    CHECK(refusalOf([&] { empty.addDisks(nullptr, 3); }) ==
          "addDisks: disks is null, for 3 disks; allowed: a pointer to 3 disks");
    World world = twoDisks();
    const std::vector<Disk> before = world.disks();
    CHECK(refusalOf([&] { world.setDisks(nullptr, 5); }).find("setDisks: disks is null") == 0);
    CHECK(refusalOf([&] { world.addDisks(nullptr, 3); }).find("addDisks: disks is null") == 0);
    CHECK(refusalOf([&] { world.editDisks(nullptr, 2); }).find("editDisks: disks is null") == 0);
    CHECK(refusalOf([&] { world.getDisks(nullptr, 2); }) ==
          "getDisks: out is null, for 2 disks; allowed: a pointer to 2 disks");
    Disk one;
    CHECK(refusalOf([&] { world.getDisks(1, 2, &one); }) ==
          "getDisks: first 1, count 2; allowed: first + count <= 2 (diskCount())");
    CHECK(refusalOf([&] { world.getDisks(std::size_t(-1), 2, &one); }) ==
          "getDisks: first 18446744073709551615, count 2; allowed: first + count <= 2 (diskCount())");
    CHECK(refusalOf([&] { world.readView(ViewValue::Speed, nullptr, 2); }) ==
          "readView: out is null, for 2 views; allowed: a pointer to 2 views");
    CHECK(world.diskCount() == 2);
    CHECK(world.disks()[1].position.x == before[1].position.x);
    world.addDisks(nullptr, 0);  // nothing to add
    CHECK(world.diskCount() == 2);
}

TEST_CASE("world: step refuses to take the step count past 2^64 - 1, and keeps its step") {
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Events}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        World world = twoDisks(scheme, 1.0f);
        world.step(20);  // a time that 2^64 steps of kMinDt reach (18.4)
        Snapshot late = world.snapshot();
        late.step = kLargest - 2;
        world.restore(late);
        CHECK(refusalOf([&] { world.step(5); }) ==
              "step: 5 steps from step 18446744073709551613 would take the step count past 2^64 - 1; allowed: "
              "at most 2");
        CHECK(world.stepCount() == kLargest - 2);
        world.step(2);
        CHECK(world.stepCount() == kLargest);
        CHECK(refusalOf([&] { world.step(1); }).find("allowed: at most 0") != std::string::npos);
    }
}

TEST_CASE("snapshot: a time that its steps cannot add up to is refused, by restore and in a checkpoint") {
    World world = twoDisks();
    world.step(100);
    const Snapshot good = world.snapshot();

    Snapshot forged = good;
    forged.time = 1e300;
    CHECK(refusalOf(world, forged) ==
          "snapshot: time 1e+300 at step 100; allowed: what 100 steps of a dt in [kMinDt, kMaxDt] add up to, "
          "[1e-16, 1e+20]");
    CHECK(refusalOf([&] { decodeCheckpoint(encodeCheckpoint(forged), "c.ckpt"); }).find("time 1e+300 at step 100") !=
          std::string::npos);
    Snapshot late = good;
    late.step = 0;
    CHECK(refusalOf(world, late).find("at step 0; allowed: what 0 steps of a dt in [kMinDt, kMaxDt] add up to, 0") !=
          std::string::npos);
    Snapshot stopped = good;
    stopped.time = 0;
    CHECK(refusalOf(world, stopped).find("snapshot: time 0 at step 100") == 0);
    CHECK(world.stepCount() == 100);  // the world as it was
    world.restore(good);
}

TEST_CASE("snapshot: a collision count past 2^63 is refused, so that a run from one never wraps it") {
    World world = twoDisks();
    Snapshot many = world.snapshot();
    many.collisions = kLargest;
    CHECK(refusalOf(world, many) ==
          "snapshot: collision count 18446744073709551615; allowed: at most 9223372036854775808 (2^63), which no "
          "run reaches");
    CHECK(refusalOf([&] {
              decodeCheckpoint(encodeCheckpoint(many), "c.ckpt");
          }).find("collision count 18446744073709551615") != std::string::npos);
    many.collisions = std::uint64_t(1) << 63;
    world.restore(many);
    CHECK(world.collisionCount() == std::uint64_t(1) << 63);
}

TEST_CASE("snapshot: an events state with two disks on one centre is refused, though its float disks differ") {
    World world = twoDisks(CollisionScheme::Events);
    world.step(3);
    Snapshot same = world.snapshot();
    EventDiskState& second = same.events->disks[1];
    const EventDiskState& first = same.events->disks[0];
    second.x = first.x;
    second.y = first.y;
    second.vx = first.vx;
    second.vy = first.vy;
    second.time = first.time;
    second.cell = first.cell;
    second.eventTime = std::numeric_limits<double>::infinity();
    second.event = kEventNone;
    CHECK(refusalOf(world, same).find("snapshot: events state: disks 0 and 1 have the same centre (") == 0);
    CHECK(refusalOf(world, same).find(") at the state's time: their collision has no direction") != std::string::npos);
    CHECK(world.stepCount() == 3);
}

TEST_CASE("world: an edit that puts two disks on one centre is refused, as setDisks refuses it, for every scheme") {
    for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous, CollisionScheme::Events}) {
        CAPTURE(std::string(collisionSchemeName(scheme)));
        World world = twoDisks(scheme);
        const std::vector<Disk> before = world.disks();
        CHECK(refusalOf([&] {
                  world.setDisk(1, Disk{{2, 2}, {0, 1}, 1, 1});
              }) ==
              "setDisk: disks 0 and 1 have the same centre (2, 2): their collision has no direction; allowed: "
              "distinct centres");
        const Disk onFirst{{-0.0f + 2, 2}, {0, 0}, 1, 0.5f};
        CHECK(refusalOf([&] { world.addDisks(&onFirst, 1); }).find("addDisks: disks 0 and 2 have the same centre") ==
              0);
        // Many at once (a hash of the centres): two new ones on one centre, and one on an old one.
        std::vector<Disk> many;
        for (int i = 0; i < 20; ++i) many.push_back(Disk{{0.5f + 0.4f * i, 9}, {0, 0}, 1, 0.1f});
        many[13].position = many[4].position;
        CHECK(refusalOf([&] {
                  world.addDisks(many.data(), many.size());
              }).find("addDisks: disks 6 and 15 have the same centre (2.1, 9)") == 0);
        many[13].position = {7, 6};
        CHECK(refusalOf([&] {
                  world.addDisks(many.data(), many.size());
              }).find("addDisks: disks 1 and 15 have the same centre (7, 6)") == 0);
        std::vector<Disk> edited = before;
        edited[0].position = edited[1].position;
        CHECK(refusalOf([&] {
                  world.editDisks(edited.data(), edited.size());
              }).find("editDisks: disks 0 and 1 have the same centre") == 0);
        CHECK(world.diskCount() == 2);
        CHECK(world.disks()[1].position.x == before[1].position.x);
    }
}
