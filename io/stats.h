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
#include <optional>
#include <string>

#include <carom/files.h>
#include "engine/diagnostics.h"

namespace carom {

class StatsWriter {
public:
    // Opens a temporary file beside `path` and writes the header; throws
    // Error if it cannot. A run resumed from a checkpoint at step `resumedAt`
    // continues an existing `path` (its rows, then this run's: one long run's
    // statistics); Error if its header is not this one or its last row is
    // after that step, since appending would repeat steps.
    explicit StatsWriter(const std::string& path, std::optional<std::uint64_t> resumedAt = std::nullopt);

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
