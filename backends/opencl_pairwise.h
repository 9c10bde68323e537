// The rounds of the pairwise scheme on an OpenCL device (kernels/pairwise.cl),
// for both pipelines: the same passes as the CPU backend's, so the same
// events in the same rounds, bit for bit.
//
// The host enqueues the rounds in batches and reads the lists' lengths after
// each batch: a round whose pending list is empty resolves nothing, so a
// batch may run past the last event without changing the result, and the
// host needs one read per batch instead of one per round.
#pragma once

#include <cstddef>
#include <vector>

#include "backends/opencl_runtime.h"
#include "kernels/pairwise.h"

namespace carom::opencl {

class DevicePairwise {
public:
    DevicePairwise() = default;
    // Kernels from `program`, buffers for `particleCount` disks; launches are
    // recorded in `profiler` when given.
    DevicePairwise(cl_context context, const DeviceInfo& device, cl_program program, std::size_t particleCount,
                   cl_command_queue queue, Profiler* profiler = nullptr);

    // Finds and resolves every event of one (sub)step: the disks of `state`
    // end at their last event's time (kernels/pairwise.h, finishStep moves
    // them to the end). `slots`, `ids`, `cellOf` and `cells` are the step's
    // grid, as kernels/pairwise.cl describes. Returns the number of rounds
    // that resolved an event.
    unsigned int resolveStep(cl_command_queue queue, cl_mem state, cl_mem slots, cl_mem ids, cl_mem cellOf,
                             cl_mem cells, cl_mem tallies, const CaromPairwiseStep& step);

private:
    unsigned int nextEpoch(cl_command_queue queue);
    void searchListed(cl_command_queue queue, cl_mem state, cl_mem slots, cl_mem ids, cl_mem cellOf, cl_mem cells,
                      const CaromPairwiseStep& step, int mode, cl_mem listed, unsigned int round,
                      unsigned int listIndex, unsigned int epoch);

    std::size_t particleCount_ = 0;
    Profiler* profiler_ = nullptr;
    std::size_t groupSize_ = 64;
    std::size_t listItems_ = 64;  // work-items of a list kernel, which stride over its list
    Kernel forwardKernel_, listedKernel_, resolveKernel_;
    Buffer events_, pending_[2], changed_, dirty_, pendingMarks_, changedMarks_, dirtyMarks_, counts_;
    std::vector<cl_uint> hostCounts_;
    unsigned int epoch_ = 0;
    unsigned int batch_ = 4;  // rounds per read of the counts, adapted to the steps before
};

}  // namespace carom::opencl
