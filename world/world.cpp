// carom::World (include/carom/world.h): the public API over a Backend.
#include <carom/world.h>
#include <carom/version.h>

#include <algorithm>
#include <cstddef>
#include <utility>

#include "backends/event_driven.h"
#include "engine/diagnostics.h"
#include "engine/grid.h"
#include "engine/disk_conversion.h"
#include "engine/observables.h"
#include "engine/scene.h"
#include "world/make_backend.h"
#include "world/world_impl.h"
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

Device findDevice(const std::string& selector) {
#ifdef CAROM_HAVE_OPENCL
    return deviceOf(opencl::selectDevice(selector));
#else
    throw Error("findDevice: this carom was built without OpenCL; allowed: ComputeEngine::Cpu");
#endif
}

ComputeEngine openClEngineFor(const Device& device) {
    return device.type == "GPU" ? ComputeEngine::OpenClResident : ComputeEngine::OpenClHostGrid;
}

const char* computeEngineName(ComputeEngine engine) {
    switch (engine) {
        case ComputeEngine::Cpu: return "cpu";
        case ComputeEngine::OpenClHostGrid: return "opencl-host-grid";
        case ComputeEngine::OpenClResident: return "opencl-resident";
    }
    return "unknown";
}

void World::Impl::start(std::vector<Particle> particles, std::uint64_t startStep, double startTime,
                        std::uint64_t collisions, const std::string& source, DeepOverlaps deepOverlaps) {
    warnings = validateStart(particles, def, source, deepOverlaps);
    if (std::string slow = gridCostWarning(particles, def); !slow.empty()) warnings.push_back(std::move(slow));
    load(std::move(particles), startStep, collisions);
    motionStep = startStep;
    motionTime = startTime;
}

void World::Impl::edit(std::vector<Particle> particles) {
    load(std::move(particles), step, collisionsBefore + backend->contacts().collisions);
}

void World::Impl::load(std::vector<Particle> particles, std::uint64_t atStep, std::uint64_t collisions) {
    backend->setParticles(particles, atStep);
    step = atStep;
    collisionsBefore = collisions;
    state = std::move(particles);
    stateCurrent = true;
    motionCurrent = false;
    intervalStartTemperature = carom::temperature(state, def.boundary);
}

World::World(const WorldDef& def) : impl_(std::make_unique<Impl>()) {
    if (def.collisions == CollisionScheme::Events && def.maxTravel != 0.0f)
        throw Error("WorldDef::maxTravel must be 0 with CollisionScheme::Events, which has no steps to split; got " +
                    std::to_string(def.maxTravel));
    impl_->def = def;
    impl_->backend = makeBackend(def);
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::setDisks(const Disk* disks, std::size_t count, const std::string& source, DeepOverlaps deepOverlaps) {
    if (count == 0) throw Error("setDisks: a world needs at least 1 disk, got 0");
    if (count > kMaxParticles)
        throw Error("setDisks: " + std::to_string(count) + " disks; allowed: at most " + std::to_string(kMaxParticles) +
                    " (kMaxParticles)");
    impl_->start(particlesOf(disks, count), 0, 0.0, 0, source, deepOverlaps);
}

void World::setDisk(std::size_t id, const Disk& disk) {
    if (id >= diskCount())
        throw Error("setDisk: id " + std::to_string(id) + " is not a disk; allowed: 0.." +
                    (diskCount() > 0 ? std::to_string(diskCount() - 1) + " (diskCount() - 1)" : "none (no disks yet)"));
    std::vector<Particle> edited = impl_->current();
    edited[id] = particleOf(disk);
    impl_->edit(std::move(edited));
}

void World::editDisks(const Disk* disks, std::size_t count) {
    if (count != diskCount())
        throw Error("editDisks: " + std::to_string(count) + " disks; allowed: " + std::to_string(diskCount()) +
                    " (diskCount(): an edit keeps the number of disks)");
    impl_->edit(particlesOf(disks, count));
}

void World::addDisks(const Disk* disks, std::size_t count) {
    if (diskCount() == 0) return setDisks(disks, count);
    std::vector<Particle> edited = impl_->current();
    if (count > kMaxParticles - edited.size())
        throw Error("addDisks: " + std::to_string(edited.size()) + " + " + std::to_string(count) +
                    " disks; allowed: at most " + std::to_string(kMaxParticles) + " (kMaxParticles)");
    for (std::size_t i = 0; i < count; ++i) edited.push_back(particleOf(disks[i]));
    impl_->edit(std::move(edited));
}

void World::getDisks(Disk* out, std::size_t capacity) const {
    const std::vector<Particle>& state = impl_->current();
    if (capacity < state.size())
        throw Error("getDisks: room for " + std::to_string(capacity) + " disks; the world has " +
                    std::to_string(state.size()) + " (diskCount())");
    for (std::size_t i = 0; i < state.size(); ++i) out[i] = diskOf(state[i]);
}

std::vector<Disk> World::disks() const { return disksOf(impl_->current()); }

ViewSums World::readView(ViewValue value, DiskView* out, std::size_t capacity) const {
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
    impl_->stateCurrent = false;
    try {
        impl_->backend->step(steps);
    } catch (const Error&) {
        const auto& stopped = impl_->backend->nonFinite();
        impl_->step = stopped ? stopped->step : impl_->backend->stepNumber();
        throw;
    }
    impl_->step = impl_->backend->stepNumber();
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
    if (auto* events = dynamic_cast<const EventDrivenBackend*>(impl_->backend.get())) return events->totalEnergy();
    return impl_->motion().totalEnergy();
}

EventCounts World::eventCounts() const {
    if (auto* events = dynamic_cast<const EventDrivenBackend*>(impl_->backend.get())) return events->eventCounts();
    return EventCounts{};
}

std::vector<std::array<double, 2>> World::exactPositions() const {
    std::vector<std::array<double, 2>> positions;
    if (auto* events = dynamic_cast<const EventDrivenBackend*>(impl_->backend.get()))
        for (const ExactDisk& d : events->exactState()) positions.push_back({d.x, d.y});
    return positions;
}

double World::temperature() const { return carom::temperature(impl_->current(), impl_->def.boundary); }

Measurements World::measurements() const {
    const ContactTotals& contacts = impl_->backend->contacts();
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

std::uint64_t World::collisionCount() const { return impl_->collisionsBefore + impl_->backend->contacts().collisions; }

void World::resetMeasurements() {
    impl_->collisionsBefore = collisionCount();
    impl_->backend->resetContacts();
    impl_->intervalStartTemperature = temperature();
}

bool World::bitwiseReproducible() const { return impl_->backend->exactArithmetic(); }

std::string World::deviceName() const { return impl_->backend->device(); }

}  // namespace carom
