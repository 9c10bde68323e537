// The rounds of the pairwise scheme on an OpenCL device (kernels/pairwise.cl),
// for both pipelines: the same passes as the CPU backend's, so the same
// events in the same rounds, bit for bit.
//
// A step enqueues the first search and a batch of rounds, as many as the
// step before needed and one more, without waiting: a round whose pending
// list is empty resolves nothing, so running past the last event changes
// nothing. The kernel that finishes the step is enqueued right behind, with
// a condition the device checks (finishCondition): the batch left no event
// pending. complete() later reads the lists' lengths, once; in the rare step
// whose batch fell short it runs the remaining rounds (reading after each
// batch), and the caller enqueues the finish again.
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

    // The grid and state of a step: `state[slots[k]]` is the disk at
    // sorted position k, `ids[k]` its id, `cellOf[slots[k]]` its cell.
    struct StepBuffers {
        cl_mem state, slots, ids, cellOf, cells, tallies;
    };

    // Enqueues the first search and a batch of rounds of one (sub)step.
    void enqueueStep(cl_command_queue queue, const StepBuffers& buffers, const CaromStepParams& step);
    // A finish kernel enqueued after enqueueStep runs only if
    // lengths()[finishCondition()] is 0: no event pending after the batch.
    cl_mem lengths() const { return counts_.get(); }
    cl_uint finishCondition() const;
    // The parameters of the step enqueueStep enqueued last.
    const CaromStepParams& step() const { return step_; }

    // Where a finish kernel records a disk it left non-finite: the two words
    // of lengths() from nonFiniteIndex() (carom_record_non_finite). The
    // caller sets them once; complete() and readLengths() read them back
    // with the lengths, so the record costs no read of its own.
    static cl_uint nonFiniteIndex();
    const cl_uint* nonFiniteRecord() const;
    // Waits for the queue and reads the lengths and the record.
    void readLengths(cl_command_queue queue);

    struct Completion {
        unsigned int rounds = 0;     // rounds that resolved an event
        bool finishSkipped = false;  // the batch fell short: enqueue the finish again (its condition now holds)
    };
    // Waits for the step's rounds; runs the rest if the batch fell short.
    Completion complete(cl_command_queue queue);

    // For a kernel that runs a whole step in one work-group instead of
    // enqueueStep (stepSmallPairwise, kernels/small_system.cl): the lists,
    // the number of lengths it zeroes, and the epochs its rounds may take,
    // firstEpoch .. firstEpoch + kMaxPairwiseRounds (the marks are cleared
    // when they would wrap). complete() then reads its rounds.
    struct Lists {
        cl_mem events, pending0, pending1, changed, dirty, pendingMarks, changedMarks, dirtyMarks, lengths;
    };
    Lists lists() const;
    static cl_uint lengthCount();
    cl_uint reserveStepEpochs(cl_command_queue queue);

private:
    unsigned int nextEpoch(cl_command_queue queue);
    void clearMarks(cl_command_queue queue);  // zeroes the three lists' marks
    void enqueueRound(cl_command_queue queue, unsigned int round);
    void searchListed(cl_command_queue queue, int mode, cl_mem listed, unsigned int round, unsigned int listIndex,
                      unsigned int epoch);

    std::size_t particleCount_ = 0;
    Profiler* profiler_ = nullptr;
    std::size_t groupSize_ = 64;
    std::size_t listItems_ = 64;  // work-items of a list kernel, which stride over its list
    Kernel forwardKernel_, listedKernel_, resolveKernel_;
    Buffer events_, pending_[2], changed_, dirty_, pendingMarks_, changedMarks_, dirtyMarks_, counts_;
    std::vector<cl_uint> hostCounts_;
    unsigned int epoch_ = 0;
    unsigned int batch_ = 4;      // rounds enqueued per batch, adapted to the steps before
    unsigned int lastRound_ = 0;  // the last round enqueued for the current step
    StepBuffers buffers_{};       // the current step's
    CaromStepParams step_{};
};

}  // namespace carom::opencl
