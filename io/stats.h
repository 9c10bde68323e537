// Statistics as CSV, one row per sample, for spreadsheets, pandas or gnuplot:
//
//   step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped
//
// step counts from the start of the scene (a resumed run continues the
// count), time = step * dt, collisions are summed since the start of the
// scene. Pressure joins when the engine measures it (issue #5). Numbers are
// the shortest text that reads back exactly, independent of locale.
#pragma once

#include <cstdint>
#include <string>

#include <carom/files.h>
#include "engine/diagnostics.h"

namespace carom {

struct Resumed;  // io/output_paths.h

class StatsWriter {
public:
    // Opens a temporary file beside `path` and writes the header; throws
    // Error if it cannot. A run resumed from a checkpoint continues an
    // existing `path` (its rows, then this run's: one long run's statistics);
    // Error if its header is not this one, its last row does not lead up to
    // the checkpoint (requireAppendable), or counts more collisions than the
    // checkpoint (at its step: another time or count) and so is another
    // simulation's.
    explicit StatsWriter(const std::string& path, const Resumed* resumed = nullptr);

    // Appends one row; throws Error if the write fails (disk full).
    void write(std::uint64_t step, double time, const Diagnostics& diagnostics, std::uint64_t collisions);
    std::size_t rows() const { return rows_; }

    // Renames the complete file into place; without it the target is untouched.
    void commit() { file_.commit(); }

private:
    io::AtomicFile file_;
    std::size_t rows_ = 0;
};

}  // namespace carom
