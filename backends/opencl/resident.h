// The OpenCL resident pipeline (--pipeline resident): the state stays on the
// device, stored in the cell order of the step before; the grid is built
// there (DeviceGrid, kernels/grid.cl) and one fused kernel resolves,
// integrates and counts the new positions into the next grid
// (kernels/resident.cl; pairwise: the rounds, then a kernel that finishes
// the step and counts). Pairwise steps run in chunks with one wait each,
// the device checking each step's substep count (stepPairwiseChunk). A
// small system's steps run whole in one work-group instead
// (DeviceSmallSystem, kernels/small_system.cl): a chunk of pairwise steps,
// or several simultaneous steps, per launch. The host reads the state only
// when asked (readParticles). Pairwise steps of large systems search
// neighbour lists, which skip the grid's build while they hold (kept in the
// order they were built for, the state stays there). Bitwise equal to the
// host-grid pipeline.
#pragma once

#include "backends/opencl/backend.h"
#include "backends/opencl/grid.h"
#include "backends/opencl/pairwise.h"
#include "backends/opencl/small_system.h"

namespace carom {

class OpenClResidentBackend final : public OpenClBackend {
public:
    // See OpenClBackend.
    OpenClResidentBackend(const WorldDef& world, const std::string& device, bool profiling = false);

    // The grid of the current state as the device builds it, read back
    // (tests compare it with the shared builder's).
    Grid readDeviceGrid();
    // Pairwise steps' neighbour lists, as of the last wait: whether they are
    // searched, and since the state was loaded how many builds there were and
    // how many substeps searched them.
    bool searchesNeighbourLists() const { return pairwise_.searchesLists(); }
    std::uint32_t neighbourListBuilds() const { return pairwise_.listBuildsRecord(); }
    std::uint32_t neighbourListUses() const { return pairwise_.listUsesRecord(); }
    std::size_t neighbourListRoom() const { return pairwise_.listRoom(); }  // entries, for all disks
    // Whether pairwise substeps may search neighbour lists (the default), as
    // of the next state loaded: the same bits either way.
    void useNeighbourLists(bool use) { listsAllowed_ = use; }

    // For a share of a decomposed world kept on this device
    // (OpenClDomainShare): steps the `count` (> 0) disks and tallies that
    // `particles` and `tallies` hold in id order by one substep of dt with
    // the grid of `whole`, as Backend::stepShare does without the copies to
    // and from the host; the result stays here (steppedShare).
    unsigned int stepDeviceShare(cl_mem particles, cl_mem tallies, std::size_t count, const Backend& whole, float dt);
    // Where the last substep left the share: the disks in slot order, the
    // share's index of the disk in each slot, the tallies by that index and,
    // pairwise, the marks of the rounds that changed each slot's disk:
    // lists[marksWord + slot] above epoch (lists null otherwise).
    struct SteppedShare {
        cl_mem state, slotIds, tallies, lists;
        cl_uint marksWord, epoch;
    };
    SteppedShare steppedShare() const;
    cl_context context() const { return context_.get(); }
    cl_command_queue queue() const { return queue_.get(); }
    cl_program program() const { return program_.get(); }

private:
    void readLastRounds(std::vector<unsigned int>& rounds) override;
    const char* pipelineName() const override { return "resident"; }
    void releaseState() override;
    void loadState(const std::vector<Particle>& particles) override;
    void startState(std::size_t n);  // loadState for n disks that state_ holds
    void enqueueStep(float dt) override;
    std::uint64_t enqueueSteps(std::uint64_t steps, float dt) override;
    cl_mem slotIds() const override { return ids_.get(); }
    // A pairwise step waits for its chunk's end (stepPairwiseChunk).
    bool waitsEachStep() const override { return world_.collisions == CollisionScheme::Pairwise; }
    float maxSpeedSquared() override;
    void stepSimultaneous(float dt);
    // Simultaneous steps of a small system, up to kSmallSystemSteps in one
    // launch; returns how many.
    std::uint64_t stepSmallSystem(std::uint64_t steps, float dt);
    opencl::DeviceSmallSystem::StepBuffers smallStepBuffers() const {
        return {state_.get(), next_.get(), ids_.get(), sortedIds_.get(), tallies_.get()};
    }
    void stepPairwise(float dt);
    // Pairwise steps run in chunks, their substep counts checked on the
    // device, with one wait a chunk (stepPairwiseChunk).
    std::uint64_t advanceWhileSubstepsHold(std::uint64_t steps, std::uint64_t substeps, float dt,
                                           const CaromSubstepRule& rule) override;
    // Enqueues up to `substeps` pairwise substeps of dt, `substepsPerStep`
    // to a step, a step after the first only while its state needs that
    // many under `rule` and no disk is non-finite; waits once, and returns
    // how many ran. A small system runs them in one launch
    // (DeviceSmallSystem::enqueuePairwiseSteps).
    std::uint64_t stepPairwiseChunk(std::uint64_t substeps, std::uint64_t substepsPerStep, float dt,
                                    const CaromSubstepRule& rule);
    void enqueuePairwiseSubstep(const CaromStepParams& step, const opencl::DevicePairwise::StartCheck& check);
    void swapStepBuffers();                // next_, sortedIds_ and the next counts become current
    void resumeAfterHalt();                // running again after a chunk stopped early
    void buildGridEachStep();              // halt[1] zeroed: the grid's kernels build it (kernels/params.h)
    opencl::Kernel fusedKernel_;           // resolveIntegrateAndCount
    opencl::Kernel finishAndCountKernel_;  // pairwise: finishPairwiseAndCount
    opencl::Kernel numberSlotsKernel_;     // numberSlots: slot s holds particle s
    opencl::DeviceSmallSystem smallSystem_;
    bool inOneGroup_ = false;   // steps run whole in one work-group (smallSystem_)
    bool gathered_ = false;     // pairwise steps gather the state into sorted order (kGatherUpTo), never with lists
    bool listsAllowed_ = true;  // useNeighbourLists
    opencl::DeviceGrid deviceGrid_;
    opencl::Buffer ids_;               // the particle id in each slot of state_
    opencl::Buffer sortedIds_;         // sortedIndices, then the ids of next_'s slots
    opencl::DevicePairwise pairwise_;  // pairwise
    // Pairwise: the finish records a disk left non-finite and the largest
    // v^2 after the pairwise lengths, which a chunk reads anyway
    // (DevicePairwise::nonFiniteIndex, speedIndex).
    unsigned int speedParity_ = 0;     // the speed word the last step wrote
    bool speedKnown_ = false;          // whether that word holds the current state's
    std::uint64_t chunkSubsteps_ = 1;  // the most a chunk of pairwise substeps takes (kChunkSeconds)
    std::size_t finishItems_ = 0;      // work-items of finishPairwiseAndCount, which stride over the particles
};

}  // namespace carom
