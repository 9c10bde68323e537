#include "io/trajectory.h"

#include <algorithm>

#include "io/output_paths.h"
#include "engine/text_format.h"

namespace carom {
namespace {

// How a run of `particles` disks resumed at `resumedAt` (if it is) opens
// `path`: appending, once the frames already there are found to end at or
// before that step, with as many disks.
io::Existing continuation(const std::string& path, std::optional<std::uint64_t> resumedAt, std::size_t particles) {
    if (!resumedAt) return io::Existing::Replace;
    if (!hasContent(path)) return io::Existing::Append;
    LinesFromEnd lines(path);
    for (std::string line; lines.previous(line);) {
        if (line.rfind("Lattice=", 0) != 0) continue;
        const std::size_t value = line.find(" step=");
        std::uint64_t step = 0;
        if (value == std::string::npos ||
            !parseStep(line.substr(value + 6, line.find(' ', value + 6) - (value + 6)), step))
            break;
        requireAppendable(path, "frame", step, *resumedAt);
        std::string count;
        if (lines.previous(count) && count != std::to_string(particles))
            refuseToAppend(path, "its last frame has " + count + " disks, the checkpoint " + std::to_string(particles) +
                                     ", so it is another simulation's trajectory");
        return io::Existing::Append;
    }
    refuseToAppend(path, "it has no frame header with a step=, so it is no carom trajectory");
}

}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& path, std::optional<std::uint64_t> resumedAt,
                                   std::size_t particles)
    : file_(path, continuation(path, resumedAt, particles)) {}

void TrajectoryWriter::write(const std::vector<Disk>& disks, const WorldDef& world, std::uint64_t step, double time) {
    float maxRadius = 0.0f;
    for (const Disk& d : disks) maxRadius = std::max(maxRadius, d.radius);

    std::string& out = frame_;
    out.clear();
    appendNumber(out, disks.size());
    out += "\nLattice=\"";
    appendNumber(out, world.width);
    out += " 0 0 0 ";
    appendNumber(out, world.height);
    out += " 0 0 0 ";
    appendNumber(out, 2.0f * maxRadius);
    out += "\" Origin=\"0 0 ";
    appendNumber(out, -maxRadius);
    out += "\" pbc=\"F F F\" Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:id:I:1 step=";
    appendNumber(out, step);
    out += " time=";
    appendNumber(out, time);
    out += '\n';
    for (std::size_t i = 0; i < disks.size(); ++i) {
        const Disk& d = disks[i];
        out += "X ";
        appendNumber(out, d.position.x);
        out += ' ';
        appendNumber(out, d.position.y);
        out += " 0 ";
        appendNumber(out, d.velocity.x);
        out += ' ';
        appendNumber(out, d.velocity.y);
        out += " 0 ";
        appendNumber(out, d.radius);
        out += ' ';
        appendNumber(out, d.mass);
        out += ' ';
        appendNumber(out, i);
        out += '\n';
    }
    file_.append(out);
    ++frames_;
}

}  // namespace carom
