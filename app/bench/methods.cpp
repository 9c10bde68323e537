#include "app/bench/methods.h"

#include <algorithm>
#include <chrono>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "app/bench/all_pairs_cpu.h"
#include "engine/disk_conversion.h"
#include "backends/backend.h"
#include "backends/cpu.h"
#include "engine/neighbour_lists.h"
#include "engine/grid.h"
#ifdef CAROM_HAVE_OPENCL
#include "backends/opencl/host_grid.h"
#include "backends/opencl/resident.h"
#include "app/bench/all_pairs_opencl.h"
#endif

namespace carom::bench {
namespace {

static_assert(kDiskStateBytes == sizeof(Particle), "the traffic model counts the engines' Particle");
constexpr double kStateBytes = 2.0 * kDiskStateBytes;  // read + written
constexpr double kIndexBytes = 2.0 * sizeof(std::uint32_t);
constexpr double kCellBytes = 2.0 * sizeof(GridCell);
// The pairwise scheme's forward search: a disk's state, sorted index and
// cell read, its event written.
constexpr double kForwardSearchBytes = kDiskStateBytes + 2.0 * sizeof(std::uint32_t) + sizeof(CaromEvent);
constexpr double kCellOfBytes = sizeof(std::uint32_t);

// The engine of a production method.
ComputeEngine engineOf(const Method& method) {
    if (!method.opencl) return ComputeEngine::Cpu;
    return method.name == "opencl-host-grid" ? ComputeEngine::OpenClHostGrid : ComputeEngine::OpenClResident;
}

// A production method: a World, as a library user makes one.
class WorldStepper final : public Stepper {
public:
    WorldStepper(const WorldDef& def, const std::vector<Disk>& disks) : world_(def) { world_.setDisks(disks); }

    std::size_t diskCount() const override { return world_.diskCount(); }
    void step(std::uint64_t steps) override { world_.step(steps); }
    double substepsPerStep() const override {
        const Measurements m = world_.measurements();
        return double(m.substeps) / double(m.steps);
    }
    std::optional<EventProgress> events() const override {
        if (world_.def().collisions != CollisionScheme::Events) return std::nullopt;
        return EventProgress{world_.eventCounts(), world_.time()};
    }
    std::uint64_t devicePeakBytes() const override { return world_.deviceMemory().peakBytes; }

private:
    World world_;
};

// A naive baseline: its all-pairs backend (app/bench/all_pairs_*.h).
class AllPairsStepper final : public Stepper {
public:
    AllPairsStepper(std::unique_ptr<Backend> backend, const std::vector<Disk>& disks) : backend_(std::move(backend)) {
        backend_->setParticles(particlesOf(disks.data(), disks.size()));
    }

    std::size_t diskCount() const override { return backend_->particleCount(); }
    void step(std::uint64_t steps) override { backend_->step(steps); }
    double substepsPerStep() const override {
        const ContactTotals& totals = backend_->contacts();
        return double(totals.substeps) / double(totals.steps);
    }
    std::optional<EventProgress> events() const override { return std::nullopt; }
    std::uint64_t devicePeakBytes() const override { return backend_->deviceMemory().peakBytes; }

private:
    std::unique_ptr<Backend> backend_;
};

#ifdef CAROM_HAVE_OPENCL
// The OpenCL backend of an OpenCL method, for its profile: a World has no
// profiler (and for naive-opencl, its timed run).
std::unique_ptr<OpenClBackend> makeOpenClBackend(const Method& method, const WorldDef& world, bool profiling) {
    if (method.allPairs) return std::make_unique<AllPairsOpenClBackend>(world, world.device, profiling);
    if (engineOf(method) == ComputeEngine::OpenClHostGrid)
        return std::make_unique<OpenClHostGridBackend>(world, world.device, profiling);
    return std::make_unique<OpenClResidentBackend>(world, world.device, profiling);
}
#endif

// The backend of a naive baseline.
std::unique_ptr<Backend> makeAllPairsBackend(const Method& method, const WorldDef& world) {
    if (!method.opencl) return std::make_unique<AllPairsCpuBackend>(world);
#ifdef CAROM_HAVE_OPENCL
    return makeOpenClBackend(method, world, false);
#else
    throw Error("this carom was built without OpenCL: method " + method.name + " is not available");
#endif
}

// The seconds of one call of `work`, the mean of `repeats` after one
// untimed call (which allocates, as a running backend has).
template <class Work>
double secondsEach(std::uint64_t repeats, Work&& work) {
    work();
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t r = 0; r < repeats; ++r) work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / double(repeats);
}

// The CPU backend's serial part, timed alone on the scene's particles, on as
// many threads as the backend's team (one below kParallelPassLength disks):
// the grid build (GridBuilder) once per substep; with the pairwise scheme,
// the neighbour lists' builds (NeighbourLists) as often as a run of `steps`
// steps after `warmupSteps` built them, and the grid's for any substep
// that did not search them.
std::map<std::string, double> profileCpu(const WorldDef& world, const std::vector<Particle>& particles,
                                         std::uint64_t steps, double substepsPerStep, std::uint64_t warmupSteps) {
    const float maxRadius = largestRadius(particles.data(), particles.size());
    int threads = 1;
#ifdef _OPENMP
    if (static_cast<std::int64_t>(particles.size()) >= kParallelPassLength) threads = omp_get_max_threads();
#endif
    const std::string team = std::to_string(threads) + (threads == 1 ? " thread" : " threads");
    Grid grid;
    grid.geometry = gridGeometryFor(world, maxRadius, particles.size());
    GridBuilder builder;
    const double gridSeconds = secondsEach(std::max<std::uint64_t>(steps, 1), [&] {
        buildGridParallel(particles.data(), particles.size(), grid, builder, threads);
    });
    if (world.collisions != CollisionScheme::Pairwise)
        return {{"buildGrid (host, " + team + ")", gridSeconds * substepsPerStep}};

    CpuBackend backend(world);
    backend.setParticles(particles);
    backend.step(warmupSteps);
    const std::uint64_t buildsBefore = backend.neighbourListBuilds();
    backend.step(steps);
    const double buildsPerStep = double(backend.neighbourListBuilds() - buildsBefore) / double(steps);
    const float skin = NeighbourLists::skinFor(
        world.skin, maxRadius,
        gridTravelAllowance(grid.geometry, world.width, world.height, maxRadius, world.boundary));
    NeighbourLists lists;
    const double listSeconds = secondsEach(std::min<std::uint64_t>(std::max<std::uint64_t>(steps, 1), 20), [&] {
        lists.build(particles.data(), particles.size(), maxRadius, skin, caromBoxOf(world), threads);
    });
    std::map<std::string, double> perStep;
    if (buildsPerStep > 0) perStep["neighbour lists (host, " + team + ")"] = listSeconds * buildsPerStep;
    // Substeps that built no lists and found none to hold searched the grid.
    if (!lists.built()) perStep["buildGrid (host, " + team + ")"] = gridSeconds * substepsPerStep;
    return perStep;
}

}  // namespace

const std::vector<Method>& allMethods() {
    static const std::vector<Method> methods = {
        {"naive-cpu", "all pairs O(N^2) on the CPU, OpenMP; simultaneous scheme only", false, true},
        {"naive-opencl", "all pairs O(N^2) on the OpenCL device; simultaneous scheme only", true, true},
        {"cpu", "CPU backend: shared grid builder, OpenMP step", false, false},
        {"opencl-host-grid", "OpenCL host-grid pipeline: the host builds the grid, state read back each step", true,
         false},
        {"opencl-resident", "OpenCL resident pipeline: grid and state stay on the device", true, false},
        {"events", "event-driven exact dynamics on one CPU thread (periodic box); events scheme only", false, false,
         true},
    };
    return methods;
}

bool runsScheme(const Method& method, CollisionScheme scheme) {
    if (method.eventDriven || scheme == CollisionScheme::Events)
        return method.eventDriven && scheme == CollisionScheme::Events;
    return scheme == CollisionScheme::Simultaneous || !method.allPairs;
}

std::vector<Method> availableMethods() {
    std::vector<Method> methods;
    const bool haveOpenCl = engineAvailable(ComputeEngine::OpenClResident);
    for (const Method& m : allMethods())
        if (!m.opencl || haveOpenCl) methods.push_back(m);
    return methods;
}

Method findMethod(const std::string& name) {
    std::string names;
    for (const Method& m : availableMethods()) {
        if (m.name == name) return m;
        names += (names.empty() ? "" : ", ") + m.name;
    }
    throw Error("--methods: unknown method '" + name + "'; allowed: " + names);
}

std::unique_ptr<Stepper> makeStepper(const Method& method, const WorldDef& world, const std::vector<Disk>& disks) {
    if (!runsScheme(method, world.collisions))
        throw Error("method " + method.name + " does not run the " + collisionSchemeName(world.collisions) + " scheme");
    if (method.allPairs) return std::make_unique<AllPairsStepper>(makeAllPairsBackend(method, world), disks);
    WorldDef def = world;
    def.engine = engineOf(method);
    return std::make_unique<WorldStepper>(def, disks);
}

std::map<std::string, double> profileMethod(const Method& method, const WorldDef& world, const std::vector<Disk>& disks,
                                            std::uint64_t steps, double substepsPerStep, std::uint64_t warmupSteps) {
    if (!method.opencl)
        return method.allPairs || method.eventDriven
                   ? std::map<std::string, double>{}
                   : profileCpu(world, particlesOf(disks.data(), disks.size()), steps, substepsPerStep, warmupSteps);
#ifdef CAROM_HAVE_OPENCL
    const std::unique_ptr<OpenClBackend> backend = makeOpenClBackend(method, world, true);
    backend->setParticles(particlesOf(disks.data(), disks.size()));
    backend->step(warmupSteps);
    backend->profiler()->clear();
    backend->step(steps);
    std::map<std::string, double> perStep = backend->profiler()->seconds();
    for (auto& [name, seconds] : perStep) seconds /= double(steps);
    return perStep;
#else
    (void)warmupSteps;
    return {};
#endif
}

Traffic trafficPerParticleStep(const Variant& variant, double cellsPerParticle) {
    const Method& method = variant.method;
    const bool pairwise = variant.scheme == CollisionScheme::Pairwise;
    const double grid = kIndexBytes + kCellBytes * cellsPerParticle;
    const double search = pairwise ? kForwardSearchBytes : 0.0;
    Traffic t;
    if (method.eventDriven) return t;
    if (method.allPairs) {
        (method.opencl ? t.device : t.host) = kStateBytes;
    } else if (!method.opencl) {
        t.host = kStateBytes + grid + search;
    } else if (method.name == "opencl-resident") {
        t.device = kStateBytes + grid + search;
    } else {  // host-grid: the host reads its copy and writes the grid; the device reads the grid once
        const double cellOf = pairwise ? kCellOfBytes : 0.0;
        t.host = kStateBytes / 2 + grid / 2 + cellOf;
        t.upload = grid / 2 + cellOf;
        t.download = kStateBytes / 2;
        t.device = kStateBytes + grid / 2 + search;
    }
    return t;
}

double cellsPerParticle(const WorldDef& world, float radius, std::uint32_t particles) {
    const GridGeometry g = gridGeometryFor(world, radius, particles);
    return double(g.cols) * g.rows / particles;
}

double floorSecondsPerParticleStep(const Traffic& t, const Bandwidth& b) {
    double seconds = 0;
    for (const auto& [bytes, rate] : {std::pair{t.device, b.deviceCopy}, std::pair{t.host, b.hostCopy},
                                      std::pair{t.upload, b.upload}, std::pair{t.download, b.download}}) {
        if (bytes == 0) continue;
        if (rate <= 0) return 0;
        seconds += bytes / rate;
    }
    return seconds;
}

}  // namespace carom::bench
