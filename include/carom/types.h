// carom's public types: the definitions a world is made from, and a disk.
//
// Every field states its unit, its range and its default. Units are whatever
// the caller picks for length, mass and time; the defaults describe disks of
// radius 1 and mass 1 moving at speed 1. Definition structs are plain values:
// start from the defaults and set what differs, as in
//
//     carom::WorldDef def;
//     def.width = def.height = 100.0f;
//     def.gravity = {0.0f, -9.81f};
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace carom {

/// Every refusal of bad input, from any function of the library: the message
/// names the value and what is allowed.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Decomposition;  // carom/decomposition.h

/// A vector in the plane: two floats, 8-byte aligned, as OpenCL's float2.
struct alignas(8) Vec2 {
    float x;
    float y;
};

/// One disk, as the caller sets and reads it. Ids are positions in the array
/// given to World::setDisks and never change.
struct Disk {
    Vec2 position{0.0f, 0.0f};  ///< centre [length]; with walls the whole disk lies inside the box,
                                ///<   [radius, width - radius] x [radius, height - radius]; in a
                                ///<   periodic box the centre lies in [0, width) x [0, height)
    Vec2 velocity{0.0f, 0.0f};  ///< [length/time], |v| <= kMaxSpeed
    float mass = 1.0f;          ///< [mass], in [kMinMass, kMaxMass]
    float radius = 1.0f;        ///< [length], in [kMinLength, kMaxLength]; the disk must fit in the box
};

/// A disk's periodic image (World::images): the box widths and heights it
/// has crossed since it was set, +1 each time it left by the right (top)
/// side and came back in on the left (bottom), -1 the other way; always
/// {0, 0} with walls. position + image * (width, height) is its unwrapped
/// centre, for displacements longer than the box. Counted modulo 2^32, as
/// the int32 images of GSD files are.
using Image = std::array<std::int32_t, 2>;

/// What a renderer draws of one disk (World::readView): 16 bytes, so that a
/// frame reads back half of what the disk holds.
struct DiskView {
    Vec2 position;  ///< centre [length]
    float radius;   ///< [length]
    float value;    ///< the quantity ViewValue names, for the disk's colour
};
/// DiskView::value: |v|, mass, radius, or the id (as a float: exact below
/// 2^24 = 16 777 216 disks, rounded above, where ids share values).
enum class ViewValue { Speed, Mass, Radius, Id };

/// Sums over every disk that World::readView measures with the views, for a
/// viewer's readouts. On the CPU engine in double, equal to kineticEnergy()
/// and the others; with CollisionScheme::Events in double from its double
/// state (as totalEnergy(), while kineticEnergy() and the others measure its
/// float copy). On the OpenCL engines each disk's terms are rounded to float
/// (up to about 1e-7 of each), summed in float-float (about 44 bits) within a
/// work-group, then in double: close to, not bitwise equal to, the others.
struct ViewSums {
    double kineticEnergy = 0.0;              ///< sum of m v^2 / 2
    double potentialEnergy = 0.0;            ///< -sum of m g . x
    std::array<double, 2> momentum{};        ///< sum of m v
    double mass = 0.0;                       ///< sum of m
    double speedSquared = 0.0;               ///< sum of v^2, unweighted
    float minValue = 0.0f, maxValue = 0.0f;  ///< of DiskView::value; 0 without disks
};

/// The kinetic energy in the centre-of-mass frame, E_kin - |P|^2 / 2M, of
/// disks of kinetic energy `kinetic`, momentum `momentum` and mass `mass`
/// (> 0): what the collisions conserve in a periodic box, under gravity too
/// (which there only accelerates the centre of mass: -sum m g.x jumps by
/// m g H whenever a disk wraps).
inline double centreOfMassFrameKinetic(double kinetic, std::array<double, 2> momentum, double mass) {
    return kinetic - (momentum[0] * momentum[0] + momentum[1] * momentum[1]) / (2.0 * mass);
}

/// The most disks a world may hold: disk ids and grid cell offsets are
/// 32-bit, and the OpenCL grid's one-pass scan sums them in 30 bits.
constexpr std::uint64_t kMaxParticles = 1'000'000'000;

// Memory: a request that cannot fit is refused before anything is allocated.

/// Host memory a world needs per disk, about [bytes]: the disks given, the
/// engine's two state buffers, the read-back copy, the grids and the CPU
/// engine's neighbour lists (10^7 pairwise disks on it peak at 278).
constexpr std::uint64_t kHostBytesPerDisk = 320;
/// The same on an OpenCL engine, whose state and grid live on the device
/// (10^8 disks on one peak at 106 [bytes] a disk, starting).
constexpr std::uint64_t kOpenClHostBytesPerDisk = 128;

/// The memory available to a new allocation now [bytes]: Linux's MemAvailable
/// (free memory plus the caches it can drop), else the free physical pages,
/// else (macOS) the physical memory; Windows' available physical memory. Less
/// where the process is limited: its cgroup's memory.max (Linux, cgroup v2:
/// containers, Slurm jobs) and the address-space limit (ulimit -v). 0 where
/// none of these is known.
std::uint64_t availableMemoryBytes();

/// What a world's engine holds on its device (World::deviceMemory) [bytes].
struct DeviceMemoryUse {
    std::uint64_t bytes = 0;      ///< the OpenCL engine's buffers alive now; 0 on the CPU engines
    std::uint64_t peakBytes = 0;  ///< the most of them alive at once since the world was made
};

/// The most memory this process has held resident at once since it started
/// [bytes], all its worlds and data together (getrusage); 0 where unknown
/// (Windows).
std::uint64_t peakResidentBytes();

/// Throws Error naming `what` (a file, a field, an option) when `disks` is
/// more than kMaxParticles or needs more than `availableBytes` of host memory
/// (`bytesPerDisk` each: kHostBytesPerDisk, or kOpenClHostBytesPerDisk for
/// an OpenCL engine; 0 bytes: unknown, not checked).
void requireRoomFor(std::uint64_t disks, const std::string& what, std::uint64_t availableBytes = availableMemoryBytes(),
                    std::uint64_t bytesPerDisk = kHostBytesPerDisk);

/// What happens at the edges of the box.
enum class Boundary {
    Walls,     ///< reflective walls on all four sides (the default)
    Periodic,  ///< the box repeats: a disk leaving one side enters the opposite
               ///<   one, and disks interact with the nearest image of each other
};

/// How the collisions of a step are resolved (README, "Collision schemes").
enum class CollisionScheme {
    /// The seed's scheme: every overlapping, approaching pair gets the elastic
    /// impulse computed from the state before the step, all summed, plus a
    /// positional push. Energy drifts (heats) in dense gases: a disk in two
    /// contacts at once sums two impulses computed from the same velocities.
    Simultaneous,
    /// Binary elastic collisions at their exact contact times, resolved in
    /// rounds of mutually earliest events: energy is conserved to rounding at
    /// any density, also under gravity. The default.
    Pairwise,
    /// Exact event-driven dynamics: free flight between instantaneous binary
    /// collisions, event by event, in double on one CPU thread. The ground
    /// truth the stepped schemes are measured against; dt only sets when the
    /// state is sampled. ComputeEngine::Cpu only.
    Events,
};

/// Where the steps run.
enum class ComputeEngine {
    /// The host's cores (OpenMP; one thread without it). Always available.
    Cpu,
    /// OpenCL, the host building the grid each step and the device resolving
    /// collisions; the state is read back every step. Best on CPU OpenCL
    /// devices (PoCL).
    OpenClHostGrid,
    /// OpenCL with the state and the grid kept on the device between steps:
    /// the fast choice on GPUs. The state is read back only when asked.
    OpenClResident,
};

/// What World::setDisks does with disks that overlap deeper than two disks
/// close in one step (2 x the fastest speed x dt, plus rounding): such
/// overlaps did not come from a run, and the disks push through each other
/// as they separate. Warn (the default) accepts them with a warning in
/// World::warnings(); Refuse throws Error naming the deepest pair.
enum class DeepOverlaps { Warn, Refuse };

/// Names as the command line and scene files spell them ("walls", "periodic";
/// "simultaneous", "pairwise", "events"; "cpu", "opencl-host-grid",
/// "opencl-resident"); the parsers throw Error naming the value otherwise.
Boundary parseBoundary(const std::string& name);
const char* boundaryName(Boundary boundary);
CollisionScheme parseCollisionScheme(const std::string& name);
const char* collisionSchemeName(CollisionScheme scheme);
ComputeEngine parseComputeEngine(const std::string& name);
const char* computeEngineName(ComputeEngine engine);

/// The ranges in which carom's float32 arithmetic gives valid results
/// (README, "Limits"): squares, sums and tallies that stay normal floats
/// (FLT_MIN 1.2e-38, FLT_MAX 3.4e38). Lengths and dt square to at most 1e36;
/// masses keep m_i + m_j, the mass shares (>= 1e-30) and the wall-momentum
/// and virial tallies (m v and m r v summed over up to 1024 substeps) finite.
constexpr float kMinLength = 1e-18f;  ///< box sides and radii [length]
constexpr float kMaxLength = 1e18f;
constexpr float kMinMass = 1e-15f;  ///< [mass]
constexpr float kMaxMass = 1e15f;
constexpr float kMinDt = 1e-18f;  ///< [time]
constexpr float kMaxDt = 1e18f;
constexpr float kMaxAcceleration = 1e18f;  ///< |gravity| [length/time^2]
constexpr float kMaxSpeed = 1e18f;         ///< [length/time]: (v_i - v_j)^2 stays finite
/// The box diagonal times the largest speed a disk can reach [length^2/time]:
/// the collision times square (x_i - x_j).(v_i - v_j), up to 4 x this squared.
constexpr double kMaxLengthTimesSpeed = 1e18;

constexpr double kPi = 3.14159265358979323846;
/// A step must move a typical disk by at least this many float spacings of
/// the positions near the far side of the box (a smaller step is lost or
/// wrong by more than 50 %; the rounding error of a step of d spacings is up
/// to 1 / (2 d)), and gets a warning below kWarnStepSpacings (error > 5 %).
constexpr double kMinStepSpacings = 1.0;
constexpr double kWarnStepSpacings = 10.0;

/// The box, the rules of motion and where they run. The box is [0, width] x
/// [0, height].
struct WorldDef {
    float width = 0.0f;   ///< box width [length], in [kMinLength, kMaxLength]; no default: set it
    float height = 0.0f;  ///< box height [length], in [kMinLength, kMaxLength]; no default: set it
    float dt = 0.01f;     ///< time step [time], in [kMinDt, kMaxDt]; with the disks' speeds it must
                          ///<   move a typical disk by >= kMinStepSpacings float spacings, and the
                          ///<   fastest by at most the smaller box side (unless maxTravel > 0)
    Vec2 gravity{0, 0};   ///< constant acceleration [length/time^2], |g| <= kMaxAcceleration; off by default
    /// A periodic box is at least 3 largest disk diameters wide and high, so
    /// that a disk meets each neighbour once, at its nearest image.
    Boundary boundary = Boundary::Walls;
    /// Adaptive substeps against tunnelling: when > 0, each step of dt is split
    /// into the fewest equal substeps in which no disk moves more than
    /// maxTravel x the smallest radius, judged from the fastest disk at the
    /// start of the step (plus what gravity adds over the step). 0 = off
    /// (every step is one substep) [fraction of the smallest radius], >= 0.
    /// Not with CollisionScheme::Events, which has no steps to split.
    float maxTravel = 0.0f;
    /// The CPU engine's neighbour lists (pairwise scheme): each disk lists the
    /// disks whose centres lie within contact plus `skin`, and the lists are
    /// rebuilt once the disks have moved about half of it since the last
    /// build [length]. 0 = automatic (the largest radius, more where a
    /// substep travels far); else at most kMaxSkinRadii x the largest radius
    /// (setDisks refuses more). Sets the speed, never a result. Must be 0 on
    /// the OpenCL engines and with the other schemes, which keep no lists.
    float skin = 0.0f;
    CollisionScheme collisions = CollisionScheme::Pairwise;
    ComputeEngine engine = ComputeEngine::Cpu;
    /// OpenCL engines only: which device, as an index in the order of the
    /// platforms and their devices (as `carom devices` lists them) or a part
    /// of the device's name; empty = the first GPU, else the first device.
    std::string device;
    /// Several processes, one world (carom/decomposition.h): each process of
    /// an MPI communicator steps the disks of its domain, and every result is
    /// bit for bit that of one process. Empty (the default): one process.
    std::shared_ptr<const Decomposition> decomposition;
};

/// What splitting a world among processes (WorldDef::decomposition) has cost
/// this process since its disks were set: World::decompositionCosts(), all
/// zero in one process. The seconds are wall-clock, so a process that waits
/// for a slower one counts the wait where it waits (in the exchanges and
/// the agreement).
struct DecompositionCosts {
    std::uint64_t substeps = 0;         ///< substeps taken
    std::uint64_t retakenSubsteps = 0;  ///< pairwise substeps taken again with a deeper halo
    std::uint64_t haloCopies = 0;       ///< copies of other processes' disks received
    std::uint64_t migrants = 0;         ///< disks handed on to other processes
    /// Messages sent to other processes: each non-empty part of an exchange,
    /// and a part of each gather for every other process.
    std::uint64_t messages = 0;
    std::uint64_t bytes = 0;        ///< the bytes those messages held [bytes]
    double computeSeconds = 0.0;    ///< the engine stepping the process's disks and the copies [s]
    double exchangeSeconds = 0.0;   ///< the halo's copies: packing, exchanging, merging by id [s]
    double migrationSeconds = 0.0;  ///< handing disks on and taking them in [s]
    double agreementSeconds = 0.0;  ///< agreeing on each substep's rounds and non-finite disks [s]
    /// Gathering the whole world on every process (after each World::step
    /// call, and for the tallies and images) [s].
    double gatherSeconds = 0.0;
};

/// A compute engine and, for OpenCL, its device: WorldDef::engine and
/// WorldDef::device apart from a world, for code that runs one world on
/// several engines (tests, `carom validate`).
struct EngineDef {
    ComputeEngine engine = ComputeEngine::Cpu;
    std::string device;  ///< OpenCL only: as WorldDef::device
};

/// `world` to run on `engine`.
inline WorldDef onEngine(WorldDef world, const EngineDef& engine) {
    world.engine = engine.engine;
    world.device = engine.device;
    return world;
}

/// Throws Error naming the first field that is not finite or out of range
/// (World's constructor checks the same).
void validate(const WorldDef& world);

/// The maxTravel the command line's `--dt auto` uses when none is given.
constexpr float kDefaultMaxTravel = 0.2f;

/// The largest WorldDef::skin, in largest radii: the lists then hold about
/// (2 + kMaxSkinRadii)^2 x the packing disks each.
constexpr float kMaxSkinRadii = 8.0f;
/// The most substeps one step may take before the run is refused as runaway.
constexpr std::uint64_t kMaxSubsteps = 1'000'000;

/// A gas to start from (makeScene, carom/world.h): N disks placed without
/// overlap on a jittered hexagonal lattice, radii and masses fixed or uniform
/// in a range, velocities of one speed in uniformly random directions.
struct SceneDef {
    std::uint32_t particles = 1000;  ///< N, in [1, kMaxParticles]
    float packing = 0.3f;    ///< area fraction sum(pi r^2) / (W H), in (0, 0.7]; sizes a square box (<= kMaxLength)
    float width = 0.0f;      ///< box [length]; when width and height are > 0 they
    float height = 0.0f;     ///<   are used instead of packing
    float radiusMin = 1.0f;  ///< radius drawn uniformly in [radiusMin, radiusMax] [length], in [kMinLength, kMaxLength]
    float radiusMax = 1.0f;
    float massMin = 1.0f;  ///< mass drawn uniformly in [massMin, massMax] [mass], in [kMinMass, kMaxMass]
    float massMax = 1.0f;
    float speed = 1.0f;      ///< initial speed of every disk [length/time], in [0, kMaxSpeed]
    std::uint64_t seed = 1;  ///< random seed; the same seed gives the same disks wherever the C library
                             ///<   rounds sin, cos and sqrt alike (the generator itself is portable)
};

/// Throws Error unless the scene can be placed (ranges valid, packing reachable).
void validate(const SceneDef& scene);

// A scene file (the README's "Scene files"; io::readSceneFile reads one) as
// it is written, before its disks are placed (makeScene, carom/world.h): a
// program may change it first, as the command line's options do.

/// An axis-aligned rectangle inside the box [length]: 0 <= xMin < xMax <=
/// width, 0 <= yMin < yMax <= height. Two groups' regions are either the same
/// rectangle (one shared lattice) or disjoint.
struct Region {
    float xMin = 0.0f;  ///< left edge
    float yMin = 0.0f;  ///< bottom edge
    float xMax = 0.0f;  ///< right edge
    float yMax = 0.0f;  ///< top edge
};

/// One [[group]]: `count` disks placed without overlap on a jittered
/// hexagonal lattice over their region. Groups that name the same region (or
/// none) share one lattice, their disks shuffled over its sites.
struct GroupDef {
    std::string name;         ///< shown in messages; default "group[K]", K counting from 1
    std::size_t line = 0;     ///< line of its [[group]] header, for messages
    std::uint32_t count = 0;  ///< number of disks, >= 1; required
    /// Radius [length] and mass [mass], each fixed (min == max) or uniform in
    /// [min, max]: finite, 0 < min <= max, and within [kMinLength, kMaxLength]
    /// and [kMinMass, kMaxMass] once placed.
    float radiusMin = 1.0f;
    float radiusMax = 1.0f;
    float massMin = 1.0f;
    float massMax = 1.0f;
    float speed = 1.0f;            ///< speed of every disk, random directions [length/time], in [0, kMaxSpeed]
    float temperature = 0.0f;      ///< > 0: Maxwell-Boltzmann velocities at k_B T = temperature
                                   ///<   [mass length^2/time^2] instead of `speed`; 0 = off
    std::optional<Region> region;  ///< where the disks go; default the whole box
};

/// One [[disk]]: a single disk, exactly where it is put.
struct DiskDef {
    std::size_t line = 0;  ///< line of its [[disk]] header, for messages
    Vec2 position{0, 0};   ///< centre [length]; required, the disk must lie inside the box
    Vec2 velocity{0, 0};   ///< [length/time]; default at rest
    float mass = 1.0f;     ///< [mass], in [kMinMass, kMaxMass]
    float radius = 1.0f;   ///< [length], in [kMinLength, kMaxLength]
};

/// [output]: the files a run writes. Paths are relative to the working
/// directory, like paths on the command line. Empty = not written.
struct OutputDef {
    std::string trajectory;     ///< extended XYZ frames (io::TrajectoryWriter)
    std::string stats;          ///< CSV rows (io::StatisticsWriter)
    std::string checkpoint;     ///< binary checkpoint (io::saveCheckpoint), also written when the run ends
    std::string state;          ///< the final state as CSV (io::writeState)
    std::uint64_t every = 100;  ///< steps between samples and checkpoints, >= 1
};

/// The whole file: its world, its groups and disks, and what `carom run`
/// does with it.
struct SceneFileDef {
    std::string path;            ///< the file, for messages
    WorldDef world;              ///< box (0 x 0 when `packing` sizes it), dt, gravity, boundary,
                                 ///<   collision scheme
    float packing = 0.0f;        ///< > 0: the box is square, sized so the disks cover this
                                 ///<   area fraction, in (0, 0.7]; instead of world's box
    std::uint64_t steps = 1000;  ///< steps `carom run` takes, in [0, 2^63 - 1]
    std::uint64_t seed = 1;      ///< random seed of the placement and the velocities, any value
    std::vector<GroupDef> groups;
    std::vector<DiskDef> disks;  ///< ids follow the groups' disks, in file order
    OutputDef output;
};

/// CollisionScheme::Events only: how often each kind of event happened since
/// setDisks, an edit, or World::restore.
struct EventCounts {
    std::uint64_t collisions = 0;     ///< disk-disk collisions
    std::uint64_t wallBounces = 0;    ///< bounces off a wall
    std::uint64_t cellCrossings = 0;  ///< moves of a disk from one grid cell to the next
    std::uint64_t stale = 0;          ///< events found stale (a partner changed) and recomputed
    std::uint64_t overlapping = 0;    ///< collisions of pairs found overlapping by rounding
};

// CollisionScheme::Events: what the event-driven engine holds between
// events, in double (Snapshot::events). Each disk keeps its position and
// velocity at its own time (it moves only when it takes part in an event)
// and its one scheduled event; the engine rebuilds its calendar and cell
// lists from these, deterministically.

/// The scheduled event of a disk (EventDiskState::event): >= 0 is a
/// collision with the disk of that id; the negative codes are the rest.
constexpr std::int32_t kEventNone = -1;      ///< nothing will happen to it
constexpr std::int32_t kEventWallLeft = -2;  ///< it bounces off the left, right, bottom or top wall
constexpr std::int32_t kEventWallRight = -3;
constexpr std::int32_t kEventWallBottom = -4;
constexpr std::int32_t kEventWallTop = -5;
constexpr std::int32_t kEventCrossLeft = -6;   ///< it leaves its cell to the left, right,
constexpr std::int32_t kEventCrossRight = -7;  ///<   below or above
constexpr std::int32_t kEventCrossDown = -8;
constexpr std::int32_t kEventCrossUp = -9;
constexpr std::int32_t kEventLowestCode = kEventCrossUp;

/// One disk of the event-driven engine.
struct EventDiskState {
    double x = 0.0, y = 0.0;              ///< centre at `time` [length]; in a periodic box, in its cell's image
    double vx = 0.0, vy = 0.0;            ///< velocity at `time` [length/time]
    double time = 0.0;                    ///< the time x, y, vx, vy hold [time], in [0, EventEngineState::time]
    double eventTime = 0.0;               ///< when its scheduled event happens [time], >= EventEngineState::time;
                                          ///<   +infinity exactly for kEventNone
    std::int32_t event = kEventNone;      ///< what happens then (the codes above)
    std::uint32_t partnerCollisions = 0;  ///< with a collision: the partner's `collisions` when it was
                                          ///<   scheduled (the event is stale once that changed)
    std::uint32_t collisions = 0;         ///< how often its velocity changed (collisions, walls), mod 2^32
    std::uint32_t cell = 0;               ///< its cell in the engine's grid, row x columns + column (the
                                          ///<   grid the disks' largest diameter sizes: copy, never compute it)
};

/// The event-driven engine's exact state.
struct EventEngineState {
    double time = 0.0;                  ///< the engine's current time [time], finite and >= 0
    std::vector<EventDiskState> disks;  ///< in id order
};

/// Everything a world needs to continue bit for bit (World::snapshot and
/// World::restore, carom/world.h; a checkpoint file holds the same, carom/io.h).
struct Snapshot {
    /// The world it was taken of: its box, dt, gravity, boundary and scheme
    /// (what restore uses), and its engine, device and maxTravel (which
    /// restore leaves as the restored world has them, and a checkpoint does
    /// not hold: read from one, they are the defaults).
    WorldDef world;
    std::uint64_t step = 0;        ///< steps taken since the scene began (World::stepCount())
    double time = 0.0;             ///< simulated time [time] (World::time()): what `step` steps of dt add up to
    std::uint64_t collisions = 0;  ///< pairs that received an impulse since the scene began
                                   ///<   (World::collisionCount()), at most 2^63
    std::vector<Disk> disks;       ///< in id order, at least 1; with the events scheme the float rounding of `events`
    /// The event-driven engine's exact state: present exactly when
    /// world.collisions is CollisionScheme::Events, with a state per disk.
    std::optional<EventEngineState> events;
    /// Each disk's periodic image (World::images()), in id order; empty for
    /// all {0, 0}. Only a periodic box has images other than {0, 0}.
    std::vector<Image> images;
};

}  // namespace carom
