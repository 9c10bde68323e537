// carom::World (include/carom/world.h): the public API over a Backend.
#include <carom/world.h>

#include <algorithm>
#include <utility>

#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include "engine/observables.h"
#include "engine/world_impl.h"

namespace carom {

namespace {

BackendDef backendFor(const WorldDef& def) {
    switch (def.engine) {
    case ComputeEngine::Cpu:
        return BackendDef{"cpu", "", "seed"};
    case ComputeEngine::OpenClHostGrid:
        return BackendDef{"opencl", def.device, "seed"};
    case ComputeEngine::OpenClResident:
        return BackendDef{"opencl", def.device, "resident"};
    }
    throw Error("WorldDef::engine " + std::to_string(static_cast<int>(def.engine)) +
                " is not a ComputeEngine; allowed: Cpu, OpenClHostGrid, OpenClResident");
}

}  // namespace

Scene makeScene(const SceneDef& def) {
    InitialState state = makeInitialState(def);
    return Scene{state.width, state.height, disksOf(state.particles)};
}

const char* computeEngineName(ComputeEngine engine) {
    switch (engine) {
    case ComputeEngine::Cpu:
        return "cpu";
    case ComputeEngine::OpenClHostGrid:
        return "opencl-host-grid";
    case ComputeEngine::OpenClResident:
        return "opencl-resident";
    }
    return "unknown";
}

void World::Impl::start(std::vector<Particle> particles, std::uint64_t startStep, std::uint64_t collisions) {
    warnings = validateStart(particles, def, "disks");
    backend->setParticles(particles, startStep);
    step = startStep;
    collisionsBefore = collisions;
    state = std::move(particles);
    stateCurrent = true;
    intervalStartTemperature = carom::temperature(state, def.boundary);
}

World::World(const WorldDef& def) : impl_(std::make_unique<Impl>()) {
    if (def.engine != ComputeEngine::Cpu && def.collisions == CollisionScheme::Events)
        throw Error(std::string("CollisionScheme::Events runs on ComputeEngine::Cpu only (one thread, double "
                                "precision); got ComputeEngine ") + computeEngineName(def.engine));
    const std::vector<std::string> built = availableBackends();
    if (def.engine != ComputeEngine::Cpu && std::find(built.begin(), built.end(), "opencl") == built.end())
        throw Error(std::string("ComputeEngine ") + computeEngineName(def.engine) +
                    " needs OpenCL, which this carom was built without; allowed: ComputeEngine::Cpu");
    if (def.collisions == CollisionScheme::Events && def.maxTravel != 0.0f)
        throw Error("WorldDef::maxTravel must be 0 with CollisionScheme::Events, which has no steps to split; got " +
                    std::to_string(def.maxTravel));
    impl_->def = def;
    impl_->backend = makeBackend(backendFor(def), def);
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::setDisks(const Disk* disks, std::size_t count) {
    if (count == 0) throw Error("setDisks: a world needs at least 1 disk, got 0");
    impl_->start(particlesOf(disks, count), 0, 0);
}

void World::getDisks(Disk* out) const {
    const std::vector<Particle>& state = impl_->current();
    for (std::size_t i = 0; i < state.size(); ++i) out[i] = diskOf(state[i]);
}

std::vector<Disk> World::disks() const { return disksOf(impl_->current()); }

std::size_t World::diskCount() const { return impl_->backend->particleCount(); }

void World::step(std::uint64_t steps) {
    if (diskCount() == 0) throw Error("step: the world has no disks yet; call setDisks first");
    impl_->stateCurrent = false;
    try {
        impl_->backend->step(steps);
    } catch (const Error&) {
        if (const auto& where = impl_->backend->nonFinite()) impl_->step = where->step;
        throw;
    }
    impl_->step += steps;
}

std::uint64_t World::stepCount() const { return impl_->step; }

double World::time() const { return double(impl_->step) * impl_->def.dt; }

void World::setMotion(float dt, Vec2 gravity) {
    impl_->backend->setMotion(dt, gravity);
    impl_->def.dt = dt;
    impl_->def.gravity = gravity;
}

const WorldDef& World::def() const { return impl_->def; }

const std::vector<std::string>& World::warnings() const { return impl_->warnings; }

double World::kineticEnergy() const { return measureMotion(impl_->current(), impl_->def).kineticEnergy; }

double World::potentialEnergy() const { return measureMotion(impl_->current(), impl_->def).potentialEnergy; }

std::array<double, 2> World::momentum() const { return measureMotion(impl_->current(), impl_->def).momentum; }

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
    m.wallPressure = t.wallPressure;
    m.substeps = contacts.substeps;
    m.lateContacts = contacts.lateContacts;
    m.maxRounds = contacts.maxRounds;
    return m;
}

std::uint64_t World::collisionCount() const {
    return impl_->collisionsBefore + impl_->backend->contacts().collisions;
}

void World::resetMeasurements() {
    impl_->collisionsBefore = collisionCount();
    impl_->backend->resetContacts();
    impl_->intervalStartTemperature = temperature();
}

bool World::bitwiseReproducible() const { return impl_->backend->exactArithmetic(); }

std::string World::deviceName() const { return impl_->backend->device(); }

}  // namespace carom
