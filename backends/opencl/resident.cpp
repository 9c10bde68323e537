#include "backends/opencl/resident.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "backends/opencl/program.h"

namespace carom {

using namespace opencl;

namespace {

// Work-groups of finishPairwiseAndCount per compute unit: enough to hide
// memory latency; each work-item strides over several particles, so few
// work-groups reduce the largest speed.
constexpr std::size_t kFinishGroupsPerComputeUnit = 16;

}  // namespace

OpenClResidentBackend::OpenClResidentBackend(const WorldDef& world, const std::string& device, bool profiling)
    : OpenClBackend(world, device, kernelSource(), profiling) {
    fusedKernel_ = createKernel(program_.get(), "resolveIntegrateAndCount");
    finishAndCountKernel_ = createKernel(program_.get(), "finishPairwiseAndCount");
    // finishPairwiseAndCount reduces in a work-group too.
    fitWorkGroups({fusedKernel_.get(), finishAndCountKernel_.get()}, {finishAndCountKernel_.get()});
    smallSystem_ = DeviceSmallSystem(device_, program_.get(), profiler_.get());
}

void OpenClResidentBackend::releaseState() {
    pairwise_ = DevicePairwise();
    deviceGrid_ = DeviceGrid();
    ids_.reset();
    sortedIds_.reset();
}

// Slot s holds particle s to begin with; the first step writes them in cell order.
void OpenClResidentBackend::loadState(std::vector<Particle> particles) {
    const std::size_t n = particles.size();
    ids_ = createBuffer(context_.get(), n * sizeof(cl_uint), "particle ids");
    sortedIds_ = createBuffer(context_.get(), n * sizeof(cl_uint), "particle ids in cell order");
    std::vector<cl_uint> ids(n);
    std::iota(ids.begin(), ids.end(), cl_uint{0});
    check(clEnqueueWriteBuffer(queue_.get(), ids_.get(), CL_TRUE, 0, n * sizeof(cl_uint), ids.data(), 0, nullptr,
                               nullptr),
          "clEnqueueWriteBuffer(particle ids)");
    deviceGrid_ = DeviceGrid(context_.get(), device_, program_.get(), grid_.geometry, n, profiler_.get());
    deviceGrid_.count(queue_.get(), state_.get());
    speedKnown_ = false;
    unconfirmed_ = false;
    inOneGroup_ = n <= kSmallSystemParticles;
    if (world_.collisions != CollisionScheme::Pairwise) return;
    pairwise_ = DevicePairwise(context_.get(), device_, program_.get(), n, queue_.get(), profiler_.get());
    // The finish's record: no disk non-finite, no speed yet (zero).
    cl_uint record[DevicePairwise::kRecordWords] = {};
    std::copy_n(kNoneNonFinite, DevicePairwise::kNonFiniteWords, record);
    check(clEnqueueWriteBuffer(queue_.get(), pairwise_.lengths(), CL_TRUE,
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
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get());
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

// The rounds resolve the events in state_ (in the cell order of the step
// before), then every disk finishes the step into slot k of next_, in this
// step's cell order, counted into the next grid, as stepSimultaneous does.
// The host does not wait: confirmStep, before anything reads the result,
// does (one wait per step, which also reads the largest speed for the next one).
void OpenClResidentBackend::stepPairwise(float dt) {
    confirmStep();
    if (nonFinite()) return;
    const CaromStepParams step = stepParams(dt);
    speedParity_ = 1 - speedParity_;
    const cl_uint stepIndex = nextStepIndex();
    if (inOneGroup_) {
        smallSystem_.enqueuePairwiseStep(queue_.get(), smallStepBuffers(), deviceGrid_, pairwise_, step,
                                         cl_uint{speedParity_}, stepIndex);
    } else {
        deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get());
        pairwise_.enqueueStep(queue_.get(),
                              {state_.get(), deviceGrid_.cellOrder(), sortedIds_.get(), deviceGrid_.cellOf(),
                               deviceGrid_.cells(), tallies_.get()},
                              step);
        enqueuePairwiseFinish(step, stepIndex);
    }
    check(clFlush(queue_.get()), "clFlush");
    unconfirmed_ = true;
}

// The kernel records a disk left non-finite and the largest speed after the
// pairwise lengths, which confirmStep reads anyway.
void OpenClResidentBackend::enqueuePairwiseFinish(const CaromStepParams& step, cl_uint stepIndex) {
    setKernelArgs(finishAndCountKernel_.get(), state_.get(), deviceGrid_.cellOrder(), sortedIds_.get(), step,
                  next_.get(), tallies_.get(), deviceGrid_.nextCounts(), deviceGrid_.cellOf(), deviceGrid_.rankInCell(),
                  pairwise_.lengths(), DevicePairwise::speedIndex(), cl_uint{speedParity_}, stepIndex,
                  DevicePairwise::nonFiniteIndex());
    setLocalArg(finishAndCountKernel_.get(), 14, reductionGroupSize_ * sizeof(cl_float));
    enqueue1d(queue_.get(), finishAndCountKernel_.get(), finishItems_, reductionGroupSize_, "finishPairwiseAndCount",
              profiler_.get());
}

void OpenClResidentBackend::confirmStep() {
    if (!unconfirmed_) return;
    unconfirmed_ = false;
    const unsigned int rounds = pairwise_.complete(queue_.get());
    std::copy_n(pairwise_.nonFiniteRecord(), DevicePairwise::kNonFiniteWords, firstNonFiniteRead_);
    checkNonFinite();
    recordRounds(rounds);
    speedKnown_ = true;
    std::swap(state_, next_);
    std::swap(ids_, sortedIds_);
    deviceGrid_.advance();
}

// Slot s holds particle ids[s].
void OpenClResidentBackend::readParticles(std::vector<Particle>& particles) {
    confirmStep();
    particles.resize(particleCount_);
    std::vector<Particle> slots(particleCount_);
    std::vector<cl_uint> ids(particleCount_);
    check(clEnqueueReadBuffer(queue_.get(), state_.get(), CL_TRUE, 0, particleCount_ * sizeof(Particle), slots.data(),
                              0, nullptr, nullptr),
          "clEnqueueReadBuffer(particle state)");
    check(clEnqueueReadBuffer(queue_.get(), ids_.get(), CL_TRUE, 0, particleCount_ * sizeof(cl_uint), ids.data(), 0,
                              nullptr, nullptr),
          "clEnqueueReadBuffer(particle ids)");
    for (std::size_t s = 0; s < particleCount_; ++s) particles[ids[s]] = slots[s];
}

// A pairwise step takes the largest speed as it finishes; otherwise the reduction.
float OpenClResidentBackend::maxSpeedSquared() {
    confirmStep();
    if (!speedKnown_) return OpenClBackend::maxSpeedSquared();
    return pairwise_.speedSquaredRecord(speedParity_);
}

Grid OpenClResidentBackend::readDeviceGrid() {
    confirmStep();
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get());
    return deviceGrid_.read(queue_.get(), sortedIds_.get());
}

}  // namespace carom
