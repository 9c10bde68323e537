// carom::World: a box of disks that steps forward in time.
//
//     carom::WorldDef def;                       // carom/types.h: every field documented
//     def.width = def.height = 100.0f;
//     carom::World world(def);                   // throws carom::Error for a bad definition
//     world.setDisks(carom::makeScene(scene).disks);
//     world.step(1000);
//     double e = world.kineticEnergy();
//
// A World is not thread-safe: call it from one thread at a time (the const
// observables too: they cache the state read from the device). A moved-from
// World may only be assigned to or destroyed. Every refusal is a
// carom::Error whose message names the value and what is allowed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <carom/types.h>

namespace carom {

/// A gas made by makeScene: the box it fills and its disks, in id order.
struct Scene {
    float width = 0.0f;   ///< [length]
    float height = 0.0f;  ///< [length]
    std::vector<Disk> disks;
};

/// Places the disks of `def` (carom/types.h SceneDef); deterministic in
/// def.seed on every platform. Throws Error when the ranges are invalid or the
/// packing cannot be reached.
Scene makeScene(const SceneDef& def);
/// Places a scene file's disks (carom/types.h SceneFileDef): the groups'
/// disks in group order (ids 0, 1, ...), then the [[disk]]s, in a box of the
/// file's size or sized by its packing; deterministic in def.seed. Throws
/// Error naming the file and the group or disk that cannot be placed.
Scene makeScene(const SceneFileDef& def);

/// What the collisions and the walls did over an interval of simulated time:
/// since World::setDisks, or since the last World::resetMeasurements.
struct Measurements {
    double time = 0.0;             ///< simulated time covered [time]
    std::uint64_t steps = 0;       ///< steps taken
    std::uint64_t collisions = 0;  ///< pairs that received an impulse, each pair once
    double collisionRate = 0.0;    ///< collisions per disk per unit time [1/time] (a disk's own rate
                                   ///<   is twice this); 0 while no time has passed
    double temperature = 0.0;      ///< kT (k = 1), the mean of the interval's first and last
                                   ///<   [mass length^2/time^2]
    /// Pressure [mass/time^2] and Z = P A / (N kT). In a periodic box from the
    /// collision virial (exact); with walls from the momentum the walls
    /// received over the perimeter. 0 while no time has passed.
    double pressure = 0.0;
    double compressibility = 0.0;
    /// The collisions' share of the pressure: the sum over the interval's
    /// impulses of r_ij . J_ij [mass length^2/time], so that P A is
    /// (N - 1) kT + collisionVirial / (2 time) in a periodic box (N kT with walls).
    double collisionVirial = 0.0;
    std::array<double, 4> wallPressure{};  ///< walls only: left, right, bottom, top [mass/time^2]
    std::uint64_t substeps = 0;            ///< substeps taken: more than steps with maxTravel > 0, or where the
                                           ///<   pairwise scheme splits a step to keep its grid valid
    /// Pairwise scheme only: pairs resolved while overlapping beyond rounding and
    /// disks found past a wall (contacts the rounds could not order in time),
    /// and the most collision rounds one substep used.
    std::uint64_t lateContacts = 0;
    std::uint32_t maxRounds = 0;
};

/// Whether this build has `engine` (ComputeEngine::Cpu always; the OpenCL
/// engines when carom was built with OpenCL, whatever devices there are).
bool engineAvailable(ComputeEngine engine);

/// The library's version, "MAJOR.MINOR.PATCH": CAROM_VERSION (carom/version.h)
/// of the carom that was linked, which may differ from the headers'.
const char* version();

/// An OpenCL device the OpenCL engines can run on.
struct Device {
    int index = 0;                  ///< its position in listDevices(), across all platforms: a WorldDef::device
    std::string name;               ///< the device's name (part of it is a WorldDef::device too)
    std::string platform;           ///< the OpenCL platform's name
    std::string type;               ///< "GPU", "CPU", "accelerator", ...
    std::string version;            ///< the device's OpenCL version
    std::uint64_t memoryBytes = 0;  ///< global memory [bytes]
    bool correctlyRoundedDivideSqrt = false;  ///< whether results are bitwise the CPU engine's there
};

/// Every OpenCL device of every platform. Throws Error when this build has no
/// OpenCL, or the machine no OpenCL platform or device.
std::vector<Device> listDevices();
/// The device WorldDef::device = `selector` runs on (empty: the first GPU,
/// else the first device). Throws Error, as World's constructor does, when
/// none matches or this build has no OpenCL.
Device findDevice(const std::string& selector);
/// The OpenCL engine that runs fastest on `device`, the choice of the command
/// line's --pipeline auto: ComputeEngine::OpenClResident on a GPU,
/// OpenClHostGrid on other devices (on a CPU device such as PoCL the
/// host-grid pipeline's transfers are memory copies, and it is the faster).
/// Both give the same bits.
ComputeEngine openClEngineFor(const Device& device);

/// The engine chosen for a world that names none (the command line's
/// --backend auto, Python's engine="auto"), and why, in words.
struct EngineChoice {
    EngineDef engine;
    std::string reason;
};
/// The rule, on the devices `devices` (as listDevices() gives them): the
/// first GPU, on openClEngineFor's pipeline; without a GPU the CPU engine,
/// which outruns OpenCL on a CPU device (PoCL: 2-3 times slower).
EngineChoice chooseEngine(const std::vector<Device>& devices);
/// The rule on this machine's devices: none where this build has no OpenCL
/// or the machine no OpenCL platform.
EngineChoice chooseEngine();

/// The disks where the CPU engine keeps them, for reading without a copy
/// (World::diskMemory): `count` records of `stride` floats from `base`, in id
/// order, each holding position x, y, velocity x, y, mass and radius at the
/// offsets below (the rest of a record is the engine's). `owner` keeps the
/// memory alive, whatever the world does: while a DiskMemory holds it, steps
/// and edits that keep the number of disks write into it (it follows the
/// world); setDisks or addDisks of another number leave it as it was.
struct DiskMemory {
    std::shared_ptr<const void> owner;
    const float* base = nullptr;  ///< null where the engine keeps no such memory
    std::size_t count = 0;
    std::size_t stride = 0;  ///< [floats]
    static constexpr std::size_t kPosition = 0;
    static constexpr std::size_t kVelocity = 2;
    static constexpr std::size_t kMass = 4;
    static constexpr std::size_t kRadius = 5;
};

/// The disks one process steps (World::ownDisks), in id order: position,
/// velocity, mass and radius as disks() gives them, and each disk's id and
/// periodic image (World::images).
struct OwnDisks {
    std::vector<std::uint32_t> ids;
    std::vector<Disk> disks;
    std::vector<Image> images;
};

class World {
public:
    /// Checks every field of `def` (finite, in range, an engine this build
    /// has, a device that exists) and starts the engine; throws Error otherwise.
    explicit World(const WorldDef& def);
    ~World();
    World(World&&) noexcept;
    World& operator=(World&&) noexcept;

    /// Replaces every disk. Disk i gets id i. Throws Error, and keeps the
    /// disks it had, when `disks` is null, a disk is out of range or outside the box, two
    /// centres coincide, the step is out of range for their speeds, or (with
    /// DeepOverlaps::Refuse) two disks overlap deeper than a step closes.
    /// Resets the step count, the time and the measurements. `source` names
    /// the disks in errors and warnings (a file they came from).
    void setDisks(const Disk* disks, std::size_t count, const std::string& source = "disks",
                  DeepOverlaps deepOverlaps = DeepOverlaps::Warn);
    void setDisks(const std::vector<Disk>& disks, const std::string& source = "disks",
                  DeepOverlaps deepOverlaps = DeepOverlaps::Warn) {
        setDisks(disks.data(), disks.size(), source, deepOverlaps);
    }
    /// What the last setDisks or restore found less accurate or slower than
    /// usual, though allowed: a step of few float spacings, disks overlapping
    /// deeper than a step closes (than rounding, in the events scheme), a
    /// step that can carry two disks through each other (simultaneous
    /// scheme), one disk so large that the grid's cells hold far too many.
    const std::vector<std::string>& warnings() const;

    /// Everything the world needs to continue bit for bit (carom/types.h
    /// Snapshot): its definition, step, time, collision count, disks and images, and
    /// with CollisionScheme::Events the engine's exact double state.
    Snapshot snapshot() const;
    /// Continues from `snapshot`, taken of this world or of another with the
    /// same box, boundary and collision scheme, on any engine: replaces every
    /// disk, the step, the time, the collision count, dt and gravity, keeps
    /// the engine, the device and maxTravel, and restarts the measurements.
    /// Stepping on then gives bit for bit what stepping the snapshot's world
    /// gave, on the same engine, and across engines where both are
    /// bitwiseReproducible() (maxTravel as that world's). Throws Error,
    /// leaving the world as it was, for a snapshot of another box, boundary
    /// or scheme, dt or gravity out of range, a disk setDisks refuses, a time
    /// that `step` steps of a dt in [kMinDt, kMaxDt] cannot add up to (0 at
    /// step 0), more than 2^63 collisions, images not one per disk (or none)
    /// or other than {0, 0} in a box with walls, or an events state that does
    /// not fit the disks (present exactly with the events scheme; every value,
    /// event, partner and cell checked, and no two centres equal); `source`
    /// names the snapshot in messages
    /// (a file it came from).
    void restore(const Snapshot& snapshot, const std::string& source = "snapshot");

    /// Edits between steps, for a hand that drags, throws or drops disks:
    /// replaces disk `id`, or appends disks (ids diskCount(), ...). The step
    /// count and collisionCount() go on; the measurements' interval restarts.
    /// The disks are checked for range and for lying inside the box, not for
    /// overlaps (the next steps push overlapping disks apart). Throws Error,
    /// keeping the disks as they were, for an id out of range, a bad disk or
    /// a null `disks`.
    void setDisk(std::size_t id, const Disk& disk);
    void addDisks(const Disk* disks, std::size_t count);
    /// Replaces every disk at once, as setDisk does one: `count` must be diskCount().
    void editDisks(const Disk* disks, std::size_t count);

    /// Copies the disks, in id order, into `out`, which has room for
    /// `capacity`; throws Error when that is less than diskCount(), or `out`
    /// is null with a capacity.
    void getDisks(Disk* out, std::size_t capacity) const;
    /// Copies the disks with ids [first, first + count) into `out`: a large
    /// state a piece at a time (the writers in carom/io.h stream it so).
    /// Throws Error when the range passes diskCount(), or `out` is null with
    /// a count.
    void getDisks(std::size_t first, std::size_t count, Disk* out) const;
    std::vector<Disk> disks() const;
    std::size_t diskCount() const;
    /// What a renderer needs of every disk, in the order the engine keeps them
    /// (not by id: no reordering, and on a GPU only these 16 bytes a disk are
    /// read back), into `out`, which has room for `capacity`; returns the
    /// readouts' sums. Throws Error when capacity is less than diskCount(),
    /// or `out` is null with a capacity.
    ViewSums readView(ViewValue value, DiskView* out, std::size_t capacity) const;
    /// The CPU engine's own disks, without a copy (DiskMemory above), with the
    /// pairwise and simultaneous schemes; empty (base null) on the OpenCL
    /// engines and with CollisionScheme::Events, which keep them elsewhere.
    /// Read it between calls to the world, not during one.
    DiskMemory diskMemory() const;

    /// Advances by `steps` steps of dt. Throws Error, taking none, when
    /// stepCount() + steps would pass 2^64 - 1; and when a step would need
    /// more than kMaxSubsteps substeps, or leaves a disk non-finite (the
    /// message names the step and the disk); the world then holds the step it
    /// reached (stepCount()), and after a non-finite step refuses to step
    /// further until setDisks.
    void step(std::uint64_t steps = 1);
    /// Lets step() stop early: while it runs, step() calls `check` on its
    /// own thread about every 20 ms, between two steps and within a long
    /// step: between events with CollisionScheme::Events (the first step of
    /// a call, and each after a step of at least one event per disk), and
    /// between substeps in a step of at least 8 substeps. When `check`
    /// returns true, step() returns at once, and the world holds the last
    /// step it completed (stepCount()): a step cut short returns to its
    /// start, so the disks, time(), the collision count and the
    /// measurements are that step's, and stepping on (or a snapshot()) gives
    /// bit for bit what an uninterrupted call gives. `check` may be empty
    /// (the default): steps are then never stopped.
    void setStopCheck(std::function<bool()> check);

    /// The step the state holds: steps taken since setDisks, or since the
    /// scene a snapshot continues (restore; carom/io.h loadCheckpoint).
    std::uint64_t stepCount() const;
    double time() const;  ///< simulated time [time]: the sum of the steps' dt
    const WorldDef& def() const;
    /// Changes dt and gravity between steps (the box, the boundary and the
    /// scheme stay); throws Error for values out of range and keeps the old ones.
    void setMotion(float dt, Vec2 gravity);

    /// Observables of the current state, summed in double in id order
    /// (energies in [mass length^2/time^2]).
    double kineticEnergy() const;  ///< sum of m v^2 / 2
    /// -sum of m g.x in the world's gravity (0 without). In a periodic box
    /// under gravity, positions wrap and this is not a potential energy:
    /// what the collisions conserve there is the kinetic energy in the
    /// centre-of-mass frame, (N - 1) temperature().
    double potentialEnergy() const;
    std::array<double, 2> momentum() const;  ///< sum of m v [mass length/time]
    /// The deepest overlap of two disks, max(r_i + r_j - |x_i - x_j|) over
    /// touching pairs, 0 if none [length]: a sort, O(N log N). The schemes
    /// that step leave overlaps of the order of a step's travel. A heap of
    /// disks with more than 8 N overlapping pairs: the deepest of the first
    /// 8 N found.
    double maxOverlap() const;
    /// Disks whose centre is outside the box or not finite: 0 unless a step
    /// was unstable (a dt too large for the speeds and the gravity).
    std::size_t escapedCount() const;
    /// kineticEnergy() + potentialEnergy(); with CollisionScheme::Events, of
    /// the engine's exact double state, whose drift the float disks would hide.
    double totalEnergy() const;
    /// kT (k = 1) [mass length^2/time^2]: E_kin / N with walls; in a periodic
    /// box the centre of mass carries no heat, so (E_kin - P^2/2M) / (N - 1).
    double temperature() const;
    /// Pairs that received an impulse since the scene began (setDisks, or the
    /// scene a snapshot continues), each pair once.
    std::uint64_t collisionCount() const;
    /// CollisionScheme::Events only (zeros otherwise).
    EventCounts eventCounts() const;
    /// CollisionScheme::Events only (empty otherwise): the disks' centres at
    /// time() in double, in id order, as the engine holds them (disks() rounds
    /// them to float; in a periodic box both are wrapped into it) [length].
    std::vector<std::array<double, 2>> exactPositions() const;
    /// Each disk's periodic image (carom/types.h Image), in id order, for the
    /// positions disks() gives: position + image * (width, height) is the
    /// disk's unwrapped centre. All {0, 0} with walls. setDisks starts every
    /// disk at {0, 0}; setDisk and editDisks keep them, addDisks adds disks
    /// at {0, 0}; snapshots and checkpoints keep them. The same on every
    /// engine where the positions are (bitwiseReproducible()).
    std::vector<Image> images() const;
    /// Collisions, pressure and Z over the interval since setDisks or resetMeasurements.
    Measurements measurements() const;
    void resetMeasurements();

    /// True when this engine's results are bitwise the CPU engine's: always on
    /// the CPU, and on OpenCL devices that round divide and sqrt correctly.
    /// Results are always bitwise reproducible on the same engine and device.
    bool bitwiseReproducible() const;
    /// The device the steps run on, in words.
    std::string deviceName() const;
    /// The buffers the engine holds on its device (all zero on the CPU
    /// engines, whose memory is the host's: carom/types.h peakResidentBytes).
    DeviceMemoryUse deviceMemory() const;
    /// This process's costs of a decomposed world (WorldDef::decomposition); all zero otherwise.
    DecompositionCosts decompositionCosts() const;
    /// The disks this process steps: in a decomposed world those whose
    /// centres lie in its domain (each disk on exactly one process), every
    /// disk otherwise. Not collective: it reads no other process's disks.
    OwnDisks ownDisks() const;
    /// Collective in a decomposed world whose DecompositionDef::gather is
    /// Gather::OnRequest: brings the whole world to every process, for the
    /// reads until the next step. Nothing to do in other worlds.
    void gather();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace carom
