// Disks as CSV: `id,x,y,vx,vy,mass,radius`, one row per disk in id order,
// each float as the shortest text that reads back bit for bit.
#pragma once

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include <carom/types.h>

#include "io/disk_blocks.h"

namespace carom {

// Reads a state file. Rows may come in any order; the ids must be exactly
// 0..N-1. Throws Error naming the file, line and column of anything wrong.
// Physical checks (inside the box, positive mass) are World::setDisks' job.
// Bounded whatever the file (io::TextLines: a line too long or with a NUL
// byte, a FIFO that nothing writes to), and more rows than kMaxParticles or
// than `availableBytes` of memory hold (requireRoomFor; 0 = unknown) are
// refused as they are read.
std::vector<Disk> readStateCsv(const std::string& path, std::uint64_t availableBytes = 0);

// The same, from a stream; `path` names it in messages.
std::vector<Disk> parseStateCsv(std::istream& in, const std::string& path, std::uint64_t availableBytes = 0);

// Writes the state through a temporary file renamed into place, so `path`
// holds either its old content or the complete new file. Throws Error, and
// writes nothing, for no disks or a value that is not finite (neither reads back).
void writeStateCsv(const std::string& path, const DiskBlocks& disks);

}  // namespace carom
