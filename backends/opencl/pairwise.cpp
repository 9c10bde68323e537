#include "backends/opencl/pairwise.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "backends/backend.h"

namespace carom::opencl {

namespace {

// Work-items per compute unit for the list kernels: enough to hide memory
// latency on a GPU; a list longer than all of them is strided over.
constexpr std::size_t kListItemsPerComputeUnit = 2048;

// A round runs as launches when the step before's pending list for it held
// at least this many disks, and in resolveRoundsInGroup's one work-group
// otherwise. Measured on an H200 (bench/results/nvidia-h200-group-rounds.txt,
// resident pairwise ms a step, two runs each): at 256, 0.117 / 0.162 / 0.328
// / 2.65 ms at 10^4 / 10^5 / 10^6 / 1.6*10^7 disks; at 1 024, 0.115 / 0.163
// / 0.350 / 2.71; at 4 096, 0.37 ms at 10^5 (rounds of a few thousand disks
// are slow on one compute unit); before, every round in launches: 0.138 /
// 0.190 / 0.357 / 2.67.
constexpr cl_uint kLaunchedRoundLength = 256;
// resolveRoundsInGroup's work-group, at most.
constexpr std::size_t kRoundsGroupSize = 1024;

// The lengths: two per round, rounds 0 .. kMaxPairwiseRounds, then the
// finish kernel's record (kRecordWords), which is not cleared with the
// lengths and is read back with them; all within the lists' header.
constexpr std::size_t kCounts = CAROM_PENDING_LENGTH(kMaxPairwiseRounds + 1);
constexpr std::size_t kCountsWithRecord = kCounts + DevicePairwise::kRecordWords;
static_assert(kCountsWithRecord <= CAROM_LIST_HEADER_WORDS, "the lengths and the record must fit the lists' header");
// The lists' buffer after its header, in words per disk (CaromDeviceLists):
// the events (two), two pending lists, the changed list, then the marks.
constexpr std::size_t kListWordsPerDisk = 8;
constexpr std::size_t kMarksWord = 5;  // the first marks' words start at kMarksWord * count
constexpr std::size_t kChangedMarksWord = 6;
static_assert(kCountsWithRecord <= CAROM_LISTS_OVERFLOW, "the record must end before the neighbour lists' words");
// The neighbour lists' buffer (carom_list_origins): words per disk
// before the entries, and the room for entries a disk to begin with (a
// disk has 3-5 neighbours within the grid's skin at packings 0.6-0.9 among
// equal disks; mixed radii may need more, and the room then grows).
constexpr std::size_t kNeighbourWordsPerDisk = 4;
constexpr std::size_t kFirstListRoomPerDisk = 6;

}  // namespace

static_assert(sizeof(CaromEvent) == 8, "CaromEvent must match its OpenCL layout");

DevicePairwise::DevicePairwise(cl_context context, const DeviceInfo& device, cl_program program,
                               std::size_t particleCount, cl_command_queue queue, Profiler* profiler)
    : particleCount_(particleCount),
      room_(particleCount),
      computeUnits_(std::max<std::size_t>(1, device.computeUnits)),
      profiler_(profiler),
      hostCounts_(CAROM_LIST_HEADER_WORDS) {
    startKernel_ = createKernel(program, "startPairwiseStep");
    findKernel_ = createKernel(program, "findEvents");
    searchChangedKernel_ = createKernel(program, "searchChanged");
    resolveKernel_ = createKernel(program, "resolveEvents");
    roundsInGroupKernel_ = createKernel(program, "resolveRoundsInGroup");
    buildListsKernel_ = createKernel(program, "buildNeighbourLists");
    for (cl_kernel k : {startKernel_.get(), findKernel_.get(), searchChangedKernel_.get(), resolveKernel_.get(),
                        buildListsKernel_.get()})
        groupSize_ = std::min(groupSize_, kernelWorkGroupLimit(k, device.id));
    roundsGroupSize_ = std::min(kRoundsGroupSize, kernelWorkGroupLimit(roundsInGroupKernel_.get(), device.id));
    lists_ = createBuffer(context, (CAROM_LIST_HEADER_WORDS + kListWordsPerDisk * particleCount) * sizeof(cl_uint),
                          "pairwise lists");
    setParticleCount(queue, particleCount);
}

// The lists' layout follows the count (kernels/pairwise.h), so the header
// and the marks are cleared for it: a word of the layout before could read
// as a mark.
void DevicePairwise::setParticleCount(cl_command_queue queue, std::size_t particleCount) {
    particleCount_ = particleCount;
    listItems_ =
        std::min((particleCount + groupSize_ - 1) / groupSize_ * groupSize_, computeUnits_ * kListItemsPerComputeUnit);
    enqueueZero(queue, lists_.get(), CAROM_LIST_HEADER_WORDS * sizeof(cl_uint), "pairwise lists' header");
    clearMarks(queue);
}

void DevicePairwise::enableLists(cl_context context, float skin) {
    context_ = context;
    skin_ = skin;
    if (!makeListRoom(context, kFirstListRoomPerDisk * particleCount_)) skin_ = 0.0f;
}

bool DevicePairwise::makeListRoom(cl_context context, std::size_t entries) {
    neighbours_.reset();  // first: the lists may fill the device
    try {
        neighbours_ = createBuffer(context, (kNeighbourWordsPerDisk * particleCount_ + entries) * sizeof(cl_uint),
                                   "neighbour lists");
    } catch (const Error&) {  // more than the device's largest buffer
        return false;
    }
    listRoom_ = entries;
    return true;
}

void DevicePairwise::clearMarks(cl_command_queue queue) {
    const cl_uint zero = 0;
    check(clEnqueueFillBuffer(queue, lists_.get(), &zero, sizeof zero,
                              (CAROM_LIST_HEADER_WORDS + kMarksWord * particleCount_) * sizeof(cl_uint),
                              (kListWordsPerDisk - kMarksWord) * particleCount_ * sizeof(cl_uint), 0, nullptr, nullptr),
          "clEnqueueFillBuffer(pairwise marks)");
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

void DevicePairwise::enqueueRound(cl_command_queue queue, unsigned int round) {
    const StepBuffers& b = buffers_;
    const unsigned int epoch = nextEpoch(queue);
    setKernelArgs(resolveKernel_.get(), b.halt, b.state, b.slots, b.ids, step_, b.tallies, lists_.get(), cl_uint{round},
                  cl_uint{epoch});
    enqueue1d(queue, resolveKernel_.get(), listItems_, groupSize_, "resolveEvents", profiler_);
    setKernelArgs(searchChangedKernel_.get(), b.halt, b.state, b.slots, b.ids, b.cellOf, b.cells, step_, lists_.get(),
                  neighbours_.get(), cl_uint{round}, cl_uint{epoch});
    enqueue1d(queue, searchChangedKernel_.get(), listItems_, groupSize_, "searchChanged", profiler_);
}

void DevicePairwise::enqueueRoundsInGroup(cl_command_queue queue, unsigned int firstRound) {
    const StepBuffers& b = buffers_;
    const cl_uint firstEpoch = reserveEpochs(queue, kMaxPairwiseRounds - firstRound + 1);
    setKernelArgs(roundsInGroupKernel_.get(), b.halt, b.state, b.slots, b.ids, b.cellOf, b.cells, step_, b.tallies,
                  lists_.get(), neighbours_.get(), cl_uint{firstRound}, cl_uint{kMaxPairwiseRounds}, firstEpoch);
    enqueue1d(queue, roundsInGroupKernel_.get(), roundsGroupSize_, roundsGroupSize_, "resolveRoundsInGroup", profiler_);
}

void DevicePairwise::enqueueStart(cl_command_queue queue, cl_mem halt, const StartCheck& check,
                                  const CaromStepParams& step) {
    setKernelArgs(startKernel_.get(), halt, lists_.get(), cl_uint(kCounts), check.check, check.rule, check.substeps,
                  cl_uint(speedIndex() + check.speedParity), check.speedParity, nonFiniteIndex(), check.stepIndex,
                  skin_, step.duration, std::hypot(step.gravityX, step.gravityY));
    enqueue1d(queue, startKernel_.get(), kCounts, groupSize_, "startPairwiseStep", profiler_);
}

void DevicePairwise::clearRoundsRecord(cl_command_queue queue) {
    const cl_uint zero = 0;  // the fill copies its pattern when enqueued
    check(clEnqueueFillBuffer(queue, lists_.get(), &zero, sizeof zero, roundsIndex() * sizeof(cl_uint), sizeof zero, 0,
                              nullptr, nullptr),
          "clEnqueueFillBuffer(rounds record)");
}

void DevicePairwise::enqueueStep(cl_command_queue queue, const StepBuffers& buffers, const CaromStepParams& step) {
    buffers_ = buffers;
    step_ = step;
    const unsigned int epoch = nextEpoch(queue);
    substepEpoch_ = epoch;
    if (neighbours_.get())
        for (const cl_uint fill : {0u, 1u}) {  // the arguments are taken as each launch is enqueued
            setKernelArgs(buildListsKernel_.get(), buffers.halt, buffers.state, buffers.slots, buffers.cellOf,
                          buffers.cells, step, lists_.get(), neighbours_.get(), skin_, cl_uint(listRoom_), fill);
            enqueue1d(queue, buildListsKernel_.get(), particleCount_, groupSize_,
                      fill ? "buildNeighbourLists (fill)" : "buildNeighbourLists (count)", profiler_);
        }
    setKernelArgs(findKernel_.get(), buffers.halt, buffers.state, buffers.slots, buffers.ids, buffers.cellOf,
                  buffers.cells, step, lists_.get(), neighbours_.get(), cl_uint{epoch});
    enqueue1d(queue, findKernel_.get(), particleCount_, groupSize_, "findEvents", profiler_);
    for (unsigned int round = 1; round <= launchedRounds_; ++round) enqueueRound(queue, round);
    if (launchedRounds_ < kMaxPairwiseRounds) enqueueRoundsInGroup(queue, launchedRounds_ + 1);
}

cl_uint DevicePairwise::nonFiniteIndex() { return kCounts; }

cl_uint DevicePairwise::speedIndex() { return kCounts + kNonFiniteWords; }
cl_uint DevicePairwise::takenIndex() { return kCounts + kNonFiniteWords + kSpeedWords; }

cl_uint DevicePairwise::lengthCount() { return kCounts; }

cl_uint DevicePairwise::reserveEpochs(cl_command_queue queue, unsigned int count) {
    if (epoch_ > std::numeric_limits<unsigned int>::max() - count) {
        clearMarks(queue);
        epoch_ = 0;
    }
    const cl_uint first = epoch_ + 1;
    epoch_ += count;
    return first;
}

cl_uint DevicePairwise::reserveSubstepEpochs(cl_command_queue queue, unsigned int substeps) {
    const cl_uint first = reserveEpochs(queue, (kMaxPairwiseRounds + 1) * substeps);
    substepEpoch_ = first + (kMaxPairwiseRounds + 1) * (substeps - 1);
    return first;
}

cl_uint DevicePairwise::changedMarksWord() const {
    return cl_uint(CAROM_LIST_HEADER_WORDS + kChangedMarksWord * particleCount_);
}

void DevicePairwise::readLastRounds(cl_command_queue queue, cl_mem ids, std::vector<unsigned int>& rounds) const {
    const std::size_t n = particleCount_;
    std::vector<cl_uint> marks(n), idOf(n);
    check(clEnqueueReadBuffer(queue, lists_.get(), CL_TRUE, changedMarksWord() * sizeof(cl_uint), n * sizeof(cl_uint),
                              marks.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(changed marks)");
    check(clEnqueueReadBuffer(queue, ids, CL_TRUE, 0, n * sizeof(cl_uint), idOf.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(particle ids)");
    rounds.assign(n, 0u);
    for (std::size_t k = 0; k < n; ++k)
        if (marks[k] > substepEpoch_) rounds[idOf[k]] = marks[k] - substepEpoch_;
}

const cl_uint* DevicePairwise::nonFiniteRecord() const { return hostCounts_.data() + kCounts; }

float DevicePairwise::speedSquaredRecord(unsigned int parity) const {
    float largest;
    std::memcpy(&largest, &hostCounts_[speedIndex() + parity], sizeof(largest));
    return largest;
}

void DevicePairwise::readLengths(cl_command_queue queue) {
    check(clEnqueueReadBuffer(queue, lists_.get(), CL_TRUE, 0, hostCounts_.size() * sizeof(cl_uint), hostCounts_.data(),
                              0, nullptr, eventSlot(profiler_, "read list lengths")),
          "clEnqueueReadBuffer(list lengths)");
}

unsigned int DevicePairwise::complete(cl_command_queue queue) {
    readLengths(queue);
    // A build whose entries did not fit left its substep to the grid
    // (buildNeighbourLists): room for them, and a quarter more; where that
    // passes 32-bit offsets (a count that wrapped reads as no more than the
    // room) or the device's largest buffer, the grid serves from here on.
    if (neighbours_.get() && hostCounts_[CAROM_LISTS_OVERFLOW] != 0) {
        const std::size_t needed = hostCounts_[CAROM_LISTS_TOTAL];
        const std::size_t room = needed + needed / 4;
        if (needed <= listRoom_ || room > std::numeric_limits<cl_uint>::max() || !makeListRoom(context_, room)) {
            neighbours_.reset();
            listRoom_ = 0;
            skin_ = 0.0f;
        }
        // Handled: not to be read again before the next build sets it.
        const cl_uint zero = 0;
        check(clEnqueueFillBuffer(queue, lists_.get(), &zero, sizeof zero, CAROM_LISTS_OVERFLOW * sizeof(cl_uint),
                                  sizeof zero, 0, nullptr, nullptr),
              "clEnqueueFillBuffer(lists' overflow)");
    }
    unsigned int rounds = 0;
    for (unsigned int r = 1; r <= kMaxPairwiseRounds; ++r)
        if (hostCounts_[CAROM_CHANGED_LENGTH(r)] > 0) rounds = r;
    // The next step's lists are likely about as long as this one's.
    launchedRounds_ = 0;
    while (launchedRounds_ < kMaxPairwiseRounds &&
           hostCounts_[CAROM_PENDING_LENGTH(launchedRounds_)] >= kLaunchedRoundLength)
        ++launchedRounds_;
    return rounds;
}

}  // namespace carom::opencl
