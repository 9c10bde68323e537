#include "engine/stats.h"

#include "engine/text_format.h"

namespace carom {

StatsWriter::StatsWriter(const std::string& path) : file_(path) {
    file_.append("step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped\n");
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
