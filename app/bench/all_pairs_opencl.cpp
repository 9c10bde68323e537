#include "app/bench/all_pairs_opencl.h"

#include <utility>

#include "app/bench/program.h"

namespace carom::bench {

using namespace opencl;

AllPairsOpenClBackend::AllPairsOpenClBackend(const WorldDef& world, const std::string& device, bool profiling)
    : OpenClBackend(world, device, bench::kernelSource(), profiling) {
    if (world.collisions != CollisionScheme::Simultaneous)
        throw Error("the all-pairs pipeline runs the simultaneous scheme only");
    allPairsKernel_ = createKernel(program_.get(), "resolveAllPairs");
    integrateKernel_ = createKernel(program_.get(), "integrate");
    fitWorkGroups({allPairsKernel_.get(), integrateKernel_.get()}, {});
}

void AllPairsOpenClBackend::enqueueStep(float dt) {
    const CaromStepParams step = stepParams(dt);
    setKernelArgs(allPairsKernel_.get(), state_.get(), step, next_.get(), tallies_.get());
    enqueue1d(queue_.get(), allPairsKernel_.get(), step.count, workGroupSize_, "resolveAllPairs", profiler_.get());
    setKernelArgs(integrateKernel_.get(), next_.get(), step, tallies_.get(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue_.get(), integrateKernel_.get(), step.count, workGroupSize_, "integrate", profiler_.get());
    std::swap(state_, next_);
}

}  // namespace carom::bench
