#include <carom/io.h>
#include "io/stats.h"

#include <fstream>

#include "io/output_paths.h"
#include "engine/text_format.h"

namespace carom {
namespace {

const std::string kHeader = "step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped";

// How a run resumed at `resumedAt` (if it is) opens `path`: appending, once
// the rows already there are found to have this header and to end at or
// before that step.
io::Existing continuation(const std::string& path, std::optional<std::uint64_t> resumedAt) {
    if (!resumedAt) return io::Existing::Replace;
    if (!hasContent(path)) return io::Existing::Append;
    std::ifstream in(path, std::ios::binary);
    std::string header;
    std::getline(in, header);
    if (header != kHeader) refuseToAppend(path, "its header is '" + io::printable(header) + "', not '" + kHeader + "'");
    LinesFromEnd lines(path);
    std::string last;
    lines.previous(last);
    if (last == kHeader) return io::Existing::Append;  // no rows yet
    std::uint64_t step = 0;
    if (!parseStep(last.substr(0, last.find(',')), step))
        refuseToAppend(path, "its last row '" + io::printable(last) + "' does not start with a step");
    requireAppendable(path, "row", step, *resumedAt);
    return io::Existing::Append;
}

}  // namespace

StatsWriter::StatsWriter(const std::string& path, std::optional<std::uint64_t> resumedAt)
    : file_(path, continuation(path, resumedAt)) {
    if (!file_.continues()) file_.append(kHeader + '\n');
}

void StatsWriter::write(std::uint64_t step, double time, const Diagnostics& d, std::uint64_t collisions) {
    std::string row;
    appendNumber(row, step);
    for (double value : {time, d.kineticEnergy, d.momentum[0], d.momentum[1]}) {
        row += ',';
        appendNumber(row, value);
    }
    row += ',';
    appendNumber(row, collisions);
    row += ',';
    appendNumber(row, d.maxOverlap);
    row += ',';
    appendNumber(row, d.escaped);
    row += '\n';
    file_.append(row);
    ++rows_;
}

}  // namespace carom
