#include "bench/all_pairs_opencl.h"

#include <utility>

#include "bench/kernel_source.h"

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
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    const cl_int periodic = caromBoxOf(world_).periodic;
    setKernelArgs(allPairsKernel_.get(), state_.get(), count, world_.width, world_.height, periodic, next_.get(),
                  tallies_.get());
    enqueue1d(queue_.get(), allPairsKernel_.get(), count, workGroupSize_, "resolveAllPairs", profiler_.get());
    setKernelArgs(integrateKernel_.get(), next_.get(), count, dt, world_.gravity.x, world_.gravity.y, world_.width,
                  world_.height, periodic, tallies_.get(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue_.get(), integrateKernel_.get(), count, workGroupSize_, "integrate", profiler_.get());
    std::swap(state_, next_);
}

}  // namespace carom::bench
