// carom::io (link carom::io): reading and writing carom's files with the
// public types. The formats are the README's: scene files ("Scene files"),
// state CSV (`id,x,y,vx,vy,mass,radius`, floats as the shortest text that
// reads back bit for bit), checkpoints ("Checkpoints": a versioned binary
// file with a checksum).
//
// Files are written whole or not at all: through a temporary file renamed
// into place, so a failure leaves the old file as it was. Every refusal is a
// carom::Error naming the file, the line and what is allowed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <carom/types.h>
#include <carom/world.h>

namespace carom::io {

// A scene file read, validated and placed: the world it defines and its
// disks in id order (the groups' disks, then the [[disk]]s).
struct SceneFile {
    WorldDef world;  // box, dt, gravity, boundary, collisions (engine: Cpu)
    std::vector<Disk> disks;
    std::uint64_t steps = 1000;  // the steps `carom run` would take
};
SceneFile loadScene(const std::string& path);

// A state CSV: the disks, in id order. The file's ids must be exactly
// 0..N-1, in any row order; the box is not checked here (World::setDisks does).
std::vector<Disk> readState(const std::string& path);
void writeState(const std::string& path, const std::vector<Disk>& disks);

// Checkpoints: everything a world needs to continue bit for bit (the box,
// dt, gravity, boundary, scheme, step, collision count, the disks, and with
// CollisionScheme::Events the engine's exact double state), in a versioned
// binary file with a checksum. loadCheckpoint takes the engine, the device
// and maxTravel from `def` (a checkpoint does not hold them) and everything
// else from the file; it refuses a file that is damaged, of another format
// or out of range, naming what is wrong.
void saveCheckpoint(const std::string& path, const World& world);
World loadCheckpoint(const std::string& path, const WorldDef& def = WorldDef{});

}  // namespace carom::io
