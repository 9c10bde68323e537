// Validation of worlds and scenes, and the initial conditions of a scene.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "engine/carom.h"

namespace carom {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kMaxPacking = 0.7f;

template <class... Parts>
[[noreturn]] void fail(const Parts&... parts) {
    std::ostringstream message;
    (message << ... << parts);
    throw Error(message.str());
}

void requirePositive(const char* name, float value) {
    if (!(std::isfinite(value) && value > 0.0f))
        fail(name, " must be a finite number > 0, got ", value);
}

// A range [min, max]; `name` stands for both ends when they are equal
// (`--radius 2` sets both).
void requireRange(const char* name, const char* minName, float min, const char* maxName, float max) {
    if (min == max) return requirePositive(name, min);
    requirePositive(minName, min);
    requirePositive(maxName, max);
    if (min > max) fail(minName, " (", min, ") must not exceed ", maxName, " (", max, ")");
}

// Random numbers specified bit for bit by the C++ standard (std::mt19937_64
// is; the std distributions are not), so a seed gives the same scene with
// every standard library.
class Random {
public:
    explicit Random(std::uint64_t seed) : engine_(seed) {}
    double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)
    float uniform(float lo, float hi) {
        return lo == hi ? lo : static_cast<float>(lo + (double(hi) - lo) * unit());
    }

private:
    std::mt19937_64 engine_;
};

// A hexagonal lattice of cols x rows sites spread over the part of the box
// where a disk of the largest radius fits; odd rows are shifted by half a
// spacing.
struct Lattice {
    int cols = 1;
    int rows = 1;
    double spacingX = 0.0;  // 0 when there is a single column
    double spacingY = 0.0;  // 0 when there is a single row
    double minDistance = 0.0;

    static Lattice make(int cols, int rows, double innerWidth, double innerHeight) {
        constexpr double inf = std::numeric_limits<double>::infinity();
        Lattice l;
        l.cols = cols;
        l.rows = rows;
        const bool shifted = cols > 1 && rows > 1;
        if (cols > 1) l.spacingX = innerWidth / (shifted ? cols - 0.5 : cols - 1);
        if (rows > 1) l.spacingY = innerHeight / (rows - 1);
        const double dx = cols > 1 ? l.spacingX : inf;
        const double dy = rows > 1 ? l.spacingY : inf;
        // Shifted rows: the nearest sites are in the same row, the next row
        // (half a spacing across) or two rows away (straight above).
        l.minDistance = shifted ? std::min({dx, std::hypot(dx / 2, dy), 2 * dy}) : std::min(dx, dy);
        return l;
    }

    // The densest lattice for n sites: the one whose closest sites are farthest apart.
    static Lattice best(std::uint32_t n, double innerWidth, double innerHeight) {
        const double ideal = std::sqrt(n * (innerWidth + 1e-12) / ((innerHeight + 1e-12) * 0.866));
        const int lastCols = static_cast<int>(std::min<double>(n, 2 * ideal + 2));
        Lattice best = make(1, static_cast<int>(n), innerWidth, innerHeight);
        for (int cols = 2; cols <= lastCols; ++cols) {
            const int rows = static_cast<int>((n + cols - 1) / cols);
            const Lattice l = make(cols, rows, innerWidth, innerHeight);
            if (l.minDistance > best.minDistance) best = l;
        }
        return best;
    }

    double siteX(int col, int row, double width, double margin) const {
        if (cols == 1) return width / 2;
        return margin + (col + (rows > 1 && row % 2 ? 0.5 : 0.0)) * spacingX;
    }
    double siteY(int row, double height, double margin) const {
        return rows == 1 ? height / 2 : margin + row * spacingY;
    }
};

}  // namespace

Boundary parseBoundary(const std::string& name) {
    if (name == "walls") return Boundary::Walls;
    if (name == "periodic") return Boundary::Periodic;
    fail("unknown boundary '", name, "'; allowed: walls, periodic");
}

const char* boundaryName(Boundary boundary) { return boundary == Boundary::Periodic ? "periodic" : "walls"; }

CollisionScheme parseCollisionScheme(const std::string& name) {
    if (name == "simultaneous") return CollisionScheme::Simultaneous;
    if (name == "pairwise") return CollisionScheme::Pairwise;
    if (name == "events") fail("collision scheme 'events' (exact event-driven dynamics) is not available yet; allowed: pairwise, simultaneous");
    fail("unknown collision scheme '", name, "'; allowed: pairwise, simultaneous");
}

const char* collisionSchemeName(CollisionScheme scheme) {
    return scheme == CollisionScheme::Pairwise ? "pairwise" : "simultaneous";
}

void validate(const WorldDef& world) {
    requirePositive("box width", world.width);
    requirePositive("box height", world.height);
    requirePositive("dt", world.dt);
    if (!std::isfinite(world.gravity.x) || !std::isfinite(world.gravity.y))
        fail("gravity must be finite, got (", world.gravity.x, ", ", world.gravity.y, ")");
    if (world.boundary != Boundary::Walls && world.boundary != Boundary::Periodic)
        fail("boundary code ", static_cast<int>(world.boundary), " is unknown; allowed: walls, periodic");
    if (!(std::isfinite(world.maxTravel) && world.maxTravel >= 0.0f))
        fail("max-travel must be a finite number >= 0 (0 = fixed dt), got ", world.maxTravel);
    if (world.collisions != CollisionScheme::Simultaneous && world.collisions != CollisionScheme::Pairwise)
        fail("collision scheme code ", static_cast<int>(world.collisions), " is unknown; allowed: pairwise, simultaneous");
}

void validate(const SceneDef& scene) {
    if (scene.particles < 1) fail("particles must be >= 1, got ", scene.particles);
    const bool boxGiven = scene.width != 0.0f || scene.height != 0.0f;
    if (boxGiven) {
        requirePositive("box width", scene.width);
        requirePositive("box height", scene.height);
    } else if (!(std::isfinite(scene.packing) && scene.packing > 0.0f &&
                 scene.packing <= kMaxPacking)) {
        fail("packing must be in (0, ", kMaxPacking, "], got ", scene.packing);
    }
    requireRange("radius", "radius-min", scene.radiusMin, "radius-max", scene.radiusMax);
    requireRange("mass", "mass-min", scene.massMin, "mass-max", scene.massMax);
    if (!(std::isfinite(scene.speed) && scene.speed >= 0.0f))
        fail("speed must be a finite number >= 0, got ", scene.speed);
}

InitialState makeInitialState(const SceneDef& scene) {
    validate(scene);
    Random random(scene.seed);
    InitialState state;
    state.particles.resize(scene.particles);

    double diskArea = 0.0;
    for (Particle& p : state.particles) {
        p = Particle{};
        p.radius = random.uniform(scene.radiusMin, scene.radiusMax);
        p.mass = random.uniform(scene.massMin, scene.massMax);
        diskArea += kPi * double(p.radius) * p.radius;
    }
    const bool boxGiven = scene.width > 0.0f;
    state.width = boxGiven ? scene.width : static_cast<float>(std::sqrt(diskArea / scene.packing));
    state.height = boxGiven ? scene.height : state.width;
    const double packing = diskArea / (double(state.width) * state.height);

    const double rmax = scene.radiusMax;
    const double innerWidth = state.width - 2 * rmax;
    const double innerHeight = state.height - 2 * rmax;
    if (innerWidth < 0 || innerHeight < 0)
        fail("a disk of radius ", scene.radiusMax, " does not fit in the ", state.width, " x ",
             state.height, " box");

    // Keep a gap of a few float ulps between neighbours so that rounding the
    // positions to float cannot create an overlap.
    const double gap = 1e-6 * std::max(state.width, state.height);
    const Lattice lattice = Lattice::best(scene.particles, innerWidth, innerHeight);
    const double freeSpace = lattice.minDistance - 2 * rmax - gap;
    if (freeSpace < 0) {
        const double reachable = packing * std::pow(std::min(1.0, lattice.minDistance / (2 * rmax + gap)), 2);
        fail("cannot place ", scene.particles, " disks of radius up to ", scene.radiusMax,
             " without overlap in a ", state.width, " x ", state.height, " box (packing ", packing,
             "); with these radii the lattice placement reaches packing ", reachable,
             " at most: lower the packing or the number of disks, or enlarge the box");
    }

    // Spread the N disks evenly over the lattice sites and jitter each inside
    // the free space around its site (a lone site has infinite free space).
    const double jitter = std::min(freeSpace, std::min(innerWidth, innerHeight)) / 2;
    const std::uint64_t sites = std::uint64_t(lattice.cols) * lattice.rows;
    for (std::uint32_t k = 0; k < scene.particles; ++k) {
        Particle& p = state.particles[k];
        const std::uint64_t site = std::uint64_t(k) * sites / scene.particles;
        const int col = static_cast<int>(site % lattice.cols);
        const int row = static_cast<int>(site / lattice.cols);
        const double angle = 2 * kPi * random.unit();
        const double distance = jitter * std::sqrt(random.unit());
        const double x = lattice.siteX(col, row, state.width, rmax) + distance * std::cos(angle);
        const double y = lattice.siteY(row, state.height, rmax) + distance * std::sin(angle);
        p.position.x = static_cast<float>(std::clamp(x, double(p.radius), state.width - double(p.radius)));
        p.position.y = static_cast<float>(std::clamp(y, double(p.radius), state.height - double(p.radius)));
    }
    for (Particle& p : state.particles) {
        const double angle = 2 * kPi * random.unit();
        p.velocity.x = static_cast<float>(scene.speed * std::cos(angle));
        p.velocity.y = static_cast<float>(scene.speed * std::sin(angle));
    }
    return state;
}

void validateParticles(const std::vector<Particle>& particles, const WorldDef& world,
                       const std::string& what) {
    validate(world);
    if (particles.empty()) fail(what, ": no particles (at least 1 is needed)");
    for (std::size_t i = 0; i < particles.size(); ++i) {
        const Particle& p = particles[i];
        const float r = p.radius;
        if (!(std::isfinite(r) && r > 0.0f))
            fail(what, ": particle ", i, ": radius must be a finite number > 0, got ", r);
        if (!(std::isfinite(p.mass) && p.mass > 0.0f))
            fail(what, ": particle ", i, ": mass must be a finite number > 0, got ", p.mass);
        if (!std::isfinite(p.velocity.x) || !std::isfinite(p.velocity.y))
            fail(what, ": particle ", i, ": velocity must be finite, got (", p.velocity.x, ", ",
                 p.velocity.y, ")");
        if (2.0f * r > world.width || 2.0f * r > world.height)
            fail(what, ": particle ", i, ": radius ", r, " does not fit in the ", world.width,
                 " x ", world.height, " box");
        const float2 x = p.position;
        if (world.boundary == Boundary::Periodic) {
            // Where the wrap in integrate keeps centres.
            if (!(x.x >= 0.0f && x.x < world.width && x.y >= 0.0f && x.y < world.height))
                fail(what, ": particle ", i, ": position (", x.x, ", ", x.y, ") is outside the periodic box; ",
                     "the centre must lie in [0, ", world.width, ") x [0, ", world.height, ")");
            continue;
        }
        // The same bounds the walls clamp to, so a saved final state reads back.
        if (!(x.x >= r && x.x <= world.width - r && x.y >= r && x.y <= world.height - r))
            fail(what, ": particle ", i, ": position (", x.x, ", ", x.y,
                 ") puts the disk outside the box; the centre must lie in [", r, ", ",
                 world.width - r, "] x [", r, ", ", world.height - r, "]");
    }
}

}  // namespace carom
