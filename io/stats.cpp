#include <carom/io.h>
#include "io/stats.h"

#include <fstream>
#include <sstream>
#include <vector>

#include "io/output_paths.h"
#include "engine/text_format.h"

namespace carom {
namespace {

const std::string kHeader = "step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped";

// The fields of a CSV row.
std::vector<std::string> fieldsOf(const std::string& row) {
    std::vector<std::string> fields;
    std::istringstream in(row);
    for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
    return fields;
}

// How a run resumed from `resumed` (if it is) opens `path`: appending, once
// the rows already there are found to have this header and to lead up to the
// checkpoint, of the same simulation.
io::Existing continuation(const std::string& path, const Resumed* resumed) {
    if (!resumed) return io::Existing::Replace;
    if (!hasContent(path)) return io::Existing::Append;
    std::ifstream in(path, std::ios::binary);
    std::string header(kHeader.size() + 1, '\0');  // no more: the file may be one huge line
    header.resize(std::size_t(in.read(header.data(), std::streamsize(header.size())).gcount()));
    if (header != kHeader + '\n')
        refuseToAppend(
            path, "its header is '" + io::printable(header.substr(0, header.find('\n'))) + "', not '" + kHeader + "'");
    LinesFromEnd lines(path);
    std::string last;
    lines.previous(last);
    if (last == kHeader) return io::Existing::Append;  // no rows yet
    const std::vector<std::string> row = fieldsOf(last);
    std::uint64_t step = 0, collisions = 0;
    if (!parseStep(row.empty() ? "" : row[0], step))
        refuseToAppend(path, "its last row '" + io::printable(last) + "' does not start with a step");
    requireAppendable(path, "row", step, *resumed);
    std::string time;
    appendNumber(time, resumed->time);
    const std::string another = "its last row, at step " + std::to_string(step) + ", ";
    const std::string simulation = ", so it is another simulation's statistics";
    if (row.size() != 8 || !parseStep(row[5], collisions))
        refuseToAppend(path, another + "is no row of 8 columns with a count of collisions" + simulation);
    if (collisions > resumed->collisions)
        refuseToAppend(path, another + "counts " + row[5] + " collisions, more than " + resumed->name + "'s " +
                                 std::to_string(resumed->collisions) + simulation);
    if (step == resumed->step && (row[1] != time || collisions != resumed->collisions))
        refuseToAppend(path, another + resumed->name + "'s, has time " + io::printable(row[1]) + " and " + row[5] +
                                 " collisions, " + resumed->name + " " + time + " and " +
                                 std::to_string(resumed->collisions) + simulation);
    return io::Existing::Append;
}

}  // namespace

StatsWriter::StatsWriter(const std::string& path, const Resumed* resumed) : file_(path, continuation(path, resumed)) {
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
