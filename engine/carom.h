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
};

// "simultaneous" or "pairwise"; throws Error naming the value otherwise.
CollisionScheme parseCollisionScheme(const std::string& name);
const char* collisionSchemeName(CollisionScheme scheme);

// The box and the rules of motion. The world is [0,width] x [0,height].
struct WorldDef {
    float width = 0.0f;    // box width [length], > 0; no default: derived from the scene
    float height = 0.0f;   // box height [length], > 0
    float dt = 0.01f;      // time step [time], > 0
    float2 gravity{0, 0};  // constant acceleration [length/time^2]; off by default
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
    float packing = 0.3f;    // area fraction sum(pi r^2) / (W H), in (0, 0.7]; sizes a square box
    float width = 0.0f;      // box [length]; when width and height are > 0 they
    float height = 0.0f;     //   are used instead of packing
    float radiusMin = 1.0f;  // radius drawn uniformly in [radiusMin, radiusMax] [length], > 0
    float radiusMax = 1.0f;
    float massMin = 1.0f;    // mass drawn uniformly in [massMin, massMax] [mass], > 0
    float massMax = 1.0f;
    float speed = 1.0f;      // initial speed of every disk [length/time], >= 0
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

// Throws Error unless every particle has finite values, positive mass and
// radius, fits in the box and lies inside it. `what` names the source in
// messages (for example the file the particles came from).
void validateParticles(const std::vector<Particle>& particles, const WorldDef& world,
                       const std::string& what);

}  // namespace carom
