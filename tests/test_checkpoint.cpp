// Checkpoints: a resumed run continues bit for bit, on each backend and
// across backends; damaged files are refused with a message, never a crash.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "checkpoint_support.h"
#include "engine/disk_conversion.h"
#include "io/checkpoint.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

// Polydisperse, unequal masses, under gravity: every field of the state matters.
Scenario polydisperseScenario() {
    Scenario scenario = polydisperseDisks(1500, 0.005f);
    scenario.world.gravity = float2{0.0f, -0.5f};
    return scenario;
}

bool sameBits(const std::vector<Disk>& a, const std::vector<Disk>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Disk)) == 0;
}

// Runs `steps` steps of `start` on backend `def` and checkpoints the result.
Snapshot runAndCheckpoint(const EngineDef& def, const Snapshot& start, std::uint64_t steps) {
    auto backend = makeBackend(def, start.world);
    backend->setParticles(particlesOf(start.disks.data(), start.disks.size()));
    backend->step(steps);
    Snapshot end;
    end.world = start.world;
    end.step = start.step + steps;
    end.time = double(end.step) * start.world.dt;
    end.collisions = start.collisions + backend->collisions();
    std::vector<Particle> particles;
    backend->readParticles(particles);
    end.disks = disksOf(particles);
    return end;
}

std::string small() {
    Snapshot c;
    c.world = box(10, 10);
    c.step = 7;
    c.time = 0.07;
    c.collisions = 3;
    c.disks = disksOf({disk(2, 2, 1, 0), disk(5, 5, 0, -1, 2, 0.5f), disk(8, 8, 0.25f, 0.5f, 3, 1.5f)});
    return encodeCheckpoint(c);
}

// 2N steps in one run equal N steps, a checkpoint and N resumed, on backend `def`.
void checkResumeBitForBit(const EngineDef& def, const Scenario& scenario, std::uint64_t half) {
    const Snapshot start{scenario.world, 0, 0.0, 0, disksOf(scenario.particles), std::nullopt, {}};
    const Snapshot whole = runAndCheckpoint(def, start, 2 * half);
    // A file of its own per engine and scheme: ctest runs the cases of each backend at once.
    const std::string file = std::string("half-") + computeEngineName(def.engine) + "-" +
                             collisionSchemeName(scenario.world.collisions) + ".ckpt";
    writeCheckpoint(file, runAndCheckpoint(def, start, half));
    const Snapshot halfway = readCheckpoint(file);
    CHECK(halfway.world.collisions == scenario.world.collisions);
    const Snapshot resumed = runAndCheckpoint(def, halfway, half);
    CHECK(resumed.step == 2 * half);
    CHECK(resumed.time == whole.time);
    CHECK(resumed.collisions == whole.collisions);
    CHECK(whole.collisions > 0);
    CHECK(sameBits(resumed.disks, whole.disks));
    std::remove(file.c_str());
}

}  // namespace

TEST_CASE("checkpoint: every field reads back bit for bit") {
    const Scenario scenario = polydisperseScenario();
    Snapshot c;
    c.world = scenario.world;
    c.world.collisions = CollisionScheme::Pairwise;
    c.step = 123456789012ull;
    c.time = 617283.945060;
    c.collisions = 98765;
    c.disks = disksOf(scenario.particles);
    writeCheckpoint("roundtrip.ckpt", c);
    const Snapshot back = readCheckpoint("roundtrip.ckpt");
    CHECK(back.world.width == c.world.width);
    CHECK(back.world.height == c.world.height);
    CHECK(back.world.dt == c.world.dt);
    CHECK(back.world.gravity.y == c.world.gravity.y);
    CHECK(back.world.collisions == CollisionScheme::Pairwise);
    CHECK(back.step == c.step);
    CHECK(back.time == c.time);
    CHECK(back.collisions == c.collisions);
    CHECK(sameBits(back.disks, c.disks));
    std::ifstream file("roundtrip.ckpt", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    CHECK(bytes.size() == 76 + 32 * c.disks.size() + 4);
    CHECK(bytes.substr(0, 8) == "CAROMCKP");
    std::remove("roundtrip.ckpt");
}

CAROM_BACKEND_TEST_CASE("checkpoint: 2000 steps in one run equal 1000, a checkpoint and 1000 resumed") {
    checkResumeBitForBit(def, polydisperseScenario(), 1000);
}

TEST_CASE("checkpoint: 400 pairwise steps equal 200, a checkpoint and 200 resumed with the same scheme (CPU)") {
    Scenario scenario = polydisperseScenario();
    scenario.world.collisions = CollisionScheme::Pairwise;
    checkResumeBitForBit(testEngine(ComputeEngine::Cpu), scenario, 200);
}

TEST_CASE("checkpoint: a version-1 file (before the collision schemes) reads as the simultaneous scheme") {
    std::string bytes = "CAROMCKP";  // the version-1 layout, as checkpoint.h describes it
    auto u32 = [&bytes](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) bytes += static_cast<char>(v >> (8 * i));
    };
    auto u64 = [&u32](std::uint64_t v) {
        u32(static_cast<std::uint32_t>(v));
        u32(static_cast<std::uint32_t>(v >> 32));
    };
    auto f32 = [&u32](float v) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        u32(bits);
    };
    u32(0x01020304);
    u32(1);                                                     // version
    u64(2);                                                     // particles
    for (float v : {12.0f, 8.0f, 0.005f, 0.0f, -2.0f}) f32(v);  // box, dt, gravity
    u32(1);                                                     // periodic
    u64(40);                                                    // step
    const double time = 0.2;
    std::uint64_t timeBits;
    std::memcpy(&timeBits, &time, sizeof timeBits);
    u64(timeBits);
    u64(9);  // collisions
    for (float v : {3.0f, 4.0f, 0.5f, -0.25f, 2.0f, 1.0f, 9.0f, 4.0f, -1.0f, 0.0f, 1.0f, 0.75f}) f32(v);
    u32(0);  // the checksum, rewritten:
    reseal(bytes);
    REQUIRE(bytes.size() == 72 + 2 * 24 + 4);

    Snapshot expected;
    expected.world = box(12, 8, 0.005f);
    expected.world.gravity = float2{0.0f, -2.0f};
    expected.world.boundary = Boundary::Periodic;
    expected.world.collisions = CollisionScheme::Simultaneous;
    expected.step = 40;
    expected.time = 0.2;
    expected.collisions = 9;
    expected.disks = disksOf({disk(3, 4, 0.5f, -0.25f, 2, 1), disk(9, 4, -1, 0, 1, 0.75f)});
    const Snapshot c = decodeCheckpoint(bytes, "v1.ckpt");
    CHECK(c.world.collisions == CollisionScheme::Simultaneous);
    // Every field, bit for bit; written again, it is a version-4 file, its images {0, 0}.
    const std::string rewritten = encodeCheckpoint(c);
    CHECK(rewritten == encodeCheckpoint(expected));
    CHECK(rewritten.size() == bytes.size() + 4 + 2 * 8);
    CHECK(rewritten[12] == 4);

    CHECK(errorOf(bytes.substr(0, 70)).find("shorter than the 72-byte header") != std::string::npos);
}

TEST_CASE("checkpoint: images read back, and a version-3 file (before them) reads with images {0, 0}") {
    Snapshot c;
    c.world = box(10, 10);
    c.world.boundary = Boundary::Periodic;
    c.disks = disksOf({disk(2, 2, 1, 0), disk(5, 5, 0, -1, 2, 0.5f), disk(8, 8, 0.25f, 0.5f, 3, 1.5f)});
    c.images = {Image{1, -2}, Image{0, 0}, Image{-2147483647 - 1, 2147483647}};
    const std::string bytes = encodeCheckpoint(c);
    CHECK(decodeCheckpoint(bytes, "c.ckpt").images == c.images);
    const Snapshot old = decodeCheckpoint(asVersion(bytes, 3, 3), "v3.ckpt");
    CHECK(old.images.empty());
    CHECK(sameBits(old.disks, c.disks));
    c.images.pop_back();
    CHECK_THROWS_WITH_AS(encodeCheckpoint(c), "2 images for 3 disks; allowed: one per disk, or none (all {0, 0})",
                         Error);
}

CAROM_OPENCL_TEST_CASE("checkpoint: a run resumed on another backend continues bit for bit where the backends agree") {
    const Scenario scenario = polydisperseScenario();
    if (!makeBackend(def, scenario.world)->exactArithmetic()) {
        MESSAGE("the OpenCL device lacks correctly rounded divide/sqrt: the backends do not agree bitwise");
        return;
    }
    const EngineDef cpu = testEngine(ComputeEngine::Cpu);
    const Snapshot start{scenario.world, 0, 0.0, 0, disksOf(scenario.particles), std::nullopt, {}};
    const Snapshot whole = runAndCheckpoint(cpu, start, 2000);
    const std::string file = std::string("cross-") + computeEngineName(def.engine) + ".ckpt";  // one per pipeline
    for (const auto& [first, second] : {std::pair{cpu, def}, std::pair{def, cpu}}) {
        CAPTURE(std::string(computeEngineName(first.engine)));
        writeCheckpoint(file, runAndCheckpoint(first, start, 1000));
        const Snapshot resumed = runAndCheckpoint(second, readCheckpoint(file), 1000);
        CHECK(resumed.collisions == whole.collisions);
        CHECK(sameBits(resumed.disks, whole.disks));
    }
    std::remove(file.c_str());
}

TEST_CASE("checkpoint: every truncation is refused") {
    const std::string bytes = small();
    for (std::size_t length = 0; length < bytes.size(); ++length) {
        CAPTURE(length);
        const std::string message = errorOf(bytes.substr(0, length));
        CHECK_MESSAGE(message.rfind("checkpoint 'c.ckpt': ", 0) == 0, message);
        if (length >= 8) CHECK_MESSAGE(message.find("truncated") != std::string::npos, message);
    }
    CHECK(errorOf(bytes).empty());
}

TEST_CASE("checkpoint: every flipped bit is refused") {
    const std::string bytes = small();
    for (std::size_t bit = 0; bit < bytes.size() * 8; ++bit) {
        std::string damaged = bytes;
        damaged[bit / 8] = static_cast<char>(damaged[bit / 8] ^ (1 << (bit % 8)));
        CAPTURE(bit);
        CHECK_FALSE(errorOf(damaged).empty());
    }
    std::string payload = bytes;
    payload[100] ^= 0x10;
    CHECK(errorOf(payload).find("checksum mismatch: the file is corrupted") != std::string::npos);
}

TEST_CASE("checkpoint: wrong files are refused with what is wrong") {
    const std::string bytes = small();
    std::string version = bytes;
    putU32(version, 12, 5);
    CHECK(errorOf(version).find("format version 5; this carom reads versions 1 to 4 (written by a newer carom?)") !=
          std::string::npos);
    putU32(version, 12, 0);
    CHECK(errorOf(version).find("format version 0; this carom reads versions 1 to 4") != std::string::npos);
    CHECK(errorOf(version).find("newer") == std::string::npos);

    std::string swapped = bytes;
    putU32(swapped, 8, 0x04030201);
    CHECK(errorOf(swapped).find("byte order is swapped (big-endian)") != std::string::npos);

    CHECK(errorOf("id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1,1\n").find("not a carom checkpoint") != std::string::npos);
    CHECK(errorOf(bytes + "x").find("trailing bytes") != std::string::npos);

    std::string count = bytes;
    count[16 + 7] = 0x7f;  // a particle count of about 9e18
    CHECK(errorOf(count).find("corrupted header: particle count") != std::string::npos);
    count = bytes;
    putU32(count, 16, 0);
    CHECK(errorOf(count).find("particle count 0 is outside 1..") != std::string::npos);

    CHECK_THROWS_WITH_AS(readCheckpoint("no-such.ckpt"), doctest::Contains("no such file"), Error);
    CHECK_THROWS_WITH_AS(readCheckpoint("."), doctest::Contains("not a regular file"), Error);
}

TEST_CASE("checkpoint: a valid checksum over invalid values is still refused") {
    Snapshot c;
    c.world = box(10, 10);
    c.disks = disksOf({disk(5, 5, 0, 0)});
    c.disks[0].position.x = NAN;
    CHECK(errorOf(encodeCheckpoint(c)).find("particle 0: position must be finite, got (nan, 5)") != std::string::npos);
    c.disks = disksOf({disk(5, 5, 0, 0)});
    c.world.dt = 0;
    CHECK(errorOf(encodeCheckpoint(c)).find("dt must be a finite number > 0") != std::string::npos);
    c.world.dt = 0.01f;
    c.time = -1;
    CHECK(errorOf(encodeCheckpoint(c)).find("time -1 must be a finite number >= 0") != std::string::npos);
    c.time = 0;
    std::string scheme = encodeCheckpoint(c);
    putU32(scheme, 72, 3);
    reseal(scheme);
    CHECK(errorOf(scheme).find("collision scheme code 3 is unknown in format version 4; allowed: 0 (simultaneous), "
                               "1 (pairwise), 2 (events)") != std::string::npos);
}

TEST_CASE("checkpoint: a failed write leaves the previous checkpoint in place") {
    Snapshot c;
    c.world = box(10, 10);
    c.disks = disksOf({disk(5, 5, 0, 0)});
    CHECK_THROWS_WITH_AS(writeCheckpoint("no-such-dir/c.ckpt", c), doctest::Contains("cannot write"), Error);
    writeCheckpoint("keep.ckpt", c);
    c.step = 5;
    c.time = 0.05;
    writeCheckpoint("keep.ckpt", c);  // replaces the old one whole
    CHECK(readCheckpoint("keep.ckpt").step == 5);
    for (const auto& entry : std::filesystem::directory_iterator("."))  // no temporary file left
        CHECK_FALSE(entry.path().filename().string().rfind("keep.ckpt.", 0) == 0);
    std::remove("keep.ckpt");
}
