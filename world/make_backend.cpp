#include "world/make_backend.h"

#include "backends/cpu.h"
#ifdef CAROM_HAVE_MPI
#include "backends/decomposed.h"
#endif
#include "backends/event_driven.h"
#ifdef CAROM_HAVE_OPENCL
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

std::unique_ptr<Backend> makeBackend(const WorldDef& world) {
    if (world.decomposition) {
        if (world.collisions == CollisionScheme::Events)
            throw Error(
                "CollisionScheme::Events runs in one process; allowed in a decomposed world: Pairwise, "
                "Simultaneous");
        if (world.engine != ComputeEngine::Cpu)
            throw Error(std::string("ComputeEngine ") + computeEngineName(world.engine) +
                        " does not step a domain of a decomposed world yet; allowed there: ComputeEngine::Cpu "
                        "(--backend cpu)");
#ifdef CAROM_HAVE_MPI
        WorldDef one = world;
        one.decomposition.reset();
        auto engine = std::make_unique<CpuBackend>(one);
        // Its shares change every substep: their lists would be built anew each one.
        engine->useNeighbourLists(false);
        return std::make_unique<DecomposedBackend>(world, std::move(engine));
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
