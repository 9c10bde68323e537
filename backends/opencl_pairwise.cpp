#include "backends/opencl_pairwise.h"

#include <algorithm>
#include <limits>

#include "backends/backend.h"

namespace carom::opencl {

namespace {

// Work-items per compute unit for the list kernels: enough to hide memory
// latency on a GPU; a list longer than all of them is strided over.
constexpr std::size_t kListItemsPerComputeUnit = 2048;

// counts_: three lengths per round, rounds 0 .. kMaxPairwiseRounds, one
// entry that stays 0 (the finish condition once the rounds are capped), then
// the two words where the finish kernel records a disk it left non-finite,
// which are not cleared with the lengths and are read back with them.
constexpr std::size_t kCounts = 3 * (kMaxPairwiseRounds + 1) + 1;
constexpr cl_uint kAlwaysZero = kCounts - 1;
constexpr std::size_t kNonFiniteWords = 2;
constexpr std::size_t kCountsWithRecord = kCounts + kNonFiniteWords;

}  // namespace

static_assert(sizeof(CaromEvent) == 8, "CaromEvent must match its OpenCL layout");

DevicePairwise::DevicePairwise(cl_context context, const DeviceInfo& device, cl_program program,
                               std::size_t particleCount, cl_command_queue queue, Profiler* profiler)
    : particleCount_(particleCount), profiler_(profiler), hostCounts_(kCountsWithRecord) {
    forwardKernel_ = createKernel(program, "findEventsForward");
    listedKernel_ = createKernel(program, "searchListed");
    resolveKernel_ = createKernel(program, "resolveEvents");
    for (cl_kernel k : {forwardKernel_.get(), listedKernel_.get(), resolveKernel_.get()})
        groupSize_ = std::min(groupSize_, kernelWorkGroupLimit(k, device.id));
    listItems_ = std::min((particleCount + groupSize_ - 1) / groupSize_ * groupSize_,
                          std::max<std::size_t>(1, device.computeUnits) * kListItemsPerComputeUnit);

    const std::size_t n = particleCount;
    events_ = createBuffer(context, n * sizeof(CaromEvent), "pairwise events");
    pending_[0] = createBuffer(context, n * sizeof(cl_uint), "pending list");
    pending_[1] = createBuffer(context, n * sizeof(cl_uint), "next pending list");
    changed_ = createBuffer(context, n * sizeof(cl_uint), "changed list");
    dirty_ = createBuffer(context, n * sizeof(cl_uint), "dirty list");
    pendingMarks_ = createBuffer(context, n * sizeof(cl_uint), "pending marks");
    changedMarks_ = createBuffer(context, n * sizeof(cl_uint), "changed marks");
    dirtyMarks_ = createBuffer(context, n * sizeof(cl_uint), "dirty marks");
    counts_ = createBuffer(context, kCountsWithRecord * sizeof(cl_uint), "list lengths");
    clearMarks(queue);
}

void DevicePairwise::clearMarks(cl_command_queue queue) {
    for (cl_mem marks : {pendingMarks_.get(), changedMarks_.get(), dirtyMarks_.get()})
        enqueueZero(queue, marks, particleCount_ * sizeof(cl_uint), "pairwise marks");
}

// Each round's marks carry a new epoch, so no list needs clearing; when the
// counter wraps, the marks are cleared once.
unsigned int DevicePairwise::nextEpoch(cl_command_queue queue) {
    if (++epoch_ == 0) {
        clearMarks(queue);
        epoch_ = 1;
    }
    return epoch_;
}

void DevicePairwise::searchListed(cl_command_queue queue, int mode, cl_mem listed, unsigned int round,
                                  unsigned int listIndex, unsigned int epoch) {
    const StepBuffers& b = buffers_;
    setKernelArgs(listedKernel_.get(), b.state, b.slots, b.ids, b.cellOf, b.cells, step_, events_.get(), cl_int{mode},
                  listed, changed_.get(), changedMarks_.get(), dirty_.get(), dirtyMarks_.get(),
                  pending_[round % 2].get(), pendingMarks_.get(), counts_.get(), cl_uint{round}, cl_uint{listIndex},
                  cl_uint{epoch});
    enqueue1d(queue, listedKernel_.get(), listItems_, groupSize_,
              mode == CAROM_SEARCH_CHANGED ? "searchListed (changed)" : "searchListed (dirty)", profiler_);
}

void DevicePairwise::enqueueRound(cl_command_queue queue, unsigned int round) {
    const StepBuffers& b = buffers_;
    const unsigned int epoch = nextEpoch(queue);
    setKernelArgs(resolveKernel_.get(), b.state, b.slots, b.ids, events_.get(), step_, b.tallies,
                  pending_[(round - 1) % 2].get(), pending_[round % 2].get(), pendingMarks_.get(), changed_.get(),
                  changedMarks_.get(), counts_.get(), cl_uint{round}, cl_uint{epoch});
    enqueue1d(queue, resolveKernel_.get(), listItems_, groupSize_, "resolveEvents", profiler_);
    searchListed(queue, CAROM_SEARCH_CHANGED, changed_.get(), round, 3 * round + 1, epoch);
    searchListed(queue, CAROM_SEARCH_ALL, dirty_.get(), round, 3 * round + 2, epoch);
    lastRound_ = round;
}

void DevicePairwise::enqueueStep(cl_command_queue queue, const StepBuffers& buffers, const CaromStepParams& step) {
    buffers_ = buffers;
    step_ = step;
    enqueueZero(queue, counts_.get(), kCounts * sizeof(cl_uint), "list lengths");
    const unsigned int epoch = nextEpoch(queue);
    setKernelArgs(forwardKernel_.get(), buffers.state, buffers.slots, buffers.ids, buffers.cellOf, buffers.cells, step,
                  events_.get(), pending_[0].get(), pendingMarks_.get(), dirty_.get(), dirtyMarks_.get(), counts_.get(),
                  cl_uint{epoch});
    enqueue1d(queue, forwardKernel_.get(), particleCount_, groupSize_, "findEventsForward", profiler_);
    searchListed(queue, CAROM_SEARCH_ALL, dirty_.get(), 0, 2, epoch);
    lastRound_ = 0;
    for (unsigned int round = 1; round <= std::min(batch_, kMaxPairwiseRounds); ++round) enqueueRound(queue, round);
}

cl_uint DevicePairwise::nonFiniteIndex() { return kCounts; }

cl_uint DevicePairwise::lengthCount() { return kCounts; }

DevicePairwise::Lists DevicePairwise::lists() const {
    return {events_.get(),       pending_[0].get(),   pending_[1].get(), changed_.get(), dirty_.get(),
            pendingMarks_.get(), changedMarks_.get(), dirtyMarks_.get(), counts_.get()};
}

cl_uint DevicePairwise::reserveStepEpochs(cl_command_queue queue) {
    if (epoch_ > std::numeric_limits<unsigned int>::max() - (kMaxPairwiseRounds + 1)) {
        clearMarks(queue);
        epoch_ = 0;
    }
    const cl_uint first = epoch_ + 1;
    epoch_ += kMaxPairwiseRounds + 1;
    lastRound_ = kMaxPairwiseRounds;  // the kernel runs every round there is: complete() runs none
    return first;
}

const cl_uint* DevicePairwise::nonFiniteRecord() const { return hostCounts_.data() + kCounts; }

cl_uint DevicePairwise::finishCondition() const {
    return lastRound_ == kMaxPairwiseRounds ? kAlwaysZero : 3 * lastRound_;
}

void DevicePairwise::readLengths(cl_command_queue queue) {
    check(clEnqueueReadBuffer(queue, counts_.get(), CL_TRUE, 0, kCountsWithRecord * sizeof(cl_uint), hostCounts_.data(),
                              0, nullptr, eventSlot(profiler_, "read list lengths")),
          "clEnqueueReadBuffer(list lengths)");
}

DevicePairwise::Completion DevicePairwise::complete(cl_command_queue queue) {
    Completion completion;
    readLengths(queue);
    while (hostCounts_[3 * lastRound_] != 0 && lastRound_ < kMaxPairwiseRounds) {
        completion.finishSkipped = true;
        const unsigned int last = std::min(kMaxPairwiseRounds, lastRound_ + batch_);
        while (lastRound_ < last) enqueueRound(queue, lastRound_ + 1);
        readLengths(queue);
    }
    for (unsigned int r = 1; r <= lastRound_; ++r)
        if (hostCounts_[3 * r + 1] > 0) completion.rounds = r;
    // The next step likely needs about as many rounds: enqueue them in one batch.
    batch_ = std::max(2u, completion.rounds + 1);
    return completion;
}

}  // namespace carom::opencl
