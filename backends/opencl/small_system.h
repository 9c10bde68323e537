// Whole steps of a small system in one work-group on an OpenCL device
// (kernels/small_system.cl), for the resident pipeline, which owns one:
// stepSmallSystem runs several simultaneous steps per launch,
// stepSmallPairwise several pairwise substeps (grid, every round, finish and
// largest speed each), checking their count on the device. They take the resident pipeline's state and its DeviceGrid's and
// DevicePairwise's buffers, and leave them as its launches do, bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>

#include "backends/opencl/grid.h"
#include "backends/opencl/pairwise.h"
#include "backends/opencl/runtime.h"

namespace carom::opencl {

// Up to this many disks, steps run whole in one work-group: below it, the
// launches of the grid build and the step cost more than one compute unit
// takes for the whole step. Measured on an H200
// (bench/results/nvidia-h200-small-system.txt), one work-group against
// launches: simultaneous 18 against 33 us a step at 1 000 disks, 37 against
// 33 at 2 000 (they cross near 1 800); pairwise 93 against 163 us at 1 000,
// 136 against 172 at 2 000, 209 against 176 at 4 000. One limit for both
// keeps each path tested on either side of it.
constexpr std::size_t kSmallSystemParticles = 2048;
// The most steps one launch of stepSmallSystem runs, and the most substeps
// one chunk of pairwise steps takes (one launch of stepSmallPairwise in a
// small system): a launch stays short (a device may stop a long one).
constexpr std::uint64_t kSmallSystemSteps = 16;
constexpr std::uint64_t kSmallPairwiseSubsteps = 64;

class DeviceSmallSystem {
public:
    DeviceSmallSystem() = default;
    // Kernels from `program`, their work-groups sized for the device;
    // launches are recorded in `profiler` when given.
    DeviceSmallSystem(const DeviceInfo& device, cl_program program, Profiler* profiler = nullptr);

    // The state of a step: slot s of `state` holds disk ids[s]; a step
    // writes its result to `next`, slot k holding disk sortedIds[k], and
    // counts its collisions into `tallies` (by id).
    struct StepBuffers {
        cl_mem state, next, ids, sortedIds, tallies;
    };

    // Enqueues `steps` (1 to kSmallSystemSteps) simultaneous steps in one
    // launch (stepSmallSystem), each building the grid from `grid`'s counts
    // and leaving its result's counts there: the last result is in `next`
    // and `sortedIds` when `steps` is odd, else in `state` and `ids`. Step s
    // records a disk left non-finite under firstStepIndex + s in
    // `firstNonFinite`.
    void enqueueSteps(cl_command_queue queue, const StepBuffers& buffers, const DeviceGrid& grid,
                      const CaromStepParams& step, cl_uint steps, cl_uint firstStepIndex, cl_mem firstNonFinite);
    // Enqueues up to `substeps` pairwise substeps of `step` in one launch
    // (stepSmallPairwise), `substepsPerStep` to a step, with `pairwise`'s
    // lists and epochs: a step after the first runs only while its state
    // needs substepsPerStep substeps under `rule` and no disk is
    // non-finite. Substep s records a disk it leaves non-finite under
    // firstStepIndex + s, as finishPairwiseAndCount does; the last state's
    // largest speed goes to word speedIndex() + `speedParity` of
    // pairwise.lists(), the substeps taken and the most rounds to
    // takenIndex(); pairwise.complete() reads them. The buffers swap roles
    // each substep: after an odd number the result is in `next`,
    // `sortedIds` and `grid`'s next counts.
    void enqueuePairwiseSteps(cl_command_queue queue, const StepBuffers& buffers, const DeviceGrid& grid,
                              DevicePairwise& pairwise, const CaromStepParams& step, const CaromSubstepRule& rule,
                              cl_uint substeps, cl_uint substepsPerStep, cl_uint speedParity, cl_uint firstStepIndex);

private:
    Profiler* profiler_ = nullptr;
    Kernel stepsKernel_;              // stepSmallSystem
    Kernel pairwiseKernel_;           // stepSmallPairwise
    std::size_t stepsGroupSize_ = 1;  // their one work-group: a power of two
    std::size_t pairwiseGroupSize_ = 1;
};

}  // namespace carom::opencl
