// carom::World (include/carom/world.h): the public API over a Backend.
#include <carom/world.h>
#include <carom/version.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "backends/backend.h"
#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include "engine/error_message.h"
#include "engine/event_state.h"
#include "engine/grid.h"
#include "engine/observables.h"
#include "engine/parallel.h"
#include "engine/scene.h"
#include "engine/snapshot_checks.h"
#include "engine/text_format.h"
#include "world/make_backend.h"
#ifdef CAROM_HAVE_OPENCL
#include "backends/opencl/runtime.h"
#endif

namespace carom {

Scene makeScene(const SceneDef& def) {
    if (def.particles > kMaxParticles)
        throw Error("SceneDef::particles " + std::to_string(def.particles) + " is more than kMaxParticles (" +
                    std::to_string(kMaxParticles) + ")");
    InitialState state = makeInitialState(def);
    return Scene{state.width, state.height, disksOf(state.particles)};
}

Scene makeScene(const SceneFileDef& def) {
    InitialState state = makeInitialState(def);
    return Scene{state.width, state.height, disksOf(state.particles)};
}

ComputeEngine parseComputeEngine(const std::string& name) {
    for (ComputeEngine engine : {ComputeEngine::Cpu, ComputeEngine::OpenClHostGrid, ComputeEngine::OpenClResident})
        if (name == computeEngineName(engine)) return engine;
    throw Error("unknown compute engine '" + name + "'; allowed: cpu, opencl-host-grid, opencl-resident");
}

const char* version() { return CAROM_VERSION; }

bool engineAvailable(ComputeEngine engine) {
    const std::vector<std::string> built = availableBackends();
    return engine == ComputeEngine::Cpu || std::find(built.begin(), built.end(), "opencl") != built.end();
}

#ifdef CAROM_HAVE_OPENCL
namespace {
Device deviceOf(const opencl::DeviceInfo& d) {
    return Device{
        d.index, d.name, d.platformName, d.type, d.version, d.globalMemoryBytes, d.correctlyRoundedDivideSqrt};
}
}  // namespace
#endif

std::vector<Device> listDevices() {
#ifdef CAROM_HAVE_OPENCL
    std::vector<Device> devices;
    for (const opencl::DeviceInfo& d : opencl::listDevices()) devices.push_back(deviceOf(d));
    return devices;
#else
    throw Error("listDevices: this carom was built without OpenCL; allowed: ComputeEngine::Cpu");
#endif
}

Device findDevice([[maybe_unused]] const std::string& selector) {
#ifdef CAROM_HAVE_OPENCL
    return deviceOf(opencl::selectDevice(selector));
#else
    throw Error("findDevice: this carom was built without OpenCL; allowed: ComputeEngine::Cpu");
#endif
}

ComputeEngine openClEngineFor(const Device& device) {
    return device.type == "GPU" ? ComputeEngine::OpenClResident : ComputeEngine::OpenClHostGrid;
}

EngineChoice chooseEngine(const std::vector<Device>& devices) {
    std::string others;
    for (const Device& d : devices) {
        if (d.type == "GPU")
            return {EngineDef{openClEngineFor(d), std::to_string(d.index)},
                    "the OpenCL GPU [" + std::to_string(d.index) + "] " + d.name};
        others += (others.empty() ? "" : ", ") + d.name + " (" + d.type + ")";
    }
    if (others.empty()) return {EngineDef{}, "no OpenCL device"};
    return {EngineDef{}, "no OpenCL GPU, and OpenCL on " + others + " runs slower than the CPU engine"};
}

EngineChoice chooseEngine() {
    if (!engineAvailable(ComputeEngine::OpenClHostGrid)) return {EngineDef{}, "this carom was built without OpenCL"};
    std::vector<Device> devices;
    try {
        devices = listDevices();
    } catch (const Error&) {  // no platform: no GPU
    }
    return chooseEngine(devices);
}

const char* computeEngineName(ComputeEngine engine) {
    switch (engine) {
        case ComputeEngine::Cpu: return "cpu";
        case ComputeEngine::OpenClHostGrid: return "opencl-host-grid";
        case ComputeEngine::OpenClResident: return "opencl-resident";
    }
    return "unknown";
}

struct World::Impl {
    WorldDef def;
    std::unique_ptr<Backend> backend;
    std::uint64_t step = 0;  // the step the state holds
    // time() = motionTime + (step - motionStep) x dt: dt may change (setMotion).
    double motionTime = 0.0;
    std::uint64_t motionStep = 0;
    std::uint64_t collisionsBefore = 0;     // since the scene began, before the measurements' interval
    std::function<bool()> stopCheck;        // every backend's (setStopCheck)
    std::vector<std::string> warnings;      // the last start's (validateStart)
    double intervalStartTemperature = 0.0;  // kT when the measurements' interval began
    // The state as last read from the backend, and its energies and
    // momentum, while they are current (one read and one pass per state,
    // however many observables a caller asks for).
    std::vector<Particle> state;
    bool stateCurrent = false;
    Diagnostics stateMotion;
    bool motionCurrent = false;
    // Its kT: a pass over every disk in id order, on one thread (a sum in
    // double whose bits depend on that order),
    // which a run asks for at its start and end and for its measurements.
    double stateTemperature = 0.0;
    bool temperatureCurrent = false;

    double time() const { return motionTime + double(step - motionStep) * def.dt; }
    // A decomposed world's reads gather from every process, so every process
    // takes them here, after each step() call (or at gather(), with
    // Gather::OnRequest), where all of them are: the reads between steps are
    // then each process's own.
    void gatherDecomposed() {
        if (!def.decomposition) return;
        whole = true;
        current();
        backend->contacts();
        backend->images();
    }
    // False from a step of a world that gathers on request until gather():
    // the whole world's reads would wait for processes that do not read.
    bool whole = true;
    void requireWhole() const {
        if (!whole)
            throw Error(
                "this process holds only its own disks since the last step (its decomposition gathers on "
                "request): gather the whole world first, on every process, or read the own disks");
    }
    const ContactTotals& contacts() {
        requireWhole();
        return backend->contacts();
    }
    std::vector<Image> images() {
        requireWhole();
        return backend->images();
    }
    const std::vector<Particle>& current() {
        requireWhole();
        if (!stateCurrent && backend->particleCount() > 0) {
            backend->readParticles(state);
            stateCurrent = true;
            motionCurrent = false;
            temperatureCurrent = false;
        }
        return state;
    }
    double temperature() {
        current();
        if (!temperatureCurrent) {
            stateTemperature = carom::temperature(state, def.boundary);
            temperatureCurrent = true;
        }
        return stateTemperature;
    }
    const Diagnostics& motion() {
        current();
        if (!motionCurrent) {
            stateMotion = measureMotion(state, def);
            motionCurrent = true;
        }
        return stateMotion;
    }
    // The checks of a start on `world` (validateStart) and its warnings, the
    // grid's cost among them; `source` names the particles in messages.
    static std::vector<std::string> checkStart(const std::vector<Particle>& particles, const WorldDef& world,
                                               const std::string& source, DeepOverlaps deepOverlaps);
    // Takes `particles`, which the backend holds now, as step `step` at
    // `time` of a scene in which `collisions` pairs collided so far.
    void start(std::vector<Particle> particles, std::uint64_t step, double time, std::uint64_t collisions,
               std::vector<std::string> startWarnings);
    // Replaces the state with an edited one, at the same step and collision
    // count: `what` (setDisk, addDisks, editDisks) changed its disks [first, last).
    void edit(std::vector<Particle> particles, std::size_t first, std::size_t last, const char* what);
    // Takes `particles`, which the backend holds now, as the state at
    // `step`, with `collisions` so far.
    void loaded(std::vector<Particle> particles, std::uint64_t step, std::uint64_t collisions);
};

namespace {

// Throws Error, naming `what`, unless a world may hold `count` disks.
void requireDiskCount(const std::string& what, std::size_t count) {
    if (count == 0) throw Error(what + ": a world needs at least 1 disk, got 0");
    if (count > kMaxParticles)
        throw Error(what + ": " + std::to_string(count) + " disks; allowed: at most " + std::to_string(kMaxParticles) +
                    " (kMaxParticles)");
}

// Throws Error, naming `what` and the argument `name`, when `array` is null
// but said to hold `count` `things`.
void requireArray(const std::string& what, const char* name, const void* array, std::size_t count, const char* things) {
    if (array == nullptr && count > 0)
        throw Error(what + ": " + name + " is null, for " + std::to_string(count) + " " + things +
                    "; allowed: a pointer to " + std::to_string(count) + " " + things);
}

// Throws Error, naming `what`, when a disk of particles[first, last) has the
// centre of another disk: their collision would have no direction (setDisks
// refuses that too, validateStart). Compared one by one for a few disks (a
// drag), through a hash of the centres for more.
void requireDistinctCentres(const std::vector<Particle>& particles, std::size_t first, std::size_t last,
                            const char* what) {
    const auto same = [&](std::size_t i, std::size_t j) {
        const float2 a = particles[i].position, b = particles[j].position;
        if (a.x != b.x || a.y != b.y) return;
        std::ostringstream text;
        text << what << ": disks " << std::min(i, j) << " and " << std::max(i, j) << " have the same centre (" << a.x
             << ", " << a.y << "): their collision has no direction; allowed: distinct centres";
        throw Error(text.str());
    };
    constexpr std::size_t kCompared = 16;
    if (last - first <= kCompared) {
        for (std::size_t i = first; i < last; ++i)
            for (std::size_t j = 0; j < particles.size(); ++j)
                if (j != i) same(i, j);
        return;
    }
    // -0 and 0 are one coordinate: keyed as 0.
    const auto key = [&](std::size_t i) {
        const float x = particles[i].position.x + 0.0f, y = particles[i].position.y + 0.0f;
        std::uint32_t bx = 0, by = 0;
        std::memcpy(&bx, &x, 4);
        std::memcpy(&by, &y, 4);
        return std::uint64_t(bx) << 32 | by;
    };
    std::unordered_map<std::uint64_t, std::size_t> changed;
    for (std::size_t i = first; i < last; ++i)
        if (const auto [at, added] = changed.emplace(key(i), i); !added) same(at->second, i);
    for (std::size_t j = 0; j < particles.size(); ++j)
        if (j < first || j >= last)
            if (const auto at = changed.find(key(j)); at != changed.end()) same(at->second, j);
}

// The definition `world` takes from `snapshot`: its dt and gravity. Throws
// Error, naming `source` and what differs, for a snapshot of a world of
// another box, boundary or collision scheme, or with dt or gravity out of range.
WorldDef restoredDef(const WorldDef& world, const Snapshot& snapshot, const std::string& source) {
    const WorldDef& from = snapshot.world;
    std::string differs;
    if (from.width != world.width || from.height != world.height) {
        const auto box = [](const WorldDef& def) {
            std::string text;
            appendNumber(text, def.width);
            text += " x ";
            appendNumber(text, def.height);
            return text;
        };
        differs = "box " + box(from) + ", this world's " + box(world);
    } else if (from.boundary != world.boundary) {
        differs =
            std::string("boundary ") + boundaryName(from.boundary) + ", this world's " + boundaryName(world.boundary);
    } else if (from.collisions != world.collisions) {
        differs = std::string("collision scheme ") + collisionSchemeName(from.collisions) + ", this world's " +
                  collisionSchemeName(world.collisions);
    }
    if (!differs.empty())
        throw Error(source + ": a snapshot of another world (" + differs +
                    "); allowed: one of a world with this one's box, boundary and collision scheme");
    WorldDef restored = world;
    restored.dt = from.dt;
    restored.gravity = from.gravity;
    try {
        validate(restored);
    } catch (const Error& e) {
        throw Error(source + ": " + e.what());
    }
    return restored;
}

// What is wrong with a snapshot's images: one per disk or none, and none
// but {0, 0} in a box with walls. Empty when nothing is.
std::string imagesProblem(const Snapshot& snapshot) {
    const std::vector<Image>& images = snapshot.images;
    if (!images.empty() && images.size() != snapshot.disks.size())
        return std::to_string(images.size()) + " images for " + std::to_string(snapshot.disks.size()) +
               " disks; allowed: one per disk, or none (all {0, 0})";
    if (snapshot.world.boundary == Boundary::Walls)
        for (std::size_t i = 0; i < images.size(); ++i)
            if (images[i] != Image{0, 0})
                return "disk " + std::to_string(i) + " has image {" + std::to_string(images[i][0]) + ", " +
                       std::to_string(images[i][1]) + "} in a box with walls; allowed: {0, 0} (only a periodic box " +
                       "has images)";
    return {};
}

}  // namespace

std::vector<std::string> World::Impl::checkStart(const std::vector<Particle>& particles, const WorldDef& world,
                                                 const std::string& source, DeepOverlaps deepOverlaps) {
    std::vector<std::string> found = validateStart(particles, world, source, deepOverlaps);
    if (std::string slow = gridCostWarning(particles, world); !slow.empty()) found.push_back(std::move(slow));
    return found;
}

void World::Impl::start(std::vector<Particle> particles, std::uint64_t startStep, double startTime,
                        std::uint64_t collisions, std::vector<std::string> startWarnings) {
    warnings = std::move(startWarnings);
    loaded(std::move(particles), startStep, collisions);
    motionStep = startStep;
    motionTime = startTime;
}

void World::Impl::edit(std::vector<Particle> particles, std::size_t first, std::size_t last, const char* what) {
    requireDistinctCentres(particles, first, last, what);
    // Counted before setParticles resets the backend's.
    const std::uint64_t collisions = collisionsBefore + contacts().collisions;
    // Edited disks keep their images (a drag is a move within the image); added ones start at {0, 0}.
    std::vector<Image> images = this->images();
    images.resize(particles.size(), Image{0, 0});
    backend->setParticles(particles, step, images);
    loaded(std::move(particles), step, collisions);
}

void World::Impl::loaded(std::vector<Particle> particles, std::uint64_t atStep, std::uint64_t collisions) {
    step = atStep;
    collisionsBefore = collisions;
    state = std::move(particles);
    stateCurrent = true;
    whole = true;
    // kT, and the energies and momentum a run reports at its start: each an
    // ordered pass over every disk on one thread (sums in double, in id
    // order), so the two side by side.
#pragma omp parallel sections if (state.size() >= std::size_t(kParallelLength))
    {
#pragma omp section
        stateTemperature = carom::temperature(state, def.boundary);
#pragma omp section
        stateMotion = measureMotion(state, def);
    }
    temperatureCurrent = motionCurrent = true;
    intervalStartTemperature = stateTemperature;
}

World::World(const WorldDef& def) : impl_(std::make_unique<Impl>()) {
    if (def.collisions == CollisionScheme::Events && def.maxTravel != 0.0f)
        throw Error("WorldDef::maxTravel must be 0 with CollisionScheme::Events, which has no steps to split; got " +
                    std::to_string(def.maxTravel));
    if (def.skin != 0.0f && (def.engine != ComputeEngine::Cpu || def.collisions != CollisionScheme::Pairwise))
        fail(
            "WorldDef::skin (--skin) sizes the CPU engine's neighbour lists, which only the pairwise scheme keeps: "
            "it must be 0 on the OpenCL engines and with the simultaneous and events schemes; got ",
            def.skin);
    impl_->def = def;
    impl_->backend = makeBackend(def);
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::setDisks(const Disk* disks, std::size_t count, const std::string& source, DeepOverlaps deepOverlaps) {
    requireDiskCount("setDisks", count);
    requireArray("setDisks", "disks", disks, count, "disks");
    std::vector<Particle> particles = particlesOf(disks, count);
    std::vector<std::string> found = Impl::checkStart(particles, impl_->def, source, deepOverlaps);
    impl_->backend->setParticles(particles);
    impl_->start(std::move(particles), 0, 0.0, 0, std::move(found));
}

Snapshot World::snapshot() const {
    Snapshot s;
    s.world = impl_->def;
    s.step = impl_->step;
    s.time = time();
    s.collisions = collisionCount();
    s.disks = disks();
    s.events = impl_->backend->saveState();
    s.images = images();
    return s;
}

void World::restore(const Snapshot& snapshot, const std::string& source) {
    const WorldDef restored = restoredDef(impl_->def, snapshot, source);
    requireDiskCount(source, snapshot.disks.size());
    if (const std::string problem = snapshotCountsProblem(snapshot); !problem.empty())
        throw Error(source + ": " + problem);
    if (const std::string problem = eventStatePlaceProblem(snapshot); !problem.empty())
        throw Error(source + ": " + problem);
    if (const std::string problem = imagesProblem(snapshot); !problem.empty()) throw Error(source + ": " + problem);
    std::vector<Particle> particles = particlesOf(snapshot.disks.data(), snapshot.disks.size());
    std::vector<std::string> found = Impl::checkStart(particles, restored, source, DeepOverlaps::Warn);
    if (snapshot.events) {
        // Only a backend that holds the disks can check the state's cells:
        // a spare one (the events scheme runs on the CPU), so that a refusal
        // leaves this world's as it was.
        std::unique_ptr<Backend> spare = makeBackend(restored);
        spare->setParticles(particles, snapshot.step, snapshot.images);
        try {
            spare->restoreState(*snapshot.events);
        } catch (const Error& e) {
            throw Error(source + ": " + e.what());
        }
        spare->readParticles(particles);  // the float rounding of the exact state, as a step reads it
        spare->setStopCheck(impl_->stopCheck);
        impl_->backend = std::move(spare);
    } else {
        impl_->backend->setMotion(restored.dt, restored.gravity);
        impl_->backend->setParticles(particles, snapshot.step, snapshot.images);
    }
    impl_->def = restored;
    impl_->start(std::move(particles), snapshot.step, snapshot.time, snapshot.collisions, std::move(found));
}

void World::setDisk(std::size_t id, const Disk& disk) {
    if (id >= diskCount())
        throw Error("setDisk: id " + std::to_string(id) + " is not a disk; allowed: 0.." +
                    (diskCount() > 0 ? std::to_string(diskCount() - 1) + " (diskCount() - 1)" : "none (no disks yet)"));
    std::vector<Particle> edited = impl_->current();
    edited[id] = particleOf(disk);
    impl_->edit(std::move(edited), id, id + 1, "setDisk");
}

void World::editDisks(const Disk* disks, std::size_t count) {
    requireArray("editDisks", "disks", disks, count, "disks");
    if (count != diskCount())
        throw Error("editDisks: " + std::to_string(count) + " disks; allowed: " + std::to_string(diskCount()) +
                    " (diskCount(): an edit keeps the number of disks)");
    impl_->edit(particlesOf(disks, count), 0, count, "editDisks");
}

void World::addDisks(const Disk* disks, std::size_t count) {
    requireArray("addDisks", "disks", disks, count, "disks");
    if (diskCount() == 0) return setDisks(disks, count);
    std::vector<Particle> edited = impl_->current();
    if (count > kMaxParticles - edited.size())
        throw Error("addDisks: " + std::to_string(edited.size()) + " + " + std::to_string(count) +
                    " disks; allowed: at most " + std::to_string(kMaxParticles) + " (kMaxParticles)");
    const std::size_t first = edited.size();
    for (std::size_t i = 0; i < count; ++i) edited.push_back(particleOf(disks[i]));
    impl_->edit(std::move(edited), first, first + count, "addDisks");
}

void World::getDisks(Disk* out, std::size_t capacity) const {
    requireArray("getDisks", "out", out, capacity, "disks");
    const std::vector<Particle>& state = impl_->current();
    if (capacity < state.size())
        throw Error("getDisks: room for " + std::to_string(capacity) + " disks; the world has " +
                    std::to_string(state.size()) + " (diskCount())");
    getDisks(0, state.size(), out);
}

void World::getDisks(std::size_t first, std::size_t count, Disk* out) const {
    requireArray("getDisks", "out", out, count, "disks");
    const std::vector<Particle>& state = impl_->current();
    if (first > state.size() || count > state.size() - first)
        throw Error("getDisks: first " + std::to_string(first) + ", count " + std::to_string(count) +
                    "; allowed: first + count <= " + std::to_string(state.size()) + " (diskCount())");
    for (std::size_t i = 0; i < count; ++i) out[i] = diskOf(state[first + i]);
}

std::vector<Disk> World::disks() const { return disksOf(impl_->current()); }

ViewSums World::readView(ViewValue value, DiskView* out, std::size_t capacity) const {
    requireArray("readView", "out", out, capacity, "views");
    const std::size_t n = diskCount();
    if (capacity < n)
        throw Error("readView: room for " + std::to_string(capacity) + " views is less than diskCount() " +
                    std::to_string(n));
    // Measured where the state lives, even when the host holds a copy, so
    // that every frame's sums are measured alike.
    if (std::optional<ViewSums> sums = impl_->backend->readView(value, out)) return *sums;
    return measureView(impl_->current(), impl_->def, value, out);
}

std::size_t World::diskCount() const { return impl_->backend->particleCount(); }

static_assert(offsetof(Particle, position) == DiskMemory::kPosition * sizeof(float) &&
                  offsetof(Particle, velocity) == DiskMemory::kVelocity * sizeof(float) &&
                  offsetof(Particle, mass) == DiskMemory::kMass * sizeof(float) &&
                  offsetof(Particle, radius) == DiskMemory::kRadius * sizeof(float) &&
                  sizeof(Particle) % sizeof(float) == 0,
              "DiskMemory's offsets are Particle's");

DiskMemory World::diskMemory() const {
    std::shared_ptr<const std::vector<Particle>> state = impl_->backend->sharedState();
    if (!state || state->empty()) return {};
    DiskMemory memory;
    memory.base = &state->front().position.x;
    memory.count = state->size();
    memory.stride = sizeof(Particle) / sizeof(float);
    memory.owner = std::move(state);
    return memory;
}

void World::step(std::uint64_t steps) {
    if (diskCount() == 0) throw Error("step: the world has no disks yet; call setDisks first");
    if (steps > std::numeric_limits<std::uint64_t>::max() - impl_->step)
        throw Error("step: " + std::to_string(steps) + " steps from step " + std::to_string(impl_->step) +
                    " would take the step count past 2^64 - 1; allowed: at most " +
                    std::to_string(std::numeric_limits<std::uint64_t>::max() - impl_->step));
    impl_->stateCurrent = false;
    impl_->whole = !impl_->backend->gathersOnRequest();
    try {
        impl_->backend->step(steps);
    } catch (const Error&) {
        const auto& stopped = impl_->backend->nonFinite();
        impl_->step = stopped ? stopped->step : impl_->backend->stepNumber();
        if (impl_->whole) impl_->gatherDecomposed();
        throw;
    }
    impl_->step = impl_->backend->stepNumber();
    if (impl_->whole) impl_->gatherDecomposed();
}

void World::setStopCheck(std::function<bool()> check) {
    impl_->stopCheck = std::move(check);
    impl_->backend->setStopCheck(impl_->stopCheck);
}

std::uint64_t World::stepCount() const { return impl_->step; }

double World::time() const { return impl_->time(); }

void World::setMotion(float dt, Vec2 gravity) {
    WorldDef changed = impl_->def;
    changed.dt = dt;
    changed.gravity = gravity;
    validate(changed);
    if (diskCount() > 0) requireValidMotion(impl_->current(), changed, "setMotion");
    impl_->motionTime = impl_->time();
    impl_->motionStep = impl_->step;
    impl_->backend->setMotion(dt, gravity);
    impl_->def.dt = dt;
    impl_->def.gravity = gravity;
    impl_->motionCurrent = false;  // the potential energy depends on gravity
}

const WorldDef& World::def() const { return impl_->def; }

const std::vector<std::string>& World::warnings() const { return impl_->warnings; }

double World::kineticEnergy() const { return impl_->motion().kineticEnergy; }

double World::potentialEnergy() const { return impl_->motion().potentialEnergy; }

std::array<double, 2> World::momentum() const { return impl_->motion().momentum; }

double World::maxOverlap() const { return findOverlaps(impl_->current(), impl_->def).deepest; }

std::size_t World::escapedCount() const { return impl_->motion().escaped; }

double World::totalEnergy() const {
    if (std::optional<double> exact = impl_->backend->exactTotalEnergy()) return *exact;
    return impl_->motion().totalEnergy();
}

EventCounts World::eventCounts() const { return impl_->backend->eventCounts(); }

std::vector<std::array<double, 2>> World::exactPositions() const { return impl_->backend->exactPositions(); }

std::vector<Image> World::images() const {
    if (diskCount() == 0) return {};
    return impl_->images();
}

double World::temperature() const { return impl_->temperature(); }

Measurements World::measurements() const {
    const ContactTotals& contacts = impl_->contacts();
    const double kT = 0.5 * (impl_->intervalStartTemperature + temperature());
    const Thermodynamics t = thermodynamics(contacts, kT, diskCount(), impl_->def);
    Measurements m;
    m.time = contacts.time;
    m.steps = contacts.steps;
    m.collisions = contacts.collisions;
    m.collisionRate = t.collisionRate;
    m.temperature = kT;
    const bool periodic = impl_->def.boundary == Boundary::Periodic;
    m.pressure = periodic ? t.virialPressure : t.wallPressureMean;
    m.compressibility = periodic ? t.virialZ : t.wallZ;
    m.collisionVirial = contacts.virial;
    m.wallPressure = t.wallPressure;
    m.substeps = contacts.substeps;
    m.lateContacts = contacts.lateContacts;
    m.maxRounds = contacts.maxRounds;
    return m;
}

std::uint64_t World::collisionCount() const { return impl_->collisionsBefore + impl_->contacts().collisions; }

void World::resetMeasurements() {
    impl_->collisionsBefore = collisionCount();
    impl_->backend->resetContacts();
    impl_->intervalStartTemperature = temperature();
}

bool World::bitwiseReproducible() const { return impl_->backend->exactArithmetic(); }

std::string World::deviceName() const { return impl_->backend->device(); }

DeviceMemoryUse World::deviceMemory() const { return impl_->backend->deviceMemory(); }

DecompositionCosts World::decompositionCosts() const { return impl_->backend->decompositionCosts(); }

OwnDisks World::ownDisks() const {
    OwnDisks own;
    if (diskCount() == 0) return own;
    std::vector<Particle> particles;
    impl_->backend->readOwnDisks(own.ids, particles, own.images);
    own.disks = disksOf(particles);
    return own;
}

void World::gather() {
    if (!impl_->whole) impl_->gatherDecomposed();
}

}  // namespace carom
