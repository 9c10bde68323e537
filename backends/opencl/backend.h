// The OpenCL backends: this base owns the device, context, queue and program
// and what every pipeline shares: the state and contact tallies on the
// device, the views and the max-speed reduction (DeviceViews,
// backends/opencl/view.h), the record of a disk left non-finite and the
// profiler. It launches no kernel itself; one class per pipeline runs the
// steps:
//  - OpenClHostGridBackend ("host-grid", backends/opencl/host_grid.h): the
//    host builds the grid, uploads it and reads the new state back each step;
//  - OpenClResidentBackend ("resident", backends/opencl/resident.h):
//    state and grid stay on the device;
//  - bench::AllPairsOpenClBackend (app/bench/all_pairs_opencl.h): the naive
//    O(N^2) baseline of `carom bench`, with a program of its own.
// Host-grid and resident give bitwise identical results (and equal the CPU
// backend's where exactArithmetic()); all-pairs sums in another order.
#pragma once

#include <initializer_list>
#include <memory>

#include "backends/backend.h"
#include "backends/opencl/runtime.h"
#include "backends/opencl/view.h"

namespace carom {

class OpenClBackend : public Backend {
public:
    ~OpenClBackend() override;
    std::string device() const override;
    bool exactArithmetic() const override { return device_.correctlyRoundedDivideSqrt; }
    DeviceMemoryUse deviceMemory() const override;
    const opencl::DeviceInfo& deviceInfo() const { return device_; }

    // Reads state_, in id order (slotIds()).
    void readParticles(std::vector<Particle>& particles) override;
    // On the device (DeviceViews::read): reads back 16 bytes a disk and the
    // work-groups' sums.
    std::optional<ViewSums> readView(ViewValue value, DiskView* out) override;

    // Seconds per kernel, transfer and host grid build over the steps so
    // far; null unless constructed with profiling.
    opencl::Profiler* profiler() { return profiler_.get(); }

protected:
    // `device`: see opencl::selectDevice. The program is built from
    // `programSource`, which must hold kernels/view.cl's kernels.
    // With `profiling`, each command's device time is recorded (profiler());
    // for explaining a step, not timing it.
    OpenClBackend(const WorldDef& world, const std::string& device, const char* programSource, bool profiling);

    // The pipeline's name in device(): "host-grid", "resident", "all-pairs".
    virtual const char* pipelineName() const = 0;
    // Frees the buffers the pipeline keeps for the state loaded before.
    virtual void releaseState() = 0;
    // Makes the pipeline's buffers for `particles`, which state_ holds by id.
    virtual void loadState(const std::vector<Particle>& particles) = 0;
    // load()'s start: state_, next_ and tallies_ (zeroed) for n disks, the
    // pipeline's buffers released and no disk non-finite; state_ is to be
    // filled. With `keepRoom` (a decomposed world's shares, whose size
    // changes every substep), buffers that hold n disks are kept, and the
    // pipeline's with them; new ones hold a quarter more.
    void createState(std::size_t n, bool keepRoom = false);
    // The disks state_, next_ and tallies_ hold: particleCount() or more.
    std::size_t stateRoom() const { return stateRoom_; }
    // Enqueues one substep of dt.
    virtual void enqueueStep(float dt) = 0;
    // Enqueues up to `steps` (>= 1) substeps of dt and returns how many: one
    // unless the pipeline can run several in one launch.
    virtual std::uint64_t enqueueSteps(std::uint64_t steps, float dt) {
        (void)steps;
        enqueueStep(dt);
        return 1;
    }
    // The id of the disk in each slot of state_; null where slot = id.
    virtual cl_mem slotIds() const { return nullptr; }
    // The disks of `state`, whose slots hold the disks `ids` names (null:
    // slot = id), in id order.
    void readInIdOrder(cl_mem state, cl_mem ids, std::vector<Particle>& particles);
    // Whether enqueueStep ends in a wait of its own; else advance() waits
    // every kStepsPerSync steps and at its end.
    virtual bool waitsEachStep() const { return false; }

    // The largest v.x^2 + v.y^2 of state_: a reduction on the device
    // (DeviceViews::maxSpeedSquared).
    float maxSpeedSquared() override;

    // Lowers workGroupSize_ to what the kernels with one work-item per
    // particle allow on the device, and reductionGroupSize_ to what those
    // that reduce in a work-group allow.
    void fitWorkGroups(std::initializer_list<cl_kernel> perParticle, std::initializer_list<cl_kernel> reducing);
    void finish();  // waits for the queue; collects the profile
    // The index under which the kernels of the substep being enqueued record
    // a disk left non-finite (counted from nonFiniteBase_); counts the substep.
    cl_uint nextStepIndex() { return reserveStepIndices(1); }
    // The indices of `count` substeps enqueued together: the first is returned.
    cl_uint reserveStepIndices(std::uint64_t count) {
        const auto first = static_cast<cl_uint>(substep_ - nonFiniteBase_);
        substep_ += count;
        return first;
    }
    // The last `count` substeps reserved did not run (the device stopped before them).
    void returnStepIndices(std::uint64_t count) { substep_ -= count; }
    // Reads firstNonFinite_ without waiting; checkNonFinite() after a wait
    // that covers the read, with nothing enqueued after it, reports what it
    // found (recordNonFinite) or moves the base past every substep so far.
    void enqueueNonFiniteRead();
    void checkNonFinite();

    // A record of a disk left non-finite before any was (kernels/physics.h, carom_record_non_finite).
    static constexpr cl_uint kNoneNonFinite[2] = {CAROM_ALL_FINITE, CAROM_ALL_FINITE};
    // halt_ while a chunk of steps runs on (kernels/params.h).
    static constexpr cl_uint kRunning = CAROM_RUNNING;

    std::unique_ptr<opencl::Profiler> profiler_;
    opencl::DeviceInfo device_;
    opencl::Context context_;
    opencl::Queue queue_;
    opencl::Program program_;
    std::size_t workGroupSize_ = 64;
    std::size_t reductionGroupSize_ = 256;  // a power of two

    opencl::Buffer state_;    // the state before the step
    opencl::Buffer next_;     // written by the step, then swapped in
    opencl::Buffer tallies_;  // ContactTally by particle id
    // Where the kernels that write a step's result record a disk it left
    // non-finite (carom_record_non_finite): the first step, as an index from
    // nonFiniteBase_, and the lowest id; read at the waits each pipeline has.
    opencl::Buffer firstNonFinite_;
    cl_uint firstNonFiniteRead_[2] = {};  // the host's copy of the record last read
    // One word every kernel of a pairwise step reads first: kRunning, or the
    // substep before which a chunk of steps enqueued without a wait stopped
    // (startPairwiseStep, kernels/pairwise.cl); those kernels then do nothing.
    // A second word tells the grid's kernels that neighbour lists hold, so
    // that the grid is not needed (kernels/params.h).
    opencl::Buffer halt_;

private:
    void load(const std::vector<Particle>& particles) final;
    std::uint64_t advance(std::uint64_t substeps, float dt) final;
    void drainTallies(ContactTotals& totals) final;
    void readTallies(std::vector<ContactTally>& tallies) final;
    void writeTallies(const std::vector<ContactTally>& tallies) final;
    // Copies on the device, made each step a stop may cut short (a read to
    // the host would cost more than the step at 10^6 disks); a stop is
    // rare, and a load (the pipeline's buffers afresh) is the one way back
    // every pipeline has.
    void keepStepStart() final;
    void returnToStepStart() final;
    void awaitSteps() final;

    opencl::DeviceViews views_;
    std::size_t stateRoom_ = 0;
    std::uint64_t substep_ = 0;        // substeps enqueued since setParticles
    std::uint64_t nonFiniteBase_ = 0;  // the substep that step index 0 means
    // keepStepStart's copies of state_, slotIds() (where the pipeline has
    // them) and tallies_; made at the first, freed by load().
    opencl::Buffer startState_, startIds_, startTallies_;
};

}  // namespace carom
