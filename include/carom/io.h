// carom::io (link carom::io): reading and writing carom's files with the
// public types. The formats are the README's: scene files ("Scene files"),
// state CSV (`id,x,y,vx,vy,mass,radius`, floats as the shortest text that
// reads back bit for bit), checkpoints ("Checkpoints": a versioned binary
// file with a checksum), trajectories (extended XYZ) and statistics (CSV).
//
// Files are written whole or not at all: through a temporary file renamed
// into place, so a failure leaves the old file as it was. Every refusal is a
// carom::Error naming the file, the line and what is allowed (carom/files.h
// has the file writing itself, for a program's own outputs).
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <memory>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include <carom/types.h>
#include <carom/world.h>

namespace carom::io {

/// A scene file read and validated, its disks not yet placed (makeScene
/// places them, carom/world.h): throws Error naming the file, the line, the
/// key, the bad value and what is allowed. parseSceneFile reads TOML text,
/// which `path` names in messages.
SceneFileDef readSceneFile(const std::string& path);
SceneFileDef parseSceneFile(std::string_view text, const std::string& path);

/// A scene file read, validated and placed, as `carom run --scene` places it:
/// the world it defines and its disks in id order (the groups' disks, then
/// the [[disk]]s).
struct SceneFile {
    WorldDef world;  ///< the definition's box (sized by its packing if need be), dt, gravity,
                     ///<   boundary, collisions, maxTravel, engine and device (a file's: Cpu, "")
    std::vector<Disk> disks;
    std::uint64_t steps = 1000;  ///< the steps `carom run` would take
};
/// Throws Error naming the file: for what readSceneFile refuses, for disks
/// more than the memory available now holds (requireRoomFor, carom/types.h,
/// checked before they are placed), for a group or disk that cannot be placed
/// and for a world out of range (validate).
SceneFile loadScene(const std::string& path);
/// The same for a scene file already read (readSceneFile) and then changed by
/// the caller, as the command line's options override the file's values.
SceneFile loadScene(const SceneFileDef& scene);

/// A state CSV: the disks, in id order. The file's ids must be exactly
/// 0..N-1, in any row order; the box is not checked here (World::setDisks does).
/// writeState throws Error, writing nothing, for no disks or a value that is
/// not finite: it writes only what readState reads back.
std::vector<Disk> readState(const std::string& path);
void writeState(const std::string& path, const std::vector<Disk>& disks);
/// The world's disks, read a piece at a time (no copy of them all).
void writeState(const std::string& path, const World& world);

/// Checkpoints: everything a world needs to continue bit for bit, its
/// snapshot (World::snapshot: the box, dt, gravity, boundary, scheme, step,
/// time, collision count, the disks, and with CollisionScheme::Events the
/// engine's exact double state), in a versioned binary file with a checksum.
/// loadCheckpoint takes the engine, the device, maxTravel, skin and
/// decomposition from `def` (a checkpoint does not hold them) and everything else from the file, which
/// it restores (World::restore); it refuses a file that is damaged, of
/// another format or out of range, naming what is wrong, and one whose disks
/// the memory available now cannot hold (requireRoomFor, carom/types.h); so
/// does readState.
void saveCheckpoint(const std::string& path, const World& world);
World loadCheckpoint(const std::string& path, const WorldDef& def = WorldDef{});

/// A checkpoint read and checked but not started, for a program that looks
/// at what it holds before it chooses the engine (CollisionScheme::Events
/// runs on the CPU only): readCheckpoint, then loadCheckpoint(std::move(file), def).
/// loadCheckpoint spends it: a moved-from CheckpointFile may only be
/// assigned to or destroyed, and loading it again throws Error.
class CheckpointFile {
public:
    ~CheckpointFile();
    CheckpointFile(CheckpointFile&&) noexcept;
    CheckpointFile& operator=(CheckpointFile&&) noexcept;

    /// Its box, dt, gravity, boundary and scheme (engine Cpu, device empty,
    /// maxTravel 0: a checkpoint does not hold them).
    const WorldDef& world() const;
    std::uint64_t step() const;  ///< the step it holds
    std::size_t diskCount() const;
    /// All it holds, for World::restore (world.engine, device and maxTravel
    /// as world() says).
    const Snapshot& snapshot() const;

private:
    struct Impl;
    explicit CheckpointFile(std::unique_ptr<Impl> impl);
    friend CheckpointFile readCheckpoint(const std::string& path);
    friend World loadCheckpoint(CheckpointFile checkpoint, const WorldDef& def);
    std::unique_ptr<Impl> impl_;
};
CheckpointFile readCheckpoint(const std::string& path);
World loadCheckpoint(CheckpointFile checkpoint, const WorldDef& def = WorldDef{});

/// Trajectories as extended XYZ (README, "Output files"), which OVITO and ASE
/// read: write() adds a frame of the world's disks at its stepCount() and
/// time(). The frames stream into a temporary file beside `path`, renamed
/// into place by close(); a writer destroyed without close() leaves `path`
/// as it was. Throws Error, naming the file, when it cannot be opened or a
/// write fails (a full disk), and for a world without disks.
class TrajectoryWriter {
public:
    explicit TrajectoryWriter(const std::string& path);
    /// Continues the trajectory at `path` that a run wrote up to the step
    /// `resumed` holds (a world loaded from that run's checkpoint). Refuses a
    /// file whose last frame is after that step, or of another simulation:
    /// another disk count, box or boundary, other radii, masses or ids, or
    /// (at that step) another time. With `every` > 0, the steps between the
    /// samples, it refuses a file whose last frame is before the last
    /// multiple of `every` up to that step, too: samples would be missing.
    /// Refusals call `resumed` `resumedName` ("its last frame is at step 20,
    /// after the world's step 10"): "the checkpoint" where it came from one.
    TrajectoryWriter(const std::string& path, const World& resumed, std::uint64_t every = 0,
                     const std::string& resumedName = "the world");
    ~TrajectoryWriter();
    TrajectoryWriter(TrajectoryWriter&&) noexcept;
    TrajectoryWriter& operator=(TrajectoryWriter&&) noexcept;

    void write(const World& world);
    std::size_t frames() const;  ///< written by this writer
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Statistics as CSV, a row per write(): step, time, kinetic energy,
/// momentum, collisionCount(), the deepest overlap and the disks outside the
/// box (README, "Output files"). Written and closed as TrajectoryWriter.
class StatisticsWriter {
public:
    explicit StatisticsWriter(const std::string& path);
    /// Continues the statistics at `path` up to the step `resumed` holds,
    /// refusing a file as TrajectoryWriter does (its last row after that step,
    /// or before its last sample; more collisions than `resumed` counts, or
    /// at its step another time or count).
    StatisticsWriter(const std::string& path, const World& resumed, std::uint64_t every = 0,
                     const std::string& resumedName = "the world");
    ~StatisticsWriter();
    StatisticsWriter(StatisticsWriter&&) noexcept;
    StatisticsWriter& operator=(StatisticsWriter&&) noexcept;

    void write(const World& world);
    std::size_t rows() const;  ///< written by this writer
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Text as carom's files hold it, for a program that reads the same from
// its users. Numbers are read strictly, as a person types them: the whole
// text must be the number, and a whole number must lie in its range. Nothing
// wraps around ("-1" is not 2^64 - 1), nothing is octal or hexadecimal, and
// an empty text is not 0.

/// Text files a person gives a program (carom's state CSV, scene files and
/// `view --events` scripts are read so), bounded whatever the file: a device
/// such as /dev/zero, a binary file, a FIFO nobody writes to.

/// Longer than any line of carom's text inputs (a state row of seven floats
/// in their longest spelling is under 200 bytes): a longer line is refused as
/// it is read, so a file without newlines cannot fill memory.
constexpr std::size_t kMaxTextLineBytes = 4096;

/// A FIFO nobody writes to is waited on this long, then refused.
constexpr int kFifoWaitSeconds = 10;

/// A text input file opened for reading. `what` names it in messages ("state
/// file"). Refuses (Error naming the file) a folder and a file that cannot be
/// opened; a FIFO (or a pipe from process substitution, <(...)) is read once
/// data arrives or its writer closes it, within kFifoWaitSeconds; devices and
/// regular files are read as they are. A read error throws Error.
class TextFile {
public:
    TextFile(const std::string& path, const std::string& what);
    ~TextFile();
    TextFile(const TextFile&) = delete;
    TextFile& operator=(const TextFile&) = delete;

    std::istream& stream() { return in_; }

    /// The whole file; refuses one of more than `maxBytes` bytes, or with a
    /// NUL byte, before reading more.
    std::string readAll(std::size_t maxBytes);

private:
    std::string path_, what_;
    std::unique_ptr<std::streambuf> buffer_;
    std::istream in_;
};

/// The lines of a text stream, each refused (Error "PATH:LINE: ...") when it
/// is longer than kMaxTextLineBytes or holds a NUL byte, before more of it is
/// stored. `what` says what the file should be ("state file").
class TextLines {
public:
    TextLines(std::istream& in, std::string path, std::string what);

    /// The next line, without its newline; false at the end.
    bool next(std::string& line);
    /// The number of the line next() returned last, counting from 1.
    std::size_t number() const { return number_; }

private:
    std::istream& in_;
    std::string path_, what_;
    std::size_t number_ = 0;
    char buffer_[kMaxTextLineBytes + 1];  // a line and the terminating zero getline writes
};

/// "allowed: whole numbers from 1 to 1000": the range in a refusal.
std::string wholeNumbersAllowed(std::uint64_t min, std::uint64_t max);

/// The number `text` spells in decimal digits. Throws Error naming the text
/// and the range when it is not one ("'' is not a whole number; allowed:
/// ...") or lies outside [min, max] ("'-1' is out of range; allowed: ...").
std::uint64_t parseWholeNumber(std::string_view text, std::uint64_t min, std::uint64_t max);

/// The number `text` spells in decimal ("2", "-0.5", "1e-3", ".5"), or inf,
/// infinity or nan in any case: throws Error "'0x10' is not a number;
/// allowed: ..." for an empty text, hexadecimal, a leading '+' or space, or
/// anything after the number. Ranges are the caller's to check.
double parseRealNumber(std::string_view text);

/// The same number as the 32-bit float nearest it, carom's precision; also
/// throws Error, naming the text, where the float would be another number:
/// a number other than 0 below 1.4e-45 (it would read as 0), a finite number
/// beyond 3.4e38 (it would read as infinite).
float parseFloat(std::string_view text);

/// `value` as a 32-bit float, refused as parseFloat refuses, naming the value.
float toFloat(double value);

/// The shortest decimal that reads back to the same bits, whatever the C
/// locale's decimal point: 0.1f is "0.1", never "0.100000001" or "0,1".
std::string shortestText(float value);
std::string shortestText(double value);

/// A value from an input file as a message shows it: at most 40 characters;
/// valid UTF-8 as it is ("café"), control characters (C0, DEL, C1) and
/// invalid bytes as `\xNN`, so a binary or huge file cannot flood or drive the
/// terminal.
std::string printable(std::string_view text);

}  // namespace carom::io
