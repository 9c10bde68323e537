#include "backends/opencl/small_system.h"

#include "backends/backend.h"

namespace carom::opencl {
namespace {

// The one work-group, at most (the largest the scan tile's local memory
// allows), and the values each work-item scans (CAROM_SMALL_SYSTEM_SCAN_ITEMS
// in kernels/small_system.cl): a small tile, so that the work-group can be large.
constexpr std::size_t kSmallSystemGroupSize = 1024;
constexpr std::size_t kSmallSystemScanItems = 4;

}  // namespace

DeviceSmallSystem::DeviceSmallSystem(const DeviceInfo& device, cl_program program, Profiler* profiler)
    : profiler_(profiler) {
    stepsKernel_ = createKernel(program, "stepSmallSystem");
    pairwiseKernel_ = createKernel(program, "stepSmallPairwise");
    stepsGroupSize_ = DeviceGrid::scanGroupSize(device, kernelWorkGroupLimit(stepsKernel_.get(), device.id),
                                                kSmallSystemGroupSize, kSmallSystemScanItems);
    // The pairwise one also reduces the largest speed: a float per work-item.
    pairwiseGroupSize_ = DeviceGrid::scanGroupSize(device, kernelWorkGroupLimit(pairwiseKernel_.get(), device.id),
                                                   kSmallSystemGroupSize, kSmallSystemScanItems, sizeof(cl_float));
}

void DeviceSmallSystem::enqueueSteps(cl_command_queue queue, const StepBuffers& buffers, const DeviceGrid& grid,
                                     const CaromStepParams& step, cl_uint steps, cl_uint firstStepIndex,
                                     cl_mem firstNonFinite) {
    const std::size_t group = stepsGroupSize_;
    setKernelArgs(stepsKernel_.get(), buffers.state, buffers.next, buffers.ids, buffers.sortedIds, grid.cells(),
                  grid.counts(), grid.cellOrder(), grid.cellOf(), grid.rankInCell(), step, steps, buffers.tallies,
                  firstStepIndex, firstNonFinite);
    setLocalArg(stepsKernel_.get(), 14, DeviceGrid::scanTileBytes(group, kSmallSystemScanItems));
    setLocalArg(stepsKernel_.get(), 15, DeviceGrid::scanRunBytes(group));
    enqueue1d(queue, stepsKernel_.get(), group, group, "stepSmallSystem", profiler_);
}

void DeviceSmallSystem::enqueuePairwiseSteps(cl_command_queue queue, const StepBuffers& buffers, const DeviceGrid& grid,
                                             DevicePairwise& pairwise, const CaromStepParams& step,
                                             const CaromSubstepRule& rule, cl_uint substeps, cl_uint substepsPerStep,
                                             cl_uint speedParity, cl_uint firstStepIndex) {
    const cl_uint firstEpoch = pairwise.reserveSubstepEpochs(queue, substeps);
    setKernelArgs(pairwiseKernel_.get(), buffers.state, buffers.next, buffers.ids, buffers.sortedIds, grid.cells(),
                  grid.counts(), grid.nextCounts(), grid.cellOrder(), grid.cellOf(), grid.rankInCell(), step,
                  buffers.tallies, pairwise.lists(), DevicePairwise::lengthCount(), firstEpoch,
                  cl_uint{kMaxPairwiseRounds}, substeps, substepsPerStep, rule, firstStepIndex,
                  DevicePairwise::nonFiniteIndex(), DevicePairwise::speedIndex(), speedParity,
                  DevicePairwise::takenIndex());
    const std::size_t group = pairwiseGroupSize_;
    setLocalArg(pairwiseKernel_.get(), 24, DeviceGrid::scanTileBytes(group, kSmallSystemScanItems));
    setLocalArg(pairwiseKernel_.get(), 25, DeviceGrid::scanRunBytes(group));
    setLocalArg(pairwiseKernel_.get(), 26, group * sizeof(cl_float));
    enqueue1d(queue, pairwiseKernel_.get(), group, group, "stepSmallPairwise", profiler_);
}

}  // namespace carom::opencl
