// Trajectories as extended XYZ, the multi-frame text format that OVITO and
// ASE read. Each frame is:
//
//   N
//   Lattice="W 0 0 0 H 0 0 0 D" Origin="0 0 -R" pbc="F F F" Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:id:I:1 step=S time=T
//   X x y 0 vx vy 0 radius mass id        (one line per particle, in id order)
//
// A periodic box says pbc="T T F" and has the disks' images after the
// velocities (Properties=...:velo:R:3:image:I:3:radius:...):
//
//   X x y 0 vx vy 0 ix iy 0 radius mass id
//
// The disks lie in the plane z = 0; the cell's third vector is one largest
// diameter D = 2R deep, centred on that plane, so 3D tools draw a flat box
// around the disks. "X" is ASE's placeholder species. Numbers are the
// shortest text that reads back to the same float, independent of locale.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <carom/files.h>
#include <carom/types.h>

#include "io/disk_blocks.h"

namespace carom {

struct Resumed;  // io/output_paths.h

class TrajectoryWriter {
public:
    // Opens a temporary file beside `path`; throws Error if it cannot. A run
    // resumed from a checkpoint continues an existing `path` (its frames,
    // then this run's: one long run's trajectory); Error unless its last
    // frame leads up to the checkpoint (requireAppendable) and is of the same
    // simulation: its disk count, cell (box, boundary), radii, masses and
    // ids, and its time when it is at the checkpoint's step.
    explicit TrajectoryWriter(const std::string& path, const Resumed* resumed = nullptr);

    // Appends one frame of `disks` (in id order) with their `images` (empty:
    // all {0, 0}; written in a periodic box only); throws Error if the write fails (disk full).
    void write(const DiskBlocks& disks, const WorldDef& world, std::uint64_t step, double time,
               const std::vector<Image>& images = {});
    std::size_t frames() const { return frames_; }

    // Renames the complete file into place; without it the target is untouched.
    void commit() { file_.commit(); }

private:
    io::AtomicFile file_;
    static constexpr std::size_t kFramePiece = std::size_t(1) << 20;  // bytes of text written at a time
    std::string frame_;                                               // reused from frame to frame
    std::size_t frames_ = 0;
};

}  // namespace carom
