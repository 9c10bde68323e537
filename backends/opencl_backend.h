// The OpenCL backend, with three pipelines:
//  - seed: each step the host builds the grid with the shared builder from
//    its copy of the state, uploads it, runs the collision scheme's kernels
//    (simultaneous: resolveCollisions and integrate, kernels/step.cl;
//    pairwise: the rounds of kernels/pairwise.cl) and reads the new state back;
//  - resident: the state stays on the device, stored in the cell order of
//    the step before; the grid is built there (DeviceGrid, kernels/grid.cl)
//    and one fused kernel resolves, integrates and counts the new positions
//    into the next grid (kernels/resident.cl; pairwise: the rounds, then a
//    kernel that finishes the step and counts). The host reads the state only
//    when asked (readParticles);
//  - all-pairs: resident too, but every particle checks every other, O(N^2):
//    the naive baseline of `carom bench` (kernels/bench.cl).
// Seed and resident give bitwise identical results (and equal the CPU
// backend's where exactArithmetic()); all-pairs sums in another order.
#pragma once

#include "backends/backend.h"
#include "backends/opencl_grid.h"
#include "backends/opencl_pairwise.h"
#include "backends/opencl_runtime.h"

namespace carom {

enum class Pipeline { Seed, Resident, AllPairs };

// "seed" or "resident" (BackendDef::pipeline); throws Error naming the value
// otherwise. All-pairs is for the benchmark only.
Pipeline parsePipeline(const std::string& name);

class OpenClBackend final : public Backend {
public:
    // `device`: see opencl::selectDevice. With `profiling`, each command's
    // device time is recorded (profiler()); for explaining a step, not timing it.
    OpenClBackend(const WorldDef& world, const std::string& device, Pipeline pipeline = Pipeline::Seed,
                  bool profiling = false);

    std::string name() const override { return "opencl"; }
    std::string device() const override;
    bool exactArithmetic() const override { return device_.correctlyRoundedDivideSqrt; }
    Pipeline pipeline() const { return pipeline_; }
    const opencl::DeviceInfo& deviceInfo() const { return device_; }

    void readParticles(std::vector<Particle>& particles) override;

    // Resident pipeline only: the grid of the current state as the device
    // builds it, read back (tests compare it with the shared builder's).
    Grid readDeviceGrid();

    // Seconds per kernel, transfer and host grid build over the steps so
    // far; null unless constructed with profiling.
    opencl::Profiler* profiler() { return profiler_.get(); }

private:
    void load(std::vector<Particle> particles) override;
    void advance(std::uint64_t substeps, float dt) override;
    float maxSpeedSquared() override;
    void drainTallies(ContactTotals& totals) override;
    void awaitSteps() override;
    void loadResident(std::size_t particleCount);
    void finish();  // waits for the queue; collects the profile
    void stepSeed(float dt);
    void stepResident(float dt);
    void stepSeedPairwise(float dt);
    void stepResidentPairwise(float dt);
    void enqueueResidentFinish(const CaromPairwiseStep& step, cl_uint stepIndex);
    // The index under which the kernels of the substep being enqueued record
    // a disk left non-finite (counted from nonFiniteBase_); counts the substep.
    cl_uint nextStepIndex() { return static_cast<cl_uint>(substep_++ - nonFiniteBase_); }
    // Reads firstNonFinite_ without waiting; checkNonFinite() after a wait
    // that covers the read, with nothing enqueued after it, reports what it
    // found (recordNonFinite) or moves the base past every substep so far.
    void enqueueNonFiniteRead();
    void checkNonFinite();
    // Resident pairwise: waits for the last step's rounds (and runs the rest
    // if its batch fell short), then makes its result the current state.
    void confirmStep();
    void uploadGrid();  // seed: the host's grid of hostState_
    void stepAllPairs(float dt);
    cl_int periodic() const { return caromBoxOf(world_).periodic; }

    Pipeline pipeline_;
    std::unique_ptr<opencl::Profiler> profiler_;
    opencl::DeviceInfo device_;
    opencl::Context context_;
    opencl::Queue queue_;
    opencl::Program program_;
    opencl::Kernel resolveKernel_;
    opencl::Kernel integrateKernel_;
    opencl::Kernel fusedKernel_;     // resident: resolveIntegrateAndCount
    opencl::Kernel allPairsKernel_;  // all-pairs: resolveAllPairs
    opencl::Kernel maxSpeedKernel_;  // resident and all-pairs: maxSpeedSquared
    opencl::Kernel finishByIdKernel_;       // pairwise, seed: finishStepById
    opencl::Kernel finishAndCountKernel_;   // pairwise, resident: finishPairwiseAndCount
    std::size_t workGroupSize_ = 64;
    std::size_t reductionGroupSize_ = 64;  // a power of two

    std::vector<Particle> hostState_;  // seed: the state the host builds the grid from
    opencl::Buffer state_;             // the state before the step (resident: in slots)
    opencl::Buffer next_;              // written by the step, then swapped in
    opencl::Buffer sortedIndices_;     // seed: uploaded each step
    opencl::Buffer cells_;             // seed: uploaded each step
    opencl::Buffer cellOf_;            // seed, pairwise: uploaded each step
    opencl::DevicePairwise pairwise_;  // pairwise
    opencl::Buffer tallies_;           // ContactTally by particle id
    opencl::Buffer groupMax_;          // maxSpeedSquared's per-group results
    opencl::Buffer speedBits_;         // pairwise, resident: the largest v^2 each step leaves (two words)
    unsigned int speedParity_ = 0;     // the word the last step wrote
    bool speedKnown_ = false;          // whether that word holds the current state's
    bool unconfirmed_ = false;         // a resident pairwise step was enqueued and not yet confirmed
    cl_uint unconfirmedStepIndex_ = 0; // and its nextStepIndex() (its parameters: pairwise_.step())
    std::size_t finishItems_ = 0;      // work-items of finishPairwiseAndCount, which stride over the particles
    opencl::DeviceGrid deviceGrid_;    // resident
    opencl::Buffer ids_;               // resident: the particle id in each slot of state_
    opencl::Buffer sortedIds_;         // resident: sortedIndices, then the ids of next_'s slots
    // Where the kernels that write a step's result record a disk it left
    // non-finite (carom_record_non_finite): the first step, as an index from
    // nonFiniteBase_, and the lowest id; read at the waits each pipeline has.
    // The resident pairwise finish records in the pairwise lengths instead,
    // which its step reads anyway (DevicePairwise::nonFiniteIndex).
    opencl::Buffer firstNonFinite_;
    cl_uint firstNonFiniteRead_[2] = {};  // the host's copy of the record last read
    std::uint64_t substep_ = 0;           // substeps enqueued since load
    std::uint64_t nonFiniteBase_ = 0;     // the substep that step index 0 means
};

}  // namespace carom
