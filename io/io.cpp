// carom::io (include/carom/io.h): the file readers and writers, on the public types.
#include <carom/io.h>

#include <utility>
#include <vector>

#include "engine/diagnostics.h"
#include "io/checkpoint.h"
#include "io/output_paths.h"
#include "io/state_csv.h"
#include "io/stats.h"
#include "io/trajectory.h"

namespace carom::io {

SceneFile loadScene(const std::string& path) { return loadScene(readSceneFile(path)); }

SceneFile loadScene(const SceneFileDef& scene) {
    std::uint64_t particles = scene.disks.size();
    for (const GroupDef& group : scene.groups) particles += group.count;
    requireRoomFor(particles, scene.path);

    Scene placed = makeScene(scene);
    SceneFile loaded;
    loaded.world = scene.world;
    loaded.world.width = placed.width;
    loaded.world.height = placed.height;
    validate(loaded.world);
    loaded.disks = std::move(placed.disks);
    loaded.steps = scene.steps;
    return loaded;
}

std::vector<Disk> readState(const std::string& path) { return readStateCsv(path, availableMemoryBytes()); }

void writeState(const std::string& path, const std::vector<Disk>& disks) { writeStateCsv(path, DiskBlocks(disks)); }
void writeState(const std::string& path, const World& world) { writeStateCsv(path, DiskBlocks(world)); }

void saveCheckpoint(const std::string& path, const World& world) {
    if (world.diskCount() == 0) throw Error("saveCheckpoint '" + path + "': the world has no disks yet");
    writeCheckpoint(path, world.snapshot());
}

struct CheckpointFile::Impl {
    std::string path;
    Snapshot contents;
};

CheckpointFile::CheckpointFile(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
CheckpointFile::~CheckpointFile() = default;
CheckpointFile::CheckpointFile(CheckpointFile&&) noexcept = default;
CheckpointFile& CheckpointFile::operator=(CheckpointFile&&) noexcept = default;
const WorldDef& CheckpointFile::world() const { return impl_->contents.world; }
std::uint64_t CheckpointFile::step() const { return impl_->contents.step; }
std::size_t CheckpointFile::diskCount() const { return impl_->contents.disks.size(); }
const Snapshot& CheckpointFile::snapshot() const { return impl_->contents; }

CheckpointFile readCheckpoint(const std::string& path) {
    return CheckpointFile(std::make_unique<CheckpointFile::Impl>(
        CheckpointFile::Impl{path, carom::readCheckpoint(path, availableMemoryBytes())}));
}

World loadCheckpoint(const std::string& path, const WorldDef& def) { return loadCheckpoint(readCheckpoint(path), def); }

World loadCheckpoint(CheckpointFile checkpoint, const WorldDef& def) {
    if (!checkpoint.impl_) throw Error("loadCheckpoint: this CheckpointFile was loaded already (a moved-from file)");
    const Snapshot& c = checkpoint.impl_->contents;
    WorldDef resumed = onEngine(c.world, EngineDef{def.engine, def.device});
    resumed.maxTravel = def.maxTravel;  // not in a checkpoint
    resumed.skin = def.skin;            // nor this
    resumed.decomposition = def.decomposition;
    World world(resumed);
    world.restore(c, "checkpoint '" + checkpoint.impl_->path + "'");
    return world;
}

// The engine's writers, built in place (they own an open file and do not move).
template <class Writer>
struct Owned {
    template <class... Arguments>
    explicit Owned(Arguments&&... arguments) : file(std::forward<Arguments>(arguments)...) {}
    Writer file;
};

struct TrajectoryWriter::Impl : Owned<carom::TrajectoryWriter> {
    using Owned::Owned;
};

TrajectoryWriter::TrajectoryWriter(const std::string& path) : impl_(std::make_unique<Impl>(path)) {}
namespace {

// What the files a run resumed from `world` appends to must lead up to.
Resumed resumedFrom(const World& world, std::uint64_t every, const std::string& name) {
    Resumed resumed;
    resumed.name = name;
    resumed.step = world.stepCount();
    resumed.time = world.time();
    resumed.collisions = world.collisionCount();
    resumed.every = every;
    resumed.disks = world.disks();
    resumed.world = world.def();
    return resumed;
}

}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& path, const World& resumed, std::uint64_t every,
                                   const std::string& resumedName) {
    const Resumed from = resumedFrom(resumed, every, resumedName);
    impl_ = std::make_unique<Impl>(path, &from);
}
TrajectoryWriter::~TrajectoryWriter() = default;
TrajectoryWriter::TrajectoryWriter(TrajectoryWriter&&) noexcept = default;
TrajectoryWriter& TrajectoryWriter::operator=(TrajectoryWriter&&) noexcept = default;

void TrajectoryWriter::write(const World& world) {
    // A frame of no disks has no cell depth, and no run continues from it.
    if (world.diskCount() == 0) throw Error("TrajectoryWriter::write: the world has no disks yet");
    impl_->file.write(DiskBlocks(world), world.def(), world.stepCount(), world.time(), world.images());
}
std::size_t TrajectoryWriter::frames() const { return impl_->file.frames(); }
void TrajectoryWriter::close() { impl_->file.commit(); }

struct StatisticsWriter::Impl : Owned<StatsWriter> {
    using Owned::Owned;
};

StatisticsWriter::StatisticsWriter(const std::string& path) : impl_(std::make_unique<Impl>(path)) {}
StatisticsWriter::StatisticsWriter(const std::string& path, const World& resumed, std::uint64_t every,
                                   const std::string& resumedName) {
    const Resumed from = resumedFrom(resumed, every, resumedName);
    impl_ = std::make_unique<Impl>(path, &from);
}
StatisticsWriter::~StatisticsWriter() = default;
StatisticsWriter::StatisticsWriter(StatisticsWriter&&) noexcept = default;
StatisticsWriter& StatisticsWriter::operator=(StatisticsWriter&&) noexcept = default;

void StatisticsWriter::write(const World& world) {
    Diagnostics measured;  // the observables the rows hold (StatsWriter), as World measures them
    measured.kineticEnergy = world.kineticEnergy();
    measured.momentum = world.momentum();
    measured.maxOverlap = world.maxOverlap();
    measured.escaped = world.escapedCount();
    impl_->file.write(world.stepCount(), world.time(), measured, world.collisionCount());
}
std::size_t StatisticsWriter::rows() const { return impl_->file.rows(); }
void StatisticsWriter::close() { impl_->file.commit(); }

}  // namespace carom::io
