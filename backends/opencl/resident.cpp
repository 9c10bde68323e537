#include "backends/opencl/resident.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>

#include "backends/opencl/program.h"
#include "engine/neighbour_lists.h"

namespace carom {

using namespace opencl;

namespace {

// Work-groups of finishPairwiseAndCount per compute unit: enough to hide
// memory latency; each work-item strides over several particles, so few
// work-groups reduce the largest speed.
constexpr std::size_t kFinishGroupsPerComputeUnit = 16;
// A chunk of pairwise steps lasts about this long: far longer than the
// wait that ends it (tens of microseconds), and short enough that a stop
// request between chunks is not kept waiting. The chunk's length follows
// its last duration; it changes no result.
constexpr auto kChunkSeconds = 0.01;
// Pairwise steps without neighbour lists (searchesLists) of up to this many
// disks gather the state into the step's sorted order: their searches then
// load no slots, which made a step 5-13 % faster at 10^4-10^5 disks on an
// H100; from 10^6 the gather's copy (64 bytes a disk) costs more than that
// saves (4-6 % slower; bench/results/nvidia-h100-gather.txt).
constexpr std::size_t kGatherUpTo = std::size_t{1} << 18;

// Whether pairwise steps of `count` disks gather the state (kGatherUpTo);
// CAROM_PAIRWISE_GATHER=on or off overrides the choice (the tests run both).
bool gathers(std::size_t count) { return forcedChoice("CAROM_PAIRWISE_GATHER", "on", "off", count <= kGatherUpTo); }

// Whether pairwise steps search neighbour lists: yes, unless
// CAROM_PAIRWISE_LISTS=off (the tests run both). On an H100 they made a
// step 17-18 % faster at 10^4-10^5 disks, 10 % at 10^6 and 4 % at 1.6*10^7
// (bench/results/nvidia-h100-lists.txt). The lists keep the state where it
// is between their builds, so with them it is not gathered.
bool searchesLists() { return forcedChoice("CAROM_PAIRWISE_LISTS", "on", "off", true); }

}  // namespace

OpenClResidentBackend::OpenClResidentBackend(const WorldDef& world, const std::string& device, bool profiling)
    : OpenClBackend(world, device, kernelSource(), profiling) {
    fusedKernel_ = createKernel(program_.get(), "resolveIntegrateAndCount");
    finishAndCountKernel_ = createKernel(program_.get(), "finishPairwiseAndCount");
    numberSlotsKernel_ = createKernel(program_.get(), "numberSlots");
    // finishPairwiseAndCount reduces in a work-group too.
    fitWorkGroups({fusedKernel_.get(), finishAndCountKernel_.get(), numberSlotsKernel_.get()},
                  {finishAndCountKernel_.get()});
    smallSystem_ = DeviceSmallSystem(device_, program_.get(), profiler_.get());
}

void OpenClResidentBackend::releaseState() {
    pairwise_ = DevicePairwise();
    deviceGrid_ = DeviceGrid();
    ids_.reset();
    sortedIds_.reset();
}

void OpenClResidentBackend::loadState(const std::vector<Particle>& particles) { startState(particles.size()); }

// Slot s holds particle s to begin with; the first step writes them in cell order.
void OpenClResidentBackend::startState(std::size_t n) {
    inOneGroup_ = n <= kSmallSystemParticles;
    const bool pairwise = world_.collisions == CollisionScheme::Pairwise;
    // The lists take the skin the CPU engine's would, and are built from the
    // device's grid, whose cells are widened for it: the substeps stay sized
    // by the pairwise grid's allowance (gridTravel()), so the results are the
    // same; only the searches' candidates and the cells change.
    const float skin = NeighbourLists::skinFor(world_.skin, maxRadius_, gridTravel());
    bool listed = pairwise && !inOneGroup_ && std::isfinite(skin) && listsAllowed_ && searchesLists();
    if (listed) {
        const std::optional<GridGeometry> wide = NeighbourLists::gridFor(caromBoxOf(world_), maxRadius_, n, skin);
        listed = wide.has_value();
        if (listed) grid_.geometry = *wide;
    }
    gathered_ = !listed && gathers(n);
    // The buffers of a state before are still here where createState kept
    // its own (releaseState frees them otherwise); new ones hold stateRoom().
    const std::size_t room = stateRoom();
    if (!ids_.get()) {
        ids_ = createBuffer(context_.get(), room * sizeof(cl_uint), "particle ids");
        sortedIds_ = createBuffer(context_.get(), room * sizeof(cl_uint), "particle ids in cell order");
    }
    setKernelArgs(numberSlotsKernel_.get(), ids_.get(), cl_uint(n));
    enqueue1d(queue_.get(), numberSlotsKernel_.get(), n, workGroupSize_, "numberSlots", profiler_.get());
    if (!deviceGrid_.holds(grid_.geometry, n))
        deviceGrid_ = DeviceGrid(context_.get(), device_, program_.get(), grid_.geometry, room, profiler_.get());
    deviceGrid_.setParticleCount(n);
    deviceGrid_.count(queue_.get(), state_.get());
    buildGridEachStep();  // whatever the lists of a state before chose
    speedKnown_ = false;
    if (!pairwise) return;
    const bool fresh = listed || pairwise_.room() < n;
    if (fresh) pairwise_ = DevicePairwise(context_.get(), device_, program_.get(), room, queue_.get(), profiler_.get());
    if (!fresh || room != n) pairwise_.setParticleCount(queue_.get(), n);
    if (listed) pairwise_.enableLists(context_.get(), skin);
    // The finish's record: no disk non-finite, no speed yet (zero).
    cl_uint record[DevicePairwise::kRecordWords] = {};
    std::copy_n(kNoneNonFinite, DevicePairwise::kNonFiniteWords, record);
    check(clEnqueueWriteBuffer(queue_.get(), pairwise_.lists(), CL_TRUE,
                               DevicePairwise::nonFiniteIndex() * sizeof(cl_uint), sizeof(record), record, 0, nullptr,
                               nullptr),
          "clEnqueueWriteBuffer(the finish's record)");
    finishItems_ = std::min((n + reductionGroupSize_ - 1) / reductionGroupSize_,
                            std::max<std::size_t>(1, device_.computeUnits) * kFinishGroupsPerComputeUnit) *
                   reductionGroupSize_;
}

void OpenClResidentBackend::enqueueStep(float dt) { enqueueSteps(1, dt); }

std::uint64_t OpenClResidentBackend::enqueueSteps(std::uint64_t steps, float dt) {
    if (inOneGroup_ && world_.collisions == CollisionScheme::Simultaneous) return stepSmallSystem(steps, dt);
    world_.collisions == CollisionScheme::Pairwise ? stepPairwise(dt) : stepSimultaneous(dt);
    return 1;
}

std::uint64_t OpenClResidentBackend::stepSmallSystem(std::uint64_t steps, float dt) {
    steps = std::min(steps, kSmallSystemSteps);
    const cl_uint firstStepIndex = nextStepIndex();
    for (std::uint64_t s = 1; s < steps; ++s) nextStepIndex();
    smallSystem_.enqueueSteps(queue_.get(), smallStepBuffers(), deviceGrid_, stepParams(dt), cl_uint(steps),
                              firstStepIndex, firstNonFinite_.get());
    if (steps % 2 == 1) {
        std::swap(state_, next_);
        std::swap(ids_, sortedIds_);
    }
    return steps;
}

void OpenClResidentBackend::stepSimultaneous(float dt) {
    const CaromStepParams step = stepParams(dt);
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get(), halt_.get());
    // next_ receives the new state in this step's cell order: slot k holds particle sortedIds_[k].
    setKernelArgs(fusedKernel_.get(), state_.get(), deviceGrid_.cellOrder(), sortedIds_.get(), deviceGrid_.cells(),
                  step, next_.get(), tallies_.get(), deviceGrid_.nextCounts(), deviceGrid_.cellOf(),
                  deviceGrid_.rankInCell(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue_.get(), fusedKernel_.get(), step.count, workGroupSize_, "resolveIntegrateAndCount",
              profiler_.get());
    std::swap(state_, next_);
    std::swap(ids_, sortedIds_);
    deviceGrid_.advance();
}

// A pairwise (sub)step alone: a chunk of one, without checks.
void OpenClResidentBackend::stepPairwise(float dt) {
    if (nonFinite()) return;
    stepPairwiseChunk(1, 1, dt, CaromSubstepRule{});
}

std::uint64_t OpenClResidentBackend::advanceWhileSubstepsHold(std::uint64_t steps, std::uint64_t substeps, float dt,
                                                              const CaromSubstepRule& rule) {
    if (world_.collisions != CollisionScheme::Pairwise)
        return Backend::advanceWhileSubstepsHold(steps, substeps, dt, rule);
    steps = std::clamp<std::uint64_t>(chunkSubsteps_ / substeps, 1, steps);
    const auto start = std::chrono::steady_clock::now();
    // A chunk cut short in a step leaves a disk non-finite, which step() reports.
    const std::uint64_t taken = stepPairwiseChunk(steps * substeps, substeps, dt, rule) / substeps;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (seconds < kChunkSeconds / 2 && taken == steps)
        chunkSubsteps_ = std::min(2 * chunkSubsteps_, kSmallPairwiseSubsteps);
    else if (seconds > 2 * kChunkSeconds)
        chunkSubsteps_ = std::max<std::uint64_t>(chunkSubsteps_ / 2, 1);
    return taken;
}

// Every substep is enqueued at once, and the host waits once, at the end:
// the device checks each substep's start (startPairwiseStep, or within
// stepSmallPairwise) and stops the chunk where the plan no longer holds.
std::uint64_t OpenClResidentBackend::stepPairwiseChunk(std::uint64_t substeps, std::uint64_t substepsPerStep, float dt,
                                                       const CaromSubstepRule& rule) {
    const CaromStepParams step = stepParams(dt);
    const cl_uint firstStepIndex = reserveStepIndices(substeps);
    std::uint64_t taken = substeps;
    if (inOneGroup_) {
        smallSystem_.enqueuePairwiseSteps(queue_.get(), smallStepBuffers(), deviceGrid_, pairwise_, step, rule,
                                          cl_uint(substeps), cl_uint(substepsPerStep), cl_uint{speedParity_},
                                          firstStepIndex);
        pairwise_.complete(queue_.get());
        taken = pairwise_.substepsTakenRecord();
        if (taken % 2 == 1) swapStepBuffers();
    } else {
        pairwise_.clearRoundsRecord(queue_.get());
        for (std::uint64_t s = 0; s < substeps; ++s) {
            DevicePairwise::StartCheck check;
            check.check = s == 0                     ? DevicePairwise::kNoCheck
                          : s % substepsPerStep == 0 ? DevicePairwise::kCheckSubsteps
                                                     : DevicePairwise::kCheckFinite;
            check.rule = rule;
            check.substeps = cl_uint(substepsPerStep);
            check.speedParity = speedParity_;
            check.stepIndex = firstStepIndex + cl_uint(s);
            enqueuePairwiseSubstep(step, check);
        }
        cl_uint halt = CAROM_RUNNING;
        check(clEnqueueReadBuffer(queue_.get(), halt_.get(), CL_FALSE, 0, sizeof(halt), &halt, 0, nullptr, nullptr),
              "clEnqueueReadBuffer(halt)");
        pairwise_.complete(queue_.get());  // waits, and reads the record
        if (halt != CAROM_RUNNING) {
            taken = halt - firstStepIndex;
            resumeAfterHalt();
            if ((substeps - taken) % 2 == 1) {  // undo the skipped substeps' swaps
                swapStepBuffers();
                speedParity_ = 1 - speedParity_;
            }
        }
    }
    returnStepIndices(substeps - taken);
    std::copy_n(pairwise_.nonFiniteRecord(), DevicePairwise::kNonFiniteWords, firstNonFiniteRead_);
    checkNonFinite();
    recordRounds(pairwise_.mostRoundsRecord());
    speedKnown_ = true;
    return taken;
}

// The start (and its check), the grid, the rounds, and the finish into
// next_ in this substep's cell order, counted into the next grid; the
// buffers swap roles as if it ran (stepPairwiseChunk undoes that for the
// substeps a halt skipped). Gathered, the grid's sort copies the state into
// next_ in its order, where the searches find disk k at k (no slots) and the
// finish runs in place.
void OpenClResidentBackend::enqueuePairwiseSubstep(const CaromStepParams& step,
                                                   const DevicePairwise::StartCheck& check) {
    pairwise_.enqueueStart(queue_.get(), halt_.get(), check, step);
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get(), halt_.get(),
                      gathered_ ? DeviceGrid::Gather{state_.get(), next_.get()} : DeviceGrid::Gather{});
    const cl_mem stepState = gathered_ ? next_.get() : state_.get();
    const cl_mem slots = gathered_ ? nullptr : deviceGrid_.cellOrder();
    pairwise_.enqueueStep(
        queue_.get(),
        {stepState, slots, sortedIds_.get(), deviceGrid_.cellOf(), deviceGrid_.cells(), tallies_.get(), halt_.get()},
        step);
    speedParity_ = 1 - speedParity_;
    setKernelArgs(finishAndCountKernel_.get(), halt_.get(), stepState, slots, sortedIds_.get(), step, next_.get(),
                  tallies_.get(), deviceGrid_.nextCounts(), deviceGrid_.cellOf(), deviceGrid_.rankInCell(),
                  pairwise_.lists(), DevicePairwise::speedIndex(), cl_uint{speedParity_}, check.stepIndex,
                  DevicePairwise::nonFiniteIndex(), DevicePairwise::roundsIndex(), pairwise_.neighbours());
    setLocalArg(finishAndCountKernel_.get(), 17, reductionGroupSize_ * sizeof(cl_float));
    enqueue1d(queue_.get(), finishAndCountKernel_.get(), finishItems_, reductionGroupSize_, "finishPairwiseAndCount",
              profiler_.get());
    swapStepBuffers();
}

void OpenClResidentBackend::resumeAfterHalt() {
    check(clEnqueueFillBuffer(queue_.get(), halt_.get(), &kRunning, sizeof kRunning, 0, sizeof kRunning, 0, nullptr,
                              nullptr),
          "clEnqueueFillBuffer(halt)");
    deviceGrid_.resetScan(queue_.get());
}

void OpenClResidentBackend::swapStepBuffers() {
    std::swap(state_, next_);
    std::swap(ids_, sortedIds_);
    deviceGrid_.advance();
}

unsigned int OpenClResidentBackend::stepDeviceShare(cl_mem particles, cl_mem tallies, std::size_t count,
                                                    const Backend& whole, float dt) {
    return stepLoadedShare(count, whole, dt, [&] {
        createState(count, true);
        enqueueCopy(queue_.get(), particles, state_.get(), count * sizeof(Particle), "a share's disks");
        enqueueCopy(queue_.get(), tallies, tallies_.get(), count * sizeof(ContactTally), "a share's tallies");
        startState(count);
    });
}

OpenClResidentBackend::SteppedShare OpenClResidentBackend::steppedShare() const {
    SteppedShare stepped{state_.get(), ids_.get(), tallies_.get(), nullptr, 0, 0};
    if (world_.collisions == CollisionScheme::Pairwise) {
        stepped.lists = pairwise_.lists();
        stepped.marksWord = pairwise_.changedMarksWord();
        stepped.epoch = pairwise_.substepEpoch();
    }
    return stepped;
}

// After a substep, ids_ names the disk at each of its sorted positions (swapStepBuffers).
void OpenClResidentBackend::readLastRounds(std::vector<unsigned int>& rounds) {
    if (world_.collisions == CollisionScheme::Pairwise)
        pairwise_.readLastRounds(queue_.get(), ids_.get(), rounds);
    else
        rounds.assign(particleCount_, 0u);
}

// A pairwise step takes the largest speed as it finishes; otherwise the reduction.
float OpenClResidentBackend::maxSpeedSquared() {
    if (!speedKnown_) return OpenClBackend::maxSpeedSquared();
    return pairwise_.speedSquaredRecord(speedParity_);
}

void OpenClResidentBackend::buildGridEachStep() {
    const cl_uint build = 0;
    check(clEnqueueWriteBuffer(queue_.get(), halt_.get(), CL_TRUE, sizeof(cl_uint), sizeof build, &build, 0, nullptr,
                               nullptr),
          "clEnqueueWriteBuffer(halt)");
}

Grid OpenClResidentBackend::readDeviceGrid() {
    buildGridEachStep();  // whatever the last pairwise substep chose
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get(), halt_.get());
    return deviceGrid_.read(queue_.get(), sortedIds_.get());
}

}  // namespace carom
