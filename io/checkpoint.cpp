#include "io/checkpoint.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

#include <carom/files.h>

#include "engine/disk_conversion.h"
#include "engine/event_state.h"
#include "engine/scene.h"
#include "engine/snapshot_checks.h"
#include "io/output_paths.h"

namespace carom {
namespace {

constexpr char kMagic[8] = {'C', 'A', 'R', 'O', 'M', 'C', 'K', 'P'};
constexpr std::uint32_t kByteOrderMark = 0x01020304;
constexpr std::uint32_t kSwappedByteOrderMark = 0x04030201;
constexpr std::uint32_t kReflectiveWalls = 0;
constexpr std::uint32_t kPeriodic = 1;
constexpr std::uint32_t kSimultaneous = 0;
constexpr std::uint32_t kPairwise = 1;
constexpr std::uint32_t kEvents = 2;
constexpr std::uint32_t kOldestVersion = 1;
constexpr std::uint32_t kFirstEventsVersion = 3;
constexpr std::uint32_t kFirstImagesVersion = 4;
constexpr std::size_t kHeaderBytes = 76;
constexpr std::size_t kVersion1HeaderBytes = 72;  // no collision scheme
constexpr std::size_t kSchemeOffset = 72;
constexpr std::size_t kParticleBytes = 24;
constexpr std::size_t kImageBytes = 8;       // two int32
constexpr std::size_t kEventsTimeBytes = 8;  // the events state's time, before its disks
constexpr std::size_t kEventDiskBytes = 64;  // 6 float64, an int32 and 3 uint32
constexpr std::size_t kChecksumBytes = 4;
constexpr const char* kChecksumMismatch = "checksum mismatch: the file is corrupted (a flipped bit or a partial copy)";

// Little-endian writes, byte by byte, so the file is the same on every machine.
class Encoder {
public:
    void u32(std::uint32_t v) {
        for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<char>(v >> (8 * i)));
    }
    void u64(std::uint64_t v) {
        for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<char>(v >> (8 * i)));
    }
    void f32(float v) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        u32(bits);
    }
    void f64(double v) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        u64(bits);
    }
    void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
    std::string& bytes() { return bytes_; }

private:
    std::string bytes_;
};

// Little-endian reads from a buffer whose size the header checks have
// already confirmed.
class Decoder {
public:
    explicit Decoder(const unsigned char* data) : data_(data) {}
    std::uint32_t u32() { return static_cast<std::uint32_t>(take(4)); }
    std::uint64_t u64() { return take(8); }
    float f32() {
        const std::uint32_t bits = u32();
        float v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    double f64() {
        const std::uint64_t bits = u64();
        double v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
    void skip(std::size_t bytes) { position_ += bytes; }

private:
    std::uint64_t take(int bytes) {
        std::uint64_t v = 0;
        for (int i = 0; i < bytes; ++i) v |= std::uint64_t(data_[position_ + i]) << (8 * i);
        position_ += bytes;
        return v;
    }
    const unsigned char* data_;
    std::size_t position_ = 0;
};

[[noreturn]] void fail(const std::string& what, const std::string& problem) {
    throw Error("checkpoint '" + what + "': " + problem);
}

std::size_t headerBytes(std::uint32_t version) { return version == 1 ? kVersion1HeaderBytes : kHeaderBytes; }

// kMaxParticles keeps this far from overflowing.
std::uint64_t expectedSize(std::uint64_t particles, std::uint32_t version, bool events) {
    return headerBytes(version) + particles * kParticleBytes +
           (version >= kFirstImagesVersion ? particles * kImageBytes : 0) +
           (events ? kEventsTimeBytes + particles * kEventDiskBytes : 0) + kChecksumBytes;
}

struct Header {
    std::uint32_t version = 0;
    std::uint64_t count = 0;  // particles
    bool events = false;      // the events scheme's state follows the particles
};

// Checks what the first `available` bytes of a `fileSize`-byte file say
// about it, and returns its version and particle count. Refuses before
// anything sized by the count is allocated.
Header checkHeader(const unsigned char* data, std::size_t available, std::uint64_t fileSize, const std::string& what) {
    if (available < sizeof kMagic || std::memcmp(data, kMagic, sizeof kMagic) != 0)
        fail(what, "not a carom checkpoint (it does not start with \"CAROMCKP\")");
    if (available < 16)
        fail(what, "truncated: " + std::to_string(fileSize) + " bytes, shorter than a header (" +
                       std::to_string(kVersion1HeaderBytes) + " or " + std::to_string(kHeaderBytes) + " bytes)");
    Decoder header(data);
    header.skip(sizeof kMagic);
    const std::uint32_t mark = header.u32();
    if (mark == kSwappedByteOrderMark)
        fail(what,
             "its byte order is swapped (big-endian); carom checkpoints are little-endian on every "
             "machine, so this file was converted or written by another program");
    if (mark != kByteOrderMark) fail(what, "corrupted header: bad byte order mark");
    const std::uint32_t version = header.u32();
    if (version < kOldestVersion || version > kCheckpointVersion)
        fail(what, "format version " + std::to_string(version) + "; this carom reads versions " +
                       std::to_string(kOldestVersion) + " to " + std::to_string(kCheckpointVersion) +
                       (version > kCheckpointVersion ? " (written by a newer carom?)" : ""));
    if (available < headerBytes(version))
        fail(what, "truncated: " + std::to_string(fileSize) + " bytes, shorter than the " +
                       std::to_string(headerBytes(version)) + "-byte header");
    const std::uint64_t count = header.u64();
    if (count < 1 || count > kMaxParticles)
        fail(what, "corrupted header: particle count " + std::to_string(count) + " is outside 1.." +
                       std::to_string(kMaxParticles));
    // Only versions 3 and later hold the events state; the scheme code is checked after the checksum.
    Decoder scheme(data + kSchemeOffset);
    const bool events = version >= kFirstEventsVersion && scheme.u32() == kEvents;
    const std::uint64_t expected = expectedSize(count, version, events);
    const std::string particles = std::to_string(count) + " particles" + (events ? " and their events state" : "");
    if (fileSize < expected)
        fail(what, "truncated: " + std::to_string(fileSize) + " bytes, but " + particles + " need " +
                       std::to_string(expected));
    if (fileSize > expected)
        fail(what, std::to_string(fileSize) + " bytes, but " + particles + " need " + std::to_string(expected) +
                       ": trailing bytes (corrupted?)");
    return Header{version, count, events};
}

void encodeEvents(Encoder& out, const EventEngineState& state) {
    out.f64(state.time);
    for (const EventDiskState& d : state.disks) {
        for (double v : {d.x, d.y, d.vx, d.vy, d.time, d.eventTime}) out.f64(v);
        out.i32(d.event);
        for (std::uint32_t v : {d.partnerCollisions, d.collisions, d.cell}) out.u32(v);
    }
}

EventEngineState decodeEvents(Decoder& in, std::size_t count) {
    EventEngineState state;
    state.time = in.f64();
    state.disks.resize(count);
    for (EventDiskState& d : state.disks) {
        for (double* v : {&d.x, &d.y, &d.vx, &d.vy, &d.time, &d.eventTime}) *v = in.f64();
        d.event = in.i32();
        for (std::uint32_t* v : {&d.partnerCollisions, &d.collisions, &d.cell}) *v = in.u32();
    }
    return state;
}

}  // namespace

std::uint32_t crc32(const unsigned char* data, std::size_t size) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int bit = 0; bit < 8; ++bit) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    std::uint32_t crc = 0xFFFFFFFFu;
    for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
    return crc ^ 0xFFFFFFFFu;
}

std::string encodeCheckpoint(const Snapshot& c) {
    Encoder out;
    if (const std::string problem = eventStatePlaceProblem(c); !problem.empty()) throw Error(problem);
    const bool events = c.events.has_value();
    out.bytes().reserve(expectedSize(c.disks.size(), kCheckpointVersion, events));
    out.bytes().append(kMagic, sizeof kMagic);
    out.u32(kByteOrderMark);
    out.u32(kCheckpointVersion);
    out.u64(c.disks.size());
    for (float v : {c.world.width, c.world.height, c.world.dt, c.world.gravity.x, c.world.gravity.y}) out.f32(v);
    out.u32(c.world.boundary == Boundary::Periodic ? kPeriodic : kReflectiveWalls);
    out.u64(c.step);
    out.f64(c.time);
    out.u64(c.collisions);
    out.u32(events ? kEvents : c.world.collisions == CollisionScheme::Pairwise ? kPairwise : kSimultaneous);
    for (const Disk& d : c.disks)
        for (float v : {d.position.x, d.position.y, d.velocity.x, d.velocity.y, d.mass, d.radius}) out.f32(v);
    if (!c.images.empty() && c.images.size() != c.disks.size())
        throw Error(std::to_string(c.images.size()) + " images for " + std::to_string(c.disks.size()) +
                    " disks; allowed: one per disk, or none (all {0, 0})");
    for (std::size_t i = 0; i < c.disks.size(); ++i)
        for (int axis = 0; axis < 2; ++axis) out.i32(c.images.empty() ? 0 : c.images[i][axis]);
    if (events) encodeEvents(out, *c.events);
    const std::string& bytes = out.bytes();
    out.u32(crc32(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()));
    return std::move(out.bytes());
}

Snapshot decodeCheckpoint(const std::string& bytes, const std::string& what) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const Header header = checkHeader(data, bytes.size(), bytes.size(), what);
    const std::size_t checked = bytes.size() - kChecksumBytes;
    Decoder trailer(data + checked);
    if (trailer.u32() != crc32(data, checked)) fail(what, kChecksumMismatch);

    Decoder in(data);
    in.skip(24);  // magic, byte order mark, version, count
    Snapshot c;
    c.world.width = in.f32();
    c.world.height = in.f32();
    c.world.dt = in.f32();
    c.world.gravity.x = in.f32();
    c.world.gravity.y = in.f32();
    const std::uint32_t boundary = in.u32();
    c.step = in.u64();
    c.time = in.f64();
    c.collisions = in.u64();
    const std::uint32_t scheme = header.version == 1 ? kSimultaneous : in.u32();
    c.disks.resize(header.count);
    for (Disk& d : c.disks) {
        d.position.x = in.f32();
        d.position.y = in.f32();
        d.velocity.x = in.f32();
        d.velocity.y = in.f32();
        d.mass = in.f32();
        d.radius = in.f32();
    }
    if (header.version >= kFirstImagesVersion) {
        c.images.resize(header.count);
        for (Image& image : c.images) image = {in.i32(), in.i32()};
    }
    if (header.events) c.events = decodeEvents(in, header.count);

    // A valid checksum over invalid values: written by something other than carom.
    if (boundary != kReflectiveWalls && boundary != kPeriodic)
        fail(what,
             "boundary code " + std::to_string(boundary) + " is unknown; allowed: 0 (reflective walls), 1 (periodic)");
    c.world.boundary = boundary == kPeriodic ? Boundary::Periodic : Boundary::Walls;
    if (scheme != kSimultaneous && scheme != kPairwise && !header.events)
        fail(what, "collision scheme code " + std::to_string(scheme) + " is unknown in format version " +
                       std::to_string(header.version) + "; allowed: 0 (simultaneous), 1 (pairwise)" +
                       (header.version >= kFirstEventsVersion ? ", 2 (events)" : ""));
    c.world.collisions = header.events         ? CollisionScheme::Events
                         : scheme == kPairwise ? CollisionScheme::Pairwise
                                               : CollisionScheme::Simultaneous;
    if (const std::string problem = snapshotCountsProblem(c); !problem.empty()) fail(what, problem);
    try {
        validateParticles(particlesOf(c.disks.data(), c.disks.size()), c.world, "particles");
    } catch (const Error& e) {
        fail(what, e.what());
    }
    if (c.events)
        if (const std::string problem = eventStateProblem(*c.events, c.world.boundary); !problem.empty())
            fail(what, problem);
    return c;
}

void writeCheckpoint(const std::string& path, const Snapshot& snapshot) {
    const std::string bytes = encodeCheckpoint(snapshot);
    io::AtomicFile file(path);
    file.append(bytes);
    file.commit();
}

Snapshot readCheckpoint(const std::string& path, std::uint64_t availableBytes) {
    std::streamoff size = 0;
    std::ifstream in = openRegularFile(path, "checkpoint", size);
    unsigned char header[kHeaderBytes];
    in.read(reinterpret_cast<char*>(header), kHeaderBytes);
    const Header checked =
        checkHeader(header, static_cast<std::size_t>(in.gcount()), static_cast<std::uint64_t>(size), path);
    // The count is held against the file size (checkHeader) and the memory
    // available before the file is read; decodeCheckpoint checks the
    // checksum before it decodes a particle.
    requireRoomFor(checked.count, "checkpoint '" + path + "'", availableBytes);
    in.clear();

    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.seekg(0);
    if (!in.read(bytes.data(), size)) throw Error("reading checkpoint '" + path + "' failed");
    return decodeCheckpoint(bytes, path);
}

}  // namespace carom
