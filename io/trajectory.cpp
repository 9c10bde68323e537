#include "io/trajectory.h"

#include <algorithm>
#include <fstream>

#include <carom/io.h>

#include "io/output_paths.h"
#include "engine/text_format.h"

namespace carom {
namespace {

// A frame's first two lines up to its step: the disk count, then the cell
// and the columns. The same for every frame of one simulation.
void appendFrameCell(std::string& out, const DiskBlocks& disks, const WorldDef& world) {
    float maxRadius = 0.0f;
    disks.forEach([&](std::size_t, const Disk& d) { maxRadius = std::max(maxRadius, d.radius); });
    appendNumber(out, disks.size());
    out += "\nLattice=\"";
    appendNumber(out, world.width);
    out += " 0 0 0 ";
    appendNumber(out, world.height);
    out += " 0 0 0 ";
    appendNumber(out, 2.0f * maxRadius);
    out += "\" Origin=\"0 0 ";
    appendNumber(out, -maxRadius);
    // A periodic box repeats in x and y, and its disks have images; the slab's depth never does.
    out += world.boundary == Boundary::Periodic ? "\" pbc=\"T T F\" Properties=species:S:1:pos:R:3:velo:R:3:image:I:3"
                                                : "\" pbc=\"F F F\" Properties=species:S:1:pos:R:3:velo:R:3";
    out += ":radius:R:1:mass:R:1:id:I:1";
}

[[noreturn]] void anotherSimulation(const std::string& path, const std::string& what) {
    refuseToAppend(path, "its last frame " + what + ", so it is another simulation's trajectory");
}

// Refuses the frame whose header line starts at `offset` in `path` unless
// the resumed run's first frame could follow it: the same cell and columns,
// the same radius, mass and id on each disk line, and (at the checkpoint's
// step) the same time.
void requireSameSimulation(const std::string& path, std::streamoff offset, std::uint64_t step, const Resumed& resumed) {
    std::string expected;
    appendFrameCell(expected, DiskBlocks(resumed.disks), resumed.world);
    expected.erase(0, expected.find('\n') + 1);
    std::ifstream in(path, std::ios::binary);
    in.seekg(offset);
    std::string line;
    std::getline(in, line);
    if (line.compare(0, expected.size() + 6, expected + " step=") != 0)
        anotherSimulation(path, "has another cell or other columns than " + resumed.name + "'s box and boundary ('" +
                                    io::printable(line.substr(0, line.find(" pbc="))) + "', " + resumed.name + "'s '" +
                                    io::printable(expected.substr(0, expected.find(" pbc="))) + "')");
    if (step == resumed.step) {
        std::string time;
        appendNumber(time, resumed.time);
        const std::size_t at = line.find(" time=");
        if (at == std::string::npos || line.compare(at + 6, std::string::npos, time) != 0)
            anotherSimulation(
                path, "is at " + resumed.name + "'s step " + std::to_string(step) + " but not at its time " + time);
    }
    std::string disk;
    for (std::size_t i = 0; i < resumed.disks.size(); ++i) {
        const Disk& d = resumed.disks[i];
        std::string tail = " ";  // " radius mass id", as write() ends a disk's line
        appendNumber(tail, d.radius);
        tail += ' ';
        appendNumber(tail, d.mass);
        tail += ' ';
        appendNumber(tail, i);
        if (!std::getline(in, line) || line.size() < tail.size() ||
            line.compare(line.size() - tail.size(), tail.size(), tail) != 0)
            anotherSimulation(path, "has disk " + std::to_string(i) + " as '" + io::printable(line) +
                                        "', not ending in " + resumed.name + "'s radius, mass and id '" +
                                        tail.substr(1) + "'");
    }
}

// How a run resumed from `resumed` (if it is) opens `path`: appending, once
// its last frame is found to lead up to the checkpoint, with its disks.
io::Existing continuation(const std::string& path, const Resumed* resumed) {
    if (!resumed) return io::Existing::Replace;
    if (!hasContent(path)) return io::Existing::Append;
    LinesFromEnd lines(path);
    const std::size_t particles = resumed->disks.size();
    std::string line;
    for (std::size_t read = 0; lines.previous(line); ++read) {
        if (line.rfind("Lattice=", 0) != 0) continue;
        const std::streamoff header = lines.offset();
        const std::size_t value = line.find(" step=");
        std::uint64_t step = 0;
        if (value == std::string::npos ||
            !parseStep(line.substr(value + 6, line.find(' ', value + 6) - (value + 6)), step))
            break;
        std::string count;
        if (lines.previous(count) && count != std::to_string(particles))
            refuseToAppend(path, "its last frame has " + io::printable(count) + " disks, " + resumed->name + " " +
                                     std::to_string(particles) + ", so it is another simulation's trajectory");
        if (read != particles)
            anotherSimulation(path, "has " + std::to_string(read) + " disk lines, not " + std::to_string(particles));
        requireSameSimulation(path, header, step, *resumed);
        requireAppendable(path, "frame", step, *resumed);
        return io::Existing::Append;
    }
    refuseToAppend(path, "it has no frame header with a step=, so it is no carom trajectory");
}

}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& path, const Resumed* resumed)
    : file_(path, continuation(path, resumed)) {}

void TrajectoryWriter::write(const DiskBlocks& disks, const WorldDef& world, std::uint64_t step, double time,
                             const std::vector<Image>& images) {
    const bool periodic = world.boundary == Boundary::Periodic;
    std::string& out = frame_;
    out.clear();
    appendFrameCell(out, disks, world);
    out += " step=";
    appendNumber(out, step);
    out += " time=";
    appendNumber(out, time);
    out += '\n';
    disks.forEach([&](std::size_t i, const Disk& d) {
        out += "X ";
        appendNumber(out, d.position.x);
        out += ' ';
        appendNumber(out, d.position.y);
        out += " 0 ";
        appendNumber(out, d.velocity.x);
        out += ' ';
        appendNumber(out, d.velocity.y);
        out += " 0 ";
        if (periodic) {
            const Image image = images.empty() ? Image{0, 0} : images[i];
            appendNumber(out, image[0]);
            out += ' ';
            appendNumber(out, image[1]);
            out += " 0 ";
        }
        appendNumber(out, d.radius);
        out += ' ';
        appendNumber(out, d.mass);
        out += ' ';
        appendNumber(out, i);
        out += '\n';
        if (out.size() >= kFramePiece) {  // written in pieces: the text of a frame is about 60 bytes a disk
            file_.append(out);
            out.clear();
        }
    });
    file_.append(out);
    ++frames_;
}

}  // namespace carom
