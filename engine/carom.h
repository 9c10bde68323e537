// carom's public definitions: what a world, a scene and a backend are made of.
//
// Every field states its unit and default. The same SceneDef drives `carom run`,
// the tests and (later) the viewer and the benchmark, so a scene means the
// same thing everywhere. Units are whatever the user picks for length, mass and
// time; the defaults describe disks of radius 1 moving at speed 1.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/particle.h"

namespace carom {

// Every refusal of bad input: the message names the value and what is allowed.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The most particles a scene, state file or checkpoint may hold: particle
// ids and grid cell offsets are 32-bit, and the grid's up to 4 cells per
// particle must stay countable in an int.
constexpr std::uint64_t kMaxParticles = 500'000'000;

// What happens at the edges of the box.
enum class Boundary {
    Walls,     // reflective walls on all four sides (the default)
    Periodic,  // the box repeats: a disk leaving one side enters the opposite
               //   one, and disks interact with the nearest image of each other
};

// "walls" or "periodic"; throws Error naming the value otherwise.
Boundary parseBoundary(const std::string& name);
const char* boundaryName(Boundary boundary);

// How the collisions of a step are resolved (README, "Collision schemes").
enum class CollisionScheme {
    // The seed's scheme: every overlapping, approaching pair gets the elastic
    // impulse computed from the state before the step, all summed, plus a
    // positional push. Energy drifts (heats) in dense gases: a disk in two
    // contacts at once sums two impulses computed from the same velocities.
    Simultaneous,
    // Binary elastic collisions at their exact contact times, resolved in
    // rounds of mutually earliest events (kernels/pairwise.h): energy is
    // conserved to rounding at any density, also under gravity.
    Pairwise,
    // Exact event-driven dynamics (backends/event_driven_backend.h): free
    // flight between instantaneous binary collisions, event by event, in
    // double on one CPU thread. The ground truth the stepped schemes are
    // measured against; dt only sets when the state is sampled.
    Events,
};

// "simultaneous", "pairwise" or "events"; throws Error naming the value otherwise.
CollisionScheme parseCollisionScheme(const std::string& name);
const char* collisionSchemeName(CollisionScheme scheme);

// The ranges in which carom's float32 arithmetic gives valid results
// (README, "Limits"): squares, sums and tallies that stay normal floats
// (FLT_MIN 1.2e-38, FLT_MAX 3.4e38). Lengths and dt square to at most 1e36;
// masses keep m_i + m_j, the mass shares (>= 1e-30) and the wall-momentum
// and virial tallies (m v and m r v summed over up to 1024 substeps) finite.
constexpr float kMinLength = 1e-18f;  // box sides and radii [length]
constexpr float kMaxLength = 1e18f;
constexpr float kMinMass = 1e-15f;    // [mass]
constexpr float kMaxMass = 1e15f;
constexpr float kMinDt = 1e-18f;      // [time]
constexpr float kMaxDt = 1e18f;
constexpr float kMaxAcceleration = 1e18f;  // |gravity| [length/time^2]
constexpr float kMaxSpeed = 1e18f;         // [length/time]: (v_i - v_j)^2 stays finite
// The box diagonal times the largest speed a disk can reach [length^2/time]:
// the collision times square (x_i - x_j).(v_i - v_j), up to 4 x this squared.
constexpr double kMaxLengthTimesSpeed = 1e18;
// A step must move a typical disk by at least this many float spacings of
// the positions near the far side of the box (a smaller step is lost or
// wrong by more than 50 %; the rounding error of a step of d spacings is up
// to 1 / (2 d)), and gets a warning below kWarnStepSpacings (error > 5 %).
constexpr double kMinStepSpacings = 1.0;
constexpr double kWarnStepSpacings = 10.0;

// The box and the rules of motion. The world is [0,width] x [0,height].
struct WorldDef {
    float width = 0.0f;    // box width [length], in [kMinLength, kMaxLength]; no default: derived from the scene
    float height = 0.0f;   // box height [length], in [kMinLength, kMaxLength]
    float dt = 0.01f;      // time step [time], in [kMinDt, kMaxDt]; with the particles' speeds it must
                           //   move a typical disk by >= kMinStepSpacings float spacings (validateParticles)
                           //   and the fastest by at most the smaller box side (without --max-travel)
    float2 gravity{0, 0};  // constant acceleration [length/time^2], |g| <= kMaxAcceleration; off by default
    Boundary boundary = Boundary::Walls;
    // Adaptive substeps against tunnelling: when > 0, each step of dt is split
    // into the fewest equal substeps in which no disk moves more than
    // maxTravel x the smallest radius, judged from the fastest disk at the
    // start of the step (plus what gravity adds over the step). 0 = off
    // (every step is one substep) [fraction of the smallest radius], >= 0.
    float maxTravel = 0.0f;
    CollisionScheme collisions = CollisionScheme::Pairwise;  // how collisions are resolved (README)
};

// The fraction `--dt auto` uses when no --max-travel is given.
constexpr float kDefaultMaxTravel = 0.2f;
// The most substeps one step may take before the run is refused as runaway.
constexpr std::uint64_t kMaxSubsteps = 1'000'000;

// Initial conditions: N disks placed without overlap on a jittered hexagonal
// lattice, radii and masses fixed or uniform in a range, velocities of one
// speed in uniformly random directions.
struct SceneDef {
    std::uint32_t particles = 1000;  // N, >= 1
    float packing = 0.3f;    // area fraction sum(pi r^2) / (W H), in (0, 0.7]; sizes a square box (<= kMaxLength)
    float width = 0.0f;      // box [length]; when width and height are > 0 they
    float height = 0.0f;     //   are used instead of packing
    float radiusMin = 1.0f;  // radius drawn uniformly in [radiusMin, radiusMax] [length], in [kMinLength, kMaxLength]
    float radiusMax = 1.0f;
    float massMin = 1.0f;    // mass drawn uniformly in [massMin, massMax] [mass], in [kMinMass, kMaxMass]
    float massMax = 1.0f;
    float speed = 1.0f;      // initial speed of every disk [length/time], in [0, kMaxSpeed]
    std::uint64_t seed = 1;  // random seed; the same seed gives the same particles on every platform
};

// The particles a scene starts from and the box they fill.
struct InitialState {
    float width = 0.0f;
    float height = 0.0f;
    std::vector<Particle> particles;
};

// Which backend runs the step.
struct BackendDef {
    std::string kind = "cpu";  // "cpu" (OpenMP) or "opencl"
    std::string device;        // OpenCL only: index from `carom devices` or part of the
                               //   device name; empty = first GPU, else first device
    std::string pipeline = "seed";  // OpenCL only: "seed" (host grid, state read back each
                                    //   step) or "resident" (grid and state stay on the device)
};

// Throws Error unless every field of the world is finite and in range.
void validate(const WorldDef& world);

// Throws Error unless the scene can be placed (ranges valid, packing reachable).
void validate(const SceneDef& scene);

// Builds the initial particles of a scene. Deterministic in scene.seed.
InitialState makeInitialState(const SceneDef& scene);

// Throws Error unless every particle has finite values, mass and radius in
// their ranges (kMinMass.., kMinLength..), fits in the box and lies inside
// it. `what` names the source in messages (for example the file the
// particles came from).
void validateParticles(const std::vector<Particle>& particles, const WorldDef& world,
                       const std::string& what);

// The checks of a run's start, beyond validateParticles (which it calls):
// throws Error where the motion leaves the ranges in which float32 results
// are valid (box diagonal x the largest reachable speed within
// kMaxLengthTimesSpeed; a step that moves a typical disk by at least
// kMinStepSpacings float spacings and, without max-travel substeps, the
// fastest by at most the smaller box side) or two disks share a centre.
// Returns warnings where results are less accurate than usual: a step of
// fewer than kWarnStepSpacings spacings, and overlaps deeper than a step
// closes (a checkpoint holds the small ones a step leaves; a scene file
// refuses any), with the pair and the overlap. O(N): one grid search.
// Not part of validateParticles, so that the viewer can upload a flicked or
// dropped disk without being refused.
std::vector<std::string> validateStart(const std::vector<Particle>& particles, const WorldDef& world,
                                       const std::string& what);

}  // namespace carom
