#include "world/make_backend.h"

#include <exception>
#include <utility>

#include <carom/world.h>

#include "backends/cpu.h"
#ifdef CAROM_HAVE_MPI
#include "backends/decomposed.h"
#endif
#include "backends/event_driven.h"
#ifdef CAROM_HAVE_OPENCL
#if defined(CAROM_HAVE_MPI)
#include "backends/opencl/domain_share.h"
#endif
#include "backends/opencl/host_grid.h"
#include "backends/opencl/resident.h"
#endif

namespace carom {

std::vector<std::string> availableBackends() {
#ifdef CAROM_HAVE_OPENCL
    return {"cpu", "opencl"};
#else
    return {"cpu"};
#endif
}

#ifdef CAROM_HAVE_MPI
namespace {

// The OpenCL device of this process where `world` names none: GPU number r
// mod the node's GPUs for the node's process r, else the first device.
std::string deviceOfProcess(const WorldDef& world, const Decomposition& decomposition) {
    if (world.engine == ComputeEngine::Cpu || !world.device.empty()) return world.device;
    std::vector<Device> gpus;
    for (const Device& d : listDevices())
        if (d.type == "GPU") gpus.push_back(d);
    if (gpus.empty()) return world.device;
    return std::to_string(gpus[std::size_t(decomposition.nodeRank()) % gpus.size()].index);
}

// The engine that steps this process's domain of `world`. Its shares change
// every substep: neighbour lists would be built anew each one.
std::unique_ptr<Backend> makeDomainEngine(WorldDef world) {
    const std::shared_ptr<const Decomposition> decomposition = std::move(world.decomposition);
    world.decomposition.reset();
    world.device = deviceOfProcess(world, *decomposition);
    std::unique_ptr<Backend> engine = makeBackend(world);
    if (auto* cpu = dynamic_cast<CpuBackend*>(engine.get())) cpu->useNeighbourLists(false);
#ifdef CAROM_HAVE_OPENCL
    if (auto* resident = dynamic_cast<OpenClResidentBackend*>(engine.get())) resident->useNeighbourLists(false);
#endif
    return engine;
}

// Where a process keeps its disks between substeps: on the device of a
// resident OpenCL engine, else on the host.
std::unique_ptr<DomainShare> domainShareOn(Backend& engine) {
#ifdef CAROM_HAVE_OPENCL
    if (auto* resident = dynamic_cast<OpenClResidentBackend*>(&engine))
        return std::make_unique<OpenClDomainShare>(*resident);
#endif
    return std::make_unique<HostDomainShare>(engine);
}

}  // namespace
#endif

std::unique_ptr<Backend> makeBackend(const WorldDef& world) {
    if (world.decomposition) {
        if (world.collisions == CollisionScheme::Events)
            throw Error(
                "CollisionScheme::Events runs in one process; allowed in a decomposed world: Pairwise, "
                "Simultaneous");
#ifdef CAROM_HAVE_MPI
        // Every process learns whether all made theirs (a device may be missing on one node).
        std::unique_ptr<Backend> engine;
        std::unique_ptr<DomainShare> share;
        std::string failure;
        try {
            engine = makeDomainEngine(world);
            share = domainShareOn(*engine);
        } catch (const std::exception& e) {
            failure = e.what();
        }
        requireEveryProcess(*world.decomposition, failure);
        return std::make_unique<DecomposedBackend>(world, std::move(engine), std::move(share));
#endif
    }
    if (world.engine != ComputeEngine::Cpu && world.collisions == CollisionScheme::Events)
        throw Error(std::string("CollisionScheme::Events runs on ComputeEngine::Cpu only (one thread, double "
                                "precision); got ComputeEngine ") +
                    computeEngineName(world.engine));
    switch (world.engine) {
        case ComputeEngine::Cpu:
            if (world.collisions == CollisionScheme::Events) return std::make_unique<EventDrivenBackend>(world);
            return std::make_unique<CpuBackend>(world);
        case ComputeEngine::OpenClHostGrid:
        case ComputeEngine::OpenClResident:
#ifdef CAROM_HAVE_OPENCL
            if (world.engine == ComputeEngine::OpenClResident)
                return std::make_unique<OpenClResidentBackend>(world, world.device);
            return std::make_unique<OpenClHostGridBackend>(world, world.device);
#else
            throw Error(std::string("ComputeEngine ") + computeEngineName(world.engine) +
                        " needs OpenCL, which this carom was built without (no OpenCL headers or loader were "
                        "found); allowed: ComputeEngine::Cpu");
#endif
    }
    throw Error("WorldDef::engine " + std::to_string(static_cast<int>(world.engine)) +
                " is not a ComputeEngine; allowed: Cpu, OpenClHostGrid, OpenClResident");
}

}  // namespace carom
