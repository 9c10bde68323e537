// The methods `carom bench` compares, each under the collision schemes it
// runs, how to start each one on a scene, and the bytes each must move per
// particle-step: the model that turns a time into a fraction of the
// memory-bandwidth floor. Public types only: app/ includes this.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <carom/world.h>

namespace carom::bench {

struct Method {
    std::string name;
    std::string description;
    bool opencl = false;       // runs on the OpenCL device, else on the host CPU
    bool allPairs = false;     // the naive O(N^2) baseline, simultaneous scheme only
    bool eventDriven = false;  // the event-driven engine, events scheme only: timed in collisions per second
};

// Whether `method` runs `scheme`: the naive baselines run the simultaneous
// scheme only, the events method the events scheme only and the other
// methods the stepped schemes.
bool runsScheme(const Method& method, CollisionScheme scheme);

// A method under one collision scheme: what one line of the results measures.
struct Variant {
    Method method;
    CollisionScheme scheme = CollisionScheme::Simultaneous;
};

// Every method, in the order of the table: the baselines first.
const std::vector<Method>& allMethods();
// The methods this build can run (the OpenCL ones need OpenCL).
std::vector<Method> availableMethods();
// The method called `name`; throws Error naming the value and the choices.
Method findMethod(const std::string& name);

// What the events method did so far: its events of every kind, and the
// simulated time they cover.
struct EventProgress {
    EventCounts counts;
    double time = 0;  // [time]
};

// A method's disks stepping, as `carom bench` times them: a carom::World for
// the production methods, so that the timings are what a library user gets;
// an all-pairs engine of bench/ for the naive baselines, which the library
// does not have.
class Stepper {
public:
    virtual ~Stepper() = default;
    virtual std::size_t diskCount() const = 0;
    virtual void step(std::uint64_t steps) = 0;
    // Substeps per step over every step taken: above 1 where steps were split.
    virtual double substepsPerStep() const = 0;
    // The events method's progress (World::eventCounts, World::time);
    // nothing for the stepped methods.
    virtual std::optional<EventProgress> events() const = 0;
    // The most the engine's buffers held on its device at once (World::deviceMemory); 0 on the CPU.
    virtual std::uint64_t devicePeakBytes() const = 0;
};

// `method` under world.collisions, on world.device for the OpenCL methods,
// holding `disks`; throws Error when the method does not run that scheme.
std::unique_ptr<Stepper> makeStepper(const Method& method, const WorldDef& world, const std::vector<Disk>& disks);

// Where a step's time goes, in seconds per step, under world.collisions: for
// an OpenCL method each kernel, transfer and host grid build, from `steps`
// steps of a separate run with profiling on (so the timed runs carry no
// profiling overhead), after `warmupSteps` unprofiled steps that bring it to
// the state the timed samples saw (the pairwise scheme's rounds cost what
// the collisions of the moment ask for; the scene starts on a lattice, with
// none); for the CPU backend its serial part, timed alone: the grid build
// (one per substep: `substepsPerStep` of them), or with the pairwise scheme
// the neighbour lists' builds, as many as a run of `steps` steps made;
// nothing for the CPU all-pairs and events methods.
std::map<std::string, double> profileMethod(const Method& method, const WorldDef& world, const std::vector<Disk>& disks,
                                            std::uint64_t steps, double substepsPerStep, std::uint64_t warmupSteps);

// The bytes of one disk's state in the engines' memory: position, velocity,
// mass and radius, padded for the device.
constexpr std::size_t kDiskStateBytes = 32;

// Bytes a method must move per particle-step, by the memory they cross: the
// state read and written once (2 x 32 B), the grid written and read once
// (sortedIndices 2 x 4 B, cells 2 x 8 B per cell); neighbour reads are assumed
// to hit in cache. The host-grid pipeline also builds the grid on the host from
// its copy of the state and moves the grid up and the state down each step.
// The pairwise scheme adds a pass, its forward search, which reads each
// disk's state (32 B), sorted index and cell (2 x 4 B) and writes its event
// (8 B); the host-grid pipeline also builds and uploads the cells (4 B). The
// rounds touch only the few disks on their lists and are not counted. The
// events method has no such model (its cost is per event, not per step):
// no bytes.
struct Traffic {
    double device = 0;    // the OpenCL device's memory
    double host = 0;      // host memory
    double upload = 0;    // host to device
    double download = 0;  // device to host
};
Traffic trafficPerParticleStep(const Variant& variant, double cellsPerParticle);
// The grid cells per disk the engines use for `particles` disks of `radius`
// in world's box, under its boundary and scheme: the model's grid term.
double cellsPerParticle(const WorldDef& world, float radius, std::uint32_t particles);

// Measured bandwidths in bytes per second; a copy counts the bytes read plus
// the bytes written. Zero where not measured.
struct Bandwidth {
    double hostCopy = 0;
    double deviceCopy = 0;
    double upload = 0;
    double download = 0;
};

// The shortest time per particle-step the traffic allows at these
// bandwidths; 0 when a bandwidth it needs was not measured.
double floorSecondsPerParticleStep(const Traffic& traffic, const Bandwidth& bandwidth);

}  // namespace carom::bench
