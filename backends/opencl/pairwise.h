// The rounds of the pairwise scheme on an OpenCL device (kernels/pairwise.cl),
// for both pipelines: the same passes as the CPU backend's, so the same
// events in the same rounds, bit for bit.
//
// A step enqueues its start (startPairwiseStep: a check, the lengths
// zeroed), the first search (findEvents), the first rounds as launches of their two
// passes, and the rest in one launch of resolveRoundsInGroup, without
// waiting: one work-group runs them with barriers until no event is left, so
// every step's rounds are done when its last kernel is. Long lists need the
// whole device, short ones not the two launches a round (each about 5.5 us
// on an H200): a round runs as launches when its pending list was long in the
// step before (kLaunchedRoundLength). Which kernel runs a round changes no
// result. complete() later reads the lists' lengths, once a step or once a
// chunk of steps.
//
// With neighbour lists (enableLists, the resident pipeline's), each
// substep's start decides on the device whether its searches use the lists
// that hold, build them first, or use the grid (startPairwiseStep): the
// candidates are the same, so the results are too.
#pragma once

#include <cstddef>
#include <vector>

#include "backends/opencl/runtime.h"
#include "kernels/pairwise.h"

namespace carom::opencl {

class DevicePairwise {
public:
    DevicePairwise() = default;
    // Kernels from `program`, buffers for `particleCount` disks; launches are
    // recorded in `profiler` when given.
    DevicePairwise(cl_context context, const DeviceInfo& device, cl_program program, std::size_t particleCount,
                   cl_command_queue queue, Profiler* profiler = nullptr);
    // The disks the buffers hold (the constructor's count); 0 for none.
    std::size_t room() const { return room_; }
    // Takes these buffers for `particleCount` (<= room()) disks, as the
    // constructor leaves them (without neighbour lists).
    void setParticleCount(cl_command_queue queue, std::size_t particleCount);

    // The grid and state of a step: `state[slots[k]]` is the disk at
    // sorted position k, `ids[k]` its id, `cellOf[slots[k]]` its cell; with
    // `slots` null, the state is in sorted order (kernels/pairwise.h,
    // carom_slot).
    // `halt`: two words (kernels/params.h), the first CAROM_RUNNING while a
    // chunk of steps runs on; its kernels do nothing once it says the chunk
    // stopped (startPairwiseStep).
    struct StepBuffers {
        cl_mem state, slots, ids, cellOf, cells, tallies, halt;
    };

    // What startPairwiseStep checks of the state a substep starts from, in
    // a chunk of substeps enqueued without a wait: nothing (the chunk's
    // first), that no disk is non-finite, or that too and that its largest
    // speed (the word speedIndex() + speedParity of lists()) needs `substeps` under `rule`
    // (a step's first substep). A failed check writes stepIndex to halt.
    static constexpr cl_uint kNoCheck = 0, kCheckFinite = 1, kCheckSubsteps = 2;
    struct StartCheck {
        cl_uint check = kNoCheck;
        CaromSubstepRule rule{};
        cl_uint substeps = 0, speedParity = 0, stepIndex = 0;  // speedParity: speedIndex()'s word of the state
    };
    // Enqueues the start of a (sub)step: the check, then the lengths zeroed
    // and, with lists, their plan for `step`.
    void enqueueStart(cl_command_queue queue, cl_mem halt, const StartCheck& check, const CaromStepParams& step);

    // Searches neighbour lists with this skin (the reach beyond contact), for
    // which the grid's cells must be wide enough, instead of the grid's cells
    // wherever they hold; the state must then stay in the order the lists
    // were built for between builds (the grid's kernels keep it where the
    // start says the lists hold: halt[1]). Their buffer (the entries'
    // room grows as they need it) is neighbours().
    void enableLists(cl_context context, float skin);
    cl_mem neighbours() const { return neighbours_.get(); }
    bool searchesLists() const { return skin_ > 0.0f; }  // whether they are on (they may stop: complete())
    // Since the buffers were made, as of the last complete(): the lists'
    // builds, and the substeps that searched them.
    cl_uint listBuildsRecord() const { return hostCounts_[CAROM_LISTS_BUILDS]; }
    cl_uint listUsesRecord() const { return hostCounts_[CAROM_LISTS_USES]; }
    std::size_t listRoom() const { return listRoom_; }  // the entries neighbours() holds
    // Enqueues the rounds of one (sub)step after its start: afterwards a finish kernel may follow.
    void enqueueStep(cl_command_queue queue, const StepBuffers& buffers, const CaromStepParams& step);
    // The lists' buffer (kernels/pairwise.cl CaromDeviceLists), whose first
    // words are the list lengths, where a finish kernel also records
    // (nonFiniteIndex, speedIndex).
    cl_mem lists() const { return lists_.get(); }

    // Where a finish kernel records a disk it left non-finite: the two words
    // of lists() from nonFiniteIndex() (carom_record_non_finite); and the
    // largest v.x^2 + v.y^2 of the state it leaves, as a float's bits: word
    // speedIndex() + parity, the other word zeroed for the step after. The
    // caller sets them once; complete() reads them back with the lengths,
    // so the record costs no read of its own.
    // stepSmallPairwise also records the substeps it took, at takenIndex();
    // it and finishPairwiseAndCount the most rounds a substep used, at
    // roundsIndex(), the word after (clearRoundsRecord() zeroes it).
    static constexpr std::size_t kNonFiniteWords = 2, kSpeedWords = 2;  // a speed word for each parity
    static constexpr std::size_t kTakenWords = 2;
    static constexpr std::size_t kRecordWords =
        kNonFiniteWords + kSpeedWords + kTakenWords;  // nonFiniteIndex()'s, speedIndex()'s, takenIndex()'s
    static cl_uint nonFiniteIndex();
    static cl_uint speedIndex();
    static cl_uint takenIndex();
    static cl_uint roundsIndex() { return takenIndex() + 1; }
    const cl_uint* nonFiniteRecord() const;
    float speedSquaredRecord(unsigned int parity) const;
    cl_uint substepsTakenRecord() const { return hostCounts_[takenIndex()]; }
    cl_uint mostRoundsRecord() const { return hostCounts_[roundsIndex()]; }
    void clearRoundsRecord(cl_command_queue queue);

    // Waits for the step's rounds and returns how many resolved an event.
    unsigned int complete(cl_command_queue queue);

    // For a kernel that runs whole steps in one work-group instead of
    // enqueueStep (stepSmallPairwise, kernels/small_system.cl): lists(), the
    // number of lengths it zeroes, and the epochs of `substeps` substeps:
    // substep s's are the one returned + s * (kMaxPairwiseRounds + 1) and
    // its rounds' after it (the marks are cleared when they would wrap).
    // complete() then reads its record.
    static cl_uint lengthCount();
    cl_uint reserveSubstepEpochs(cl_command_queue queue, unsigned int substeps);
    // For a share of a decomposed world (Backend::readLastRounds): the last
    // round of the last substep enqueued that changed each disk, 0 for none,
    // by id; `ids` names the disk at each sorted position of that substep.
    void readLastRounds(cl_command_queue queue, cl_mem ids, std::vector<unsigned int>& rounds) const;
    // Where those marks are: the word of lists() with the first sorted
    // position's; a mark above substepEpoch() is that epoch plus the round.
    cl_uint changedMarksWord() const;
    unsigned int substepEpoch() const { return substepEpoch_; }

private:
    unsigned int nextEpoch(cl_command_queue queue);
    cl_uint reserveEpochs(cl_command_queue queue, unsigned int count);  // `count` epochs, from the one returned
    void readLengths(cl_command_queue queue);  // waits for the queue; reads the lengths and the record
    void clearMarks(cl_command_queue queue);   // zeroes the three lists' marks
    void enqueueRound(cl_command_queue queue, unsigned int round);
    void enqueueRoundsInGroup(cl_command_queue queue, unsigned int firstRound);

    bool makeListRoom(cl_context context, std::size_t entries);  // neighbours_ for this many entries, if it can

    std::size_t particleCount_ = 0;
    std::size_t room_ = 0;
    std::size_t computeUnits_ = 1;
    Profiler* profiler_ = nullptr;
    cl_context context_ = nullptr;  // lists: where their room grows
    float skin_ = 0.0f;             // lists: their skin; 0 without
    std::size_t listRoom_ = 0;      // lists: the entries neighbours_ holds
    std::size_t groupSize_ = 64;
    std::size_t listItems_ = 64;        // work-items of a list kernel, which stride over its list
    std::size_t roundsGroupSize_ = 64;  // resolveRoundsInGroup's one work-group
    Kernel startKernel_, findKernel_, searchChangedKernel_, resolveKernel_, roundsInGroupKernel_, buildListsKernel_;
    Buffer lists_, neighbours_;
    std::vector<cl_uint> hostCounts_;
    unsigned int epoch_ = 0;
    // The epoch of the last substep enqueued: its round r marks the disks it changes with this + r.
    unsigned int substepEpoch_ = 0;
    // Rounds 1 .. this run as launches: set from the step before's lengths;
    // the first step's is a guess.
    unsigned int launchedRounds_ = 4;
    StepBuffers buffers_{};  // the current step's
    CaromStepParams step_{};
};

}  // namespace carom::opencl
