// Checkpoints: everything a run needs to continue bit for bit, in a versioned
// binary file with a checksum.
//
// Layout (version 4), every field little-endian whatever the machine:
//
//   offset  bytes  field
//        0      8  magic "CAROMCKP"
//        8      4  byte order mark 0x01020304 (reads 0x04030201 if byte-swapped)
//       12      4  format version, 4
//       16      8  particle count N, 1..kMaxParticles
//       24     20  box width, box height, dt, gravity x, gravity y (float32)
//       44      4  boundary: 0 = reflective walls, 1 = periodic
//       48      8  step: steps taken since the scene began
//       56      8  time (float64) = step * dt
//       64      8  collisions since the scene began
//       72      4  collision scheme: 0 = simultaneous, 1 = pairwise, 2 = events
//       76    24N  per particle, in id order: x, y, vx, vy, mass, radius (float32)
//   76+24N     8N  per particle, in id order: its periodic image x, y (int32;
//                  carom/types.h Image, 0 with walls)
//   76+32N      4  CRC-32 (IEEE, as zlib's crc32) of every byte before it
//
// With the events scheme the engine's exact state (carom/types.h EventEngineState)
// comes between the images and the CRC, so that a resumed run continues
// bit for bit (the particles above are its float32 projection):
//
//   76+32N      8  the engine's time (float64) since its origin
//   84+32N    64N  per disk, in id order: x, y, vx, vy, time, event time (float64;
//                  the event time is +infinity for no event), event (int32: a
//                  partner id >= 0, or -1..-9 as kEvent*), partner collisions,
//                  collisions, cell (uint32)
//   84+96N      4  CRC-32 of every byte before it
//
// Version 3 is version 4 without the images: its disks read back at image
// {0, 0}. Version 2 is version 3 without the events scheme. Version 1 is the
// same without the collision scheme (its particles start at offset 72): only
// the simultaneous scheme wrote it, so it reads as that. A reader refuses
// anything else with a message saying what is wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <carom/types.h>

namespace carom {

// A checkpoint holds a Snapshot (carom/types.h), but for the world's
// engine, device and maxTravel: it reads back with their defaults.

constexpr std::uint32_t kCheckpointVersion = 4;  // the version written; versions 1 to 3 are still read

// CRC-32 (IEEE, as zlib's crc32) of `size` bytes: the checkpoint's checksum.
std::uint32_t crc32(const unsigned char* data, std::size_t size);

// The file's bytes, and back. decodeCheckpoint validates the header, the
// size, the checksum, the world, every disk and the events state (every
// value finite, event codes and partners in range; the cells are checked by
// World::restore, whose engine knows the grid); `what` names the source.
// encodeCheckpoint throws Error when `events` is present without the events
// scheme or the other way round.
std::string encodeCheckpoint(const Snapshot& snapshot);
Snapshot decodeCheckpoint(const std::string& bytes, const std::string& what);

// Writes through a temporary file renamed into place.
void writeCheckpoint(const std::string& path, const Snapshot& snapshot);

// Reads and validates. Before anything sized by the particle count is
// allocated, checks the header against the file size, the count against
// `availableBytes` of memory (requireRoomFor; 0 = unknown) and the checksum,
// streamed over the file: a corrupt or forged count cannot make it allocate.
Snapshot readCheckpoint(const std::string& path, std::uint64_t availableBytes = 0);

}  // namespace carom
