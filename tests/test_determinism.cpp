// Pinned trajectories (Box2D's determinism test): a fixed scene of 300
// polydisperse disks, stepped 500 steps with each collision scheme, in a
// walled box under gravity and in a periodic one, and with adaptive
// substeps in the walled box, hashed (the final state and
// the contact totals), and the hash compared with a constant written below.
// The differential tests catch a backend that drifts from the CPU; these
// catch a change of results on all backends alike.
//
// Where the OpenCL device rounds divide and sqrt correctly
// (Backend::exactArithmetic), its hash must equal the CPU's pinned constant;
// where not, the test says so and checks only that two runs on the device
// agree. The events scheme runs on the CPU only.
//
// Re-pinning: a change that alters results on purpose fails here with the
// new hash in the message (run `build/tests/carom_tests -tc='determinism*'`).
// Copy it into kPinned, and say in the commit message why the results
// changed (which physics or rounding, and that the differential and
// conservation tests still pass). A re-pin without that justification is a
// regression, not an update.
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <string>

#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

struct Pinned {
    CollisionScheme scheme;
    Boundary boundary;
    float maxTravel;     // > 0: adaptive substeps (WorldDef::maxTravel), whose count the hash includes
    std::uint64_t hash;  // trajectoryHash of the fixed scene after kSteps steps
};

// The CPU's hashes, which an OpenCL device with exact arithmetic must equal.
constexpr Pinned kPinned[] = {
    {CollisionScheme::Simultaneous, Boundary::Walls, 0.0f, 0xf9c06c893c95a36eull},
    {CollisionScheme::Simultaneous, Boundary::Periodic, 0.0f, 0x608e930d47e1d23full},
    {CollisionScheme::Simultaneous, Boundary::Walls, 0.05f, 0xa585a8230d2b0aa7ull},
    {CollisionScheme::Pairwise, Boundary::Walls, 0.0f, 0xf53183987e64d6d5ull},
    {CollisionScheme::Pairwise, Boundary::Periodic, 0.0f, 0x21dda79dbc0237d0ull},
    {CollisionScheme::Pairwise, Boundary::Walls, 0.05f, 0x8269b64c77b61867ull},
    {CollisionScheme::Events, Boundary::Walls, 0.0f, 0x75c5b5bb854b73c3ull},
    {CollisionScheme::Events, Boundary::Periodic, 0.0f, 0xf3aa5687efa1d189ull},
};

constexpr std::uint64_t kSteps = 500;
constexpr int kColumns = 20, kRows = 15;
constexpr float kPitch = 2.25f;  // lattice spacing, more than the largest diameter 2

// FNV-1a, 64 bits, fed byte by byte in little-endian order whatever the host's.
class Fnv1a {
public:
    void add(std::uint64_t value, int bytes) {
        for (int i = 0; i < bytes; ++i) {
            hash_ ^= (value >> (8 * i)) & 0xff;
            hash_ *= 0x100000001b3ull;
        }
    }
    void add(float value) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &value, sizeof bits);
        add(bits, 4);
    }
    void add(double value) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &value, sizeof bits);
        add(bits, 8);
    }
    std::uint64_t value() const { return hash_; }

private:
    std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

// 300 disks on a 20 x 15 lattice; radius, mass and velocity cycle with the
// index over coprime periods (17, 13, 41, 37). Every value is a small
// multiple of a power of two, exact in float, so the scene is the same bits
// on any compiler and host, and it depends on no scene generator.
std::vector<Particle> fixedScene() {
    std::vector<Particle> disks;
    for (int i = 0; i < kColumns * kRows; ++i) {
        const float x = kPitch / 2 + kPitch * float(i % kColumns), y = kPitch / 2 + kPitch * float(i / kColumns);
        const float radius = 0.5f + float((i * 7) % 17) / 32;                                // 0.5 to 1
        const float mass = 0.5f + float((i * 11) % 13) / 4;                                  // 0.5 to 3.5
        const float vx = float((i * 13) % 41 - 20) / 8, vy = float((i * 29) % 37 - 18) / 8;  // up to 2.5
        disks.push_back(disk(x, y, vx, vy, mass, radius));
    }
    return disks;
}

WorldDef fixedWorld(const Pinned& pinned) {
    WorldDef world = box(kPitch * kColumns, kPitch * kRows, 0.01f);
    world.collisions = pinned.scheme;
    world.boundary = pinned.boundary;
    world.maxTravel = pinned.maxTravel;
    if (pinned.boundary == Boundary::Walls) world.gravity = float2{0.0f, -1.0f};
    return world;
}

std::string hex(std::uint64_t value) {
    std::ostringstream text;
    text << "0x" << std::hex << std::setw(16) << std::setfill('0') << value << "ull";
    return text.str();
}

// The hash of the disks' positions, velocities, masses and radii in id order
// and of the contact totals (collisions, virial, wall impulses, substeps,
// late contacts, rounds), after kSteps steps of the fixed scene.
std::uint64_t trajectoryHash(Backend& backend) {
    backend.setParticles(fixedScene());
    backend.step(kSteps);
    std::vector<Particle> disks;
    backend.readParticles(disks);
    const std::uint64_t collisions = backend.collisions();
    CHECK(collisions > 1000);  // the scene exercises the collisions, not just the flight
    Fnv1a hash;
    for (const Particle& p : disks) {
        for (float value : {p.position.x, p.position.y, p.velocity.x, p.velocity.y, p.mass, p.radius}) hash.add(value);
    }
    const ContactTotals& totals = backend.contacts();
    if (backend.world().maxTravel > 0.0f) CHECK(totals.substeps > kSteps);  // the substeps are exercised
    hash.add(collisions, 8);
    hash.add(totals.virial);
    for (double impulse : totals.wallImpulse) hash.add(impulse);
    hash.add(totals.substeps, 8);
    hash.add(totals.lateContacts, 8);
    hash.add(totals.maxRounds, 4);
    return hash.value();
}

void checkPinned(const EngineDef& def, CollisionScheme scheme) {
    for (const Pinned& pinned : kPinned) {
        if (pinned.scheme != scheme) continue;
        CAPTURE(std::string(boundaryName(pinned.boundary)));
        CAPTURE(pinned.maxTravel);
        const WorldDef world = fixedWorld(pinned);
        auto backend = makeBackend(def, world);
        const std::uint64_t hash = trajectoryHash(*backend);
        if (backend->exactArithmetic()) {
            CHECK_MESSAGE(hash == pinned.hash, "trajectory hash " << hex(hash) << ", pinned " << hex(pinned.hash)
                                                                  << " (re-pinning: the comment at the top)");
        } else {
            MESSAGE("the device lacks correctly rounded divide/sqrt: its hash "
                    << hex(hash) << " is checked for repeatability only");
            CHECK(trajectoryHash(*makeBackend(def, world)) == hash);
        }
    }
}

}  // namespace

CAROM_BACKEND_TEST_CASE("determinism: the simultaneous scheme's trajectory of a fixed scene has the pinned hash") {
    checkPinned(def, CollisionScheme::Simultaneous);
}

CAROM_BACKEND_TEST_CASE("determinism: the pairwise scheme's trajectory of a fixed scene has the pinned hash") {
    checkPinned(def, CollisionScheme::Pairwise);
}

TEST_CASE("determinism: the events scheme's trajectory of a fixed scene has the pinned hash (CPU)") {
    checkPinned(testEngine(ComputeEngine::Cpu), CollisionScheme::Events);
}

TEST_CASE("determinism: the hash is FNV-1a 64") {
    // Of no bytes and of "a", from the specification's test vectors.
    CHECK(Fnv1a().value() == 0xcbf29ce484222325ull);
    Fnv1a a;
    a.add('a', 1);
    CHECK(a.value() == 0xaf63dc4c8601ec8cull);
}

// makeScene draws its numbers block by block and places the disks of a block
// in parallel: 200 000 disks (several blocks) land where one loop over them
// put them (the hash pinned before the change), whatever the threads.
TEST_CASE("determinism: a scene of 200 000 disks is placed with the pinned hash") {
    SceneDef scene;
    scene.particles = 200000;
    scene.packing = 0.5f;
    scene.radiusMin = 0.5f;
    scene.radiusMax = 1.0f;
    scene.massMin = 1.0f;
    scene.massMax = 3.0f;
    scene.seed = 7;
    const InitialState s = makeInitialState(scene);
    Fnv1a hash;
    for (const Particle& p : s.particles)
        for (float value : {p.position.x, p.position.y, p.velocity.x, p.velocity.y, p.mass, p.radius}) hash.add(value);
    hash.add(s.width);
    hash.add(s.height);
    CHECK_MESSAGE(hash.value() == 0x65750179c6a294edull, "placement hash " << hex(hash.value()));
}
