#include "engine/trajectory.h"

#include <algorithm>

#include "engine/text_format.h"

namespace carom {

TrajectoryWriter::TrajectoryWriter(const std::string& path) : file_(path) {}

void TrajectoryWriter::write(const std::vector<Particle>& particles, const WorldDef& world, std::uint64_t step,
                             double time) {
    float maxRadius = 0.0f;
    for (const Particle& p : particles) maxRadius = std::max(maxRadius, p.radius);

    std::string& out = frame_;
    out.clear();
    appendNumber(out, particles.size());
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
    for (std::size_t i = 0; i < particles.size(); ++i) {
        const Particle& p = particles[i];
        out += "X ";
        appendNumber(out, p.position.x);
        out += ' ';
        appendNumber(out, p.position.y);
        out += " 0 ";
        appendNumber(out, p.velocity.x);
        out += ' ';
        appendNumber(out, p.velocity.y);
        out += " 0 ";
        appendNumber(out, p.radius);
        out += ' ';
        appendNumber(out, p.mass);
        out += ' ';
        appendNumber(out, i);
        out += '\n';
    }
    file_.append(out);
    ++frames_;
}

}  // namespace carom
