// Names of the boundaries and collision schemes, and the validation of worlds,
// scenes and particles (the initial conditions are placed in scene_placement.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>

#include "engine/scene.h"
#include "engine/constants.h"
#include "engine/diagnostics.h"
#include "engine/error_message.h"
#include "engine/parallel.h"

namespace carom {
namespace {

// A finite value > 0 inside the range where float32 results are valid.
void requireWithin(std::string_view name, float value, float least, float most, const char* reason) {
    requirePositive(name, value);
    if (value < least || value > most)
        fail(name, " ", value, " is outside [", least, ", ", most, "], the range where results are valid: ", reason,
             " (README, Limits)");
}

constexpr const char* kLengthReason = "squared distances must stay normal, finite float32 numbers";
constexpr const char* kMassReason = "sums of masses and the momentum tallies must stay finite float32 numbers";

// A range [min, max] within [least, most]; `name` stands for both ends when
// they are the same (`--radius 2` sets both, as `--radius nan` does).
void requireRange(const char* name, const char* minName, float min, const char* maxName, float max, float least,
                  float most, const char* reason) {
    if (min == max || (std::isnan(min) && std::isnan(max))) return requireWithin(name, min, least, most, reason);
    requireWithin(minName, min, least, most, reason);
    requireWithin(maxName, max, least, most, reason);
    if (min > max) fail(minName, " (", min, ") must not exceed ", maxName, " (", max, ")");
}

// The distance between a coordinate just below `extent` and the next float:
// how finely positions near the far side of the box are resolved.
double floatSpacingBelow(float extent) { return double(extent) - std::nextafter(extent, 0.0f); }

// The largest box whose positions are resolved to `spacing` or finer: below
// 2^k the spacing is 2^(k - 24).
double largestBoxFor(double spacing) { return std::exp2(std::floor(std::log2(spacing)) + 24); }

// Disks per block of motionScale's sums.
constexpr std::int64_t kMotionBlock = 1 << 16;

// What the particles and the world imply for the motion, for the range checks.
struct MotionScale {
    double fastest = 0.0;     // a bound on any disk's speed: the fastest now, plus a step of gravity and a fall
                              //   across the box diagonal
    double typical = 0.0;     // the speed the heaviest disks settle at: sqrt(sum m v^2 / (N m_max)) with the
                              //   energy of a fall across the box, |g_x| W + |g_y| H, added to its square; or,
                              //   when smaller, the moving disks' median speed (the same fall added): one fast
                              //   disk holds most of the energy, but the slow ones move (or not) at their own
    double fastestNow = 0.0;  // the fastest disk's speed now, plus a step of gravity
    double smallestRadius = 0.0;
    double step = 0.0;  // dt, or the substep --max-travel splits it into (as the backend does at the start)
    double diagonal = 0.0;
    double spacing = 0.0;                           // of the positions near the far side of the box
    double move() const { return typical * step; }  // a typical disk's displacement per step
    double spacings() const { return move() / spacing; }
};

MotionScale motionScale(const std::vector<Particle>& particles, const WorldDef& world) {
    const double fall =
        std::fabs(double(world.gravity.x)) * world.width + std::fabs(double(world.gravity.y)) * world.height;
    // In blocks of fixed size, in parallel; the blocks' sums added in order:
    // the same bits on any number of threads.
    const auto n = static_cast<std::int64_t>(particles.size());
    const std::int64_t blocks = (n + kMotionBlock - 1) / kMotionBlock;
    std::vector<double> blockKinetic(std::size_t(blocks), 0.0);
    double fastest = 0.0, heaviest = 0.0, smallestRadius = HUGE_VAL;
    // The squared speeds of the disks that move, the fall added; +inf for
    // those that do not, which lie above the median of those that do.
    UninitialisedVector<double> moving(particles.size());
    std::int64_t movingCount = 0;
#pragma omp parallel for schedule(static) reduction(max : fastest, heaviest) reduction(min : smallestRadius) \
    reduction(+ : movingCount) if (blocks > 1)
    for (std::int64_t b = 0; b < blocks; ++b) {
        double twiceKinetic = 0.0;
        for (std::int64_t i = b * kMotionBlock; i < std::min(n, (b + 1) * kMotionBlock); ++i) {
            const Particle& p = particles[std::size_t(i)];
            const double speed = std::hypot(double(p.velocity.x), double(p.velocity.y));
            fastest = std::max(fastest, speed);
            twiceKinetic += p.mass * speed * speed;
            heaviest = std::max(heaviest, double(p.mass));
            smallestRadius = std::min(smallestRadius, double(p.radius));
            const bool moves = speed * speed + fall > 0.0;
            moving[std::size_t(i)] = moves ? speed * speed + fall : HUGE_VAL;
            movingCount += moves;
        }
        blockKinetic[std::size_t(b)] = twiceKinetic;
    }
    double twiceKinetic = 0.0;
    for (const double k : blockKinetic) twiceKinetic += k;
    const double gravity = std::hypot(double(world.gravity.x), double(world.gravity.y));
    MotionScale m;
    m.diagonal = std::hypot(double(world.width), double(world.height));
    m.fastestNow = fastest + gravity * world.dt;
    m.fastest = m.fastestNow + std::sqrt(2 * gravity * m.diagonal);
    m.smallestRadius = smallestRadius;
    m.typical = std::sqrt(twiceKinetic / (double(particles.size()) * heaviest) + fall);
    if (movingCount > 0) {
        const double median =
            kthSmallest(moving.size(), std::size_t(movingCount / 2), [&](std::size_t i) { return moving[i]; });
        m.typical = std::min(m.typical, std::sqrt(median));
    }
    m.step = world.dt;
    if (world.maxTravel > 0.0f) {
        const double substeps =
            std::ceil((fastest + gravity * world.dt) * world.dt / (world.maxTravel * smallestRadius));
        if (substeps > 1) m.step = world.dt / std::min(substeps, double(kMaxSubsteps));
    }
    m.spacing = floatSpacingBelow(std::max(world.width, world.height));
    return m;
}

// Refuses motion outside the ranges the checks of `m` allow (requireValidMotion).
void requireValidMotion(const MotionScale& m, const WorldDef& world, const std::string& what) {
    if (m.fastest > kMaxSpeed || m.fastest * m.diagonal > kMaxLengthTimesSpeed)
        fail(what, ": the largest speed a disk can reach, ", m.fastest,
             " (the fastest now plus what gravity adds across the box), times the box diagonal ", m.diagonal, " is ",
             m.fastest * m.diagonal, "; results are valid up to ", kMaxLengthTimesSpeed, " and speeds up to ",
             kMaxSpeed, ", where the squares in the collision times stay finite float32 numbers (README, Limits)");
    // The event-driven scheme moves disks exactly, in double, whatever dt
    // (which only sets when the state is sampled): no step-size limits.
    if (world.collisions == CollisionScheme::Events) return;
    const double side = std::min(world.width, world.height);
    if (world.maxTravel == 0.0f && m.fastest * world.dt > side)
        fail(what, ": a step of dt ", world.dt, " moves the fastest disk (speed up to ", m.fastest, ") by ",
             m.fastest * world.dt, ", more than the box side ", side, "; the largest dt is ", side / m.fastest,
             " (or split each step into substeps: WorldDef::maxTravel > 0, on the command line --max-travel or "
             "--dt auto)");
    if (m.typical > 0.0 && m.spacings() < kMinStepSpacings)
        fail(
            what, ": a step moves a typical disk (speed ", m.typical, ", step ", m.step, ") by ", m.move(),
            ", less than the float32 spacing ", m.spacing, " of positions in the ", world.width, " x ", world.height,
            " box, so its motion would be lost or wrong by more than 50 %; for these speeds and dt the largest box is ",
            largestBoxFor(m.move() / kMinStepSpacings), " (README, Limits)");
}

}  // namespace

void requireValidMotion(const std::vector<Particle>& particles, const WorldDef& world, const std::string& what) {
    requireValidMotion(motionScale(particles, world), world, what);
}

Boundary parseBoundary(const std::string& name) {
    if (name == "walls") return Boundary::Walls;
    if (name == "periodic") return Boundary::Periodic;
    fail("unknown boundary '", name, "'; allowed: walls, periodic");
}

const char* boundaryName(Boundary boundary) { return boundary == Boundary::Periodic ? "periodic" : "walls"; }

CollisionScheme parseCollisionScheme(const std::string& name) {
    if (name == "simultaneous") return CollisionScheme::Simultaneous;
    if (name == "pairwise") return CollisionScheme::Pairwise;
    if (name == "events") return CollisionScheme::Events;
    fail("unknown collision scheme '", name, "'; allowed: pairwise, simultaneous, events");
}

const char* collisionSchemeName(CollisionScheme scheme) {
    switch (scheme) {
        case CollisionScheme::Simultaneous: return "simultaneous";
        case CollisionScheme::Pairwise: return "pairwise";
        case CollisionScheme::Events: return "events";
    }
    return "unknown";
}

void validate(const WorldDef& world) {
    requireWithin("box width", world.width, kMinLength, kMaxLength, kLengthReason);
    requireWithin("box height", world.height, kMinLength, kMaxLength, kLengthReason);
    requireWithin("dt", world.dt, kMinDt, kMaxDt, "dt and its square must stay normal, finite float32 numbers");
    if (!std::isfinite(world.gravity.x) || !std::isfinite(world.gravity.y))
        fail("gravity must be finite, got (", world.gravity.x, ", ", world.gravity.y, ")");
    if (std::hypot(world.gravity.x, world.gravity.y) > kMaxAcceleration)
        fail("gravity (", world.gravity.x, ", ", world.gravity.y, ") is stronger than ", kMaxAcceleration,
             ", the most where results are valid: the speeds it gives must square to finite float32 numbers "
             "(README, Limits)");
    if (world.boundary != Boundary::Walls && world.boundary != Boundary::Periodic)
        fail("boundary code ", static_cast<int>(world.boundary), " is unknown; allowed: walls, periodic");
    if (!(std::isfinite(world.maxTravel) && world.maxTravel >= 0.0f))
        fail("max-travel must be a finite number >= 0 (0 = fixed dt), got ", world.maxTravel);
    if (!(std::isfinite(world.skin) && world.skin >= 0.0f))
        fail("skin must be a finite number >= 0 (0 = automatic), got ", world.skin);
    if (world.collisions != CollisionScheme::Simultaneous && world.collisions != CollisionScheme::Pairwise &&
        world.collisions != CollisionScheme::Events)
        fail("collision scheme code ", static_cast<int>(world.collisions),
             " is unknown; allowed: pairwise, simultaneous, events");
}

void validate(const SceneDef& scene) {
    if (scene.particles < 1) fail("particles must be >= 1, got ", scene.particles);
    const bool boxGiven = scene.width != 0.0f || scene.height != 0.0f;
    if (boxGiven) {
        requireWithin("box width", scene.width, kMinLength, kMaxLength, kLengthReason);
        requireWithin("box height", scene.height, kMinLength, kMaxLength, kLengthReason);
    } else if (!(std::isfinite(scene.packing) && scene.packing > 0.0f && scene.packing <= kMaxPacking)) {
        fail("packing must be in (0, ", kMaxPacking, "], got ", scene.packing);
    }
    requireRange("radius", "radius-min", scene.radiusMin, "radius-max", scene.radiusMax, kMinLength, kMaxLength,
                 kLengthReason);
    requireRange("mass", "mass-min", scene.massMin, "mass-max", scene.massMax, kMinMass, kMaxMass, kMassReason);
    requireNonNegative("speed", scene.speed);
    if (scene.speed > kMaxSpeed)
        fail("speed ", scene.speed, " is outside [0, ", kMaxSpeed,
             "], the range where results are valid: speeds must square to finite float32 numbers (README, Limits)");
}

namespace {

// Whether particle p fits `world`: checkParticle's conditions, without its
// messages, so that millions of particles are checked in parallel.
bool particleFits(const Particle& p, const WorldDef& world) {
    const float r = p.radius;
    const auto within = [](float v, float least, float most) { return std::isfinite(v) && v >= least && v <= most; };
    if (!within(r, kMinLength, kMaxLength) || !within(p.mass, kMinMass, kMaxMass) || !(r > 0.0f) || !(p.mass > 0.0f) ||
        !std::isfinite(p.velocity.x) || !std::isfinite(p.velocity.y) || 2.0f * r > world.width ||
        2.0f * r > world.height)
        return false;
    const float2 x = p.position;
    if (world.boundary == Boundary::Periodic)
        return x.x >= 0.0f && x.x < world.width && x.y >= 0.0f && x.y < world.height;
    return x.x >= r && x.x <= world.width - r && x.y >= r && x.y <= world.height - r;
}

// Throws the Error that names particle i's first problem, if it has one.
void checkParticle(const Particle& p, std::size_t i, const WorldDef& world, const std::string& what) {
    const float r = p.radius;
    const std::string particle = what + ": particle " + std::to_string(i) + ": ";
    requirePositive(particle + "radius", r);
    requirePositive(particle + "mass", p.mass);
    if (!std::isfinite(p.velocity.x) || !std::isfinite(p.velocity.y))
        fail(particle, "velocity must be finite, got (", p.velocity.x, ", ", p.velocity.y, ")");
    requireWithin(particle + "radius", r, kMinLength, kMaxLength, kLengthReason);
    requireWithin(particle + "mass", p.mass, kMinMass, kMaxMass, kMassReason);
    if (2.0f * r > world.width || 2.0f * r > world.height)
        fail(what, ": particle ", i, ": radius ", r, " does not fit in the ", world.width, " x ", world.height, " box");
    const float2 x = p.position;
    if (!std::isfinite(x.x) || !std::isfinite(x.y))
        fail(particle, "position must be finite, got (", x.x, ", ", x.y, ")");
    if (world.boundary == Boundary::Periodic) {
        // Where the wrap in integrate keeps centres.
        if (!(x.x >= 0.0f && x.x < world.width && x.y >= 0.0f && x.y < world.height))
            fail(what, ": particle ", i, ": position (", x.x, ", ", x.y, ") is outside the periodic box; ",
                 "the centre must lie in [0, ", world.width, ") x [0, ", world.height, ")");
        return;
    }
    // The same bounds the walls clamp to, so a saved final state reads back.
    if (!(x.x >= r && x.x <= world.width - r && x.y >= r && x.y <= world.height - r))
        fail(what, ": particle ", i, ": position (", x.x, ", ", x.y,
             ") puts the disk outside the box; the centre must lie in [", r, ", ", world.width - r, "] x [", r, ", ",
             world.height - r, "]");
}

}  // namespace

void validateParticles(const std::vector<Particle>& particles, const WorldDef& world, const std::string& what) {
    validate(world);
    if (particles.empty()) fail(what, ": no particles (at least 1 is needed)");
    // The lowest id that does not fit, found in parallel; then its message.
    const auto n = static_cast<std::int64_t>(particles.size());
    std::int64_t first = n;
#pragma omp parallel for reduction(min : first) schedule(static) if (n >= kParallelLength)
    for (std::int64_t i = 0; i < n; ++i)
        if (!particleFits(particles[i], world)) first = std::min(first, i);
    if (first == n) return;
    checkParticle(particles[first], std::size_t(first), world, what);
    fail(what, ": particle ", first, " does not fit the world");  // the two checks disagree: refuse anyway
}

std::vector<std::string> validateStart(const std::vector<Particle>& particles, const WorldDef& world,
                                       const std::string& what, DeepOverlaps deepOverlaps) {
    validateParticles(particles, world, what);
    const MotionScale m = motionScale(particles, world);
    requireValidMotion(m, world, what);
    const Overlaps overlaps = findOverlaps(particles, world);
    if (overlaps.coincident > 0) {
        const auto [i, j] = overlaps.coincidentPair;
        fail(what, ": particles ", i, " and ", j, " have the same centre (", particles[i].position.x, ", ",
             particles[i].position.y, "): their collision has no direction; ", overlaps.coincident,
             " such pair(s) in all: move one disk of each");
    }

    std::vector<std::string> warnings;
    std::ostringstream text;
    if (world.collisions != CollisionScheme::Events && m.typical > 0.0 && m.spacings() < kWarnStepSpacings) {
        text << "a step moves a typical disk by " << m.move() << ", only " << m.spacings()
             << " float32 spacings of the positions in this box: each step may be off by up to " << 50.0 / m.spacings()
             << " %; boxes up to " << largestBoxFor(m.move() / kWarnStepSpacings) << " keep it within "
             << 50.0 / kWarnStepSpacings << " % at these speeds and dt (README, Limits)";
        warnings.push_back(text.str());
    }
    // The simultaneous scheme finds collisions as overlaps at the ends of
    // steps: two disks that close by more than their contact distance in one
    // step can land past each other's centre, or clear through.
    if (world.collisions == CollisionScheme::Simultaneous && m.fastestNow * m.step > m.smallestRadius) {
        text.str("");
        text << "a step moves the fastest disk (speed " << m.fastestNow << ", step " << m.step << ") by "
             << m.fastestNow * m.step << ", more than the smallest radius " << m.smallestRadius
             << ": two disks meeting head-on at this speed close by more than their contact distance in one step, "
                "and the simultaneous scheme, which looks for collisions only at the ends of steps, can let them "
                "pass through each other; steps up to "
             << m.smallestRadius / m.fastestNow
             << " avoid it (or split each step into substeps: WorldDef::maxTravel <= 1, on the command line "
                "--max-travel or --dt auto; or use the pairwise scheme)";
        warnings.push_back(text.str());
    }
    // Overlaps up to what two disks close in one step, plus rounding, are
    // what a step leaves behind (the simultaneous scheme's overlaps, the
    // pairwise scheme's late contacts); deeper ones did not come from a run.
    // The events scheme moves disks exactly: only rounding leaves overlaps.
    const bool exact = world.collisions == CollisionScheme::Events;
    const double rounding = 1e-6 * (double(world.width) + world.height);
    const double stepClosing = exact ? rounding : 2 * (m.fastest * world.dt) + rounding;
    if (overlaps.deepest > stepClosing) {
        const auto [i, j] = overlaps.deepestPair;
        text.str("");
        text << (overlaps.allCounted ? "" : "more than ") << overlaps.pairs
             << " pair(s) of disks overlap, the deepest particles " << i << " and " << j << " by " << overlaps.deepest
             << " (" << 100 * overlaps.deepest / (double(particles[i].radius) + particles[j].radius)
             << " % of their contact distance), more than " << (exact ? "rounding leaves" : "a step closes") << " ("
             << stepClosing << ")";
        if (deepOverlaps == DeepOverlaps::Refuse) fail(what, ": ", text.str(), "; allowed: overlaps up to that depth");
        text << "; they separate as they move apart (the simultaneous scheme also pushes them apart)";
        warnings.push_back(text.str());
    }
    return warnings;
}

}  // namespace carom
