#include "backends/opencl_backend.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <utility>

namespace carom {

using namespace opencl;

namespace {

// Steps enqueued between waits for the device: bounds the commands in flight
// on a long run, while one wait per batch costs the GPU almost no idle time.
constexpr std::uint64_t kStepsPerSync = 64;

// Work-groups of the max-speed reduction: enough to fill a GPU, few enough
// for the host to finish the reduction at once.
constexpr std::size_t kReductionGroups = 256;

// firstNonFinite_ before any disk went non-finite (kernels/physics.h, carom_record_non_finite).
constexpr cl_uint kNoneNonFinite[2] = {0xffffffffu, 0xffffffffu};

// Work-groups of finishPairwiseAndCount per compute unit: enough to hide
// memory latency; each work-item strides over several particles, so few
// work-groups reduce the largest speed.
constexpr std::size_t kFinishGroupsPerComputeUnit = 16;

}  // namespace

Pipeline parsePipeline(const std::string& name) {
    if (name == "seed") return Pipeline::Seed;
    if (name == "resident") return Pipeline::Resident;
    throw Error("unknown pipeline '" + name + "'; allowed: seed, resident");
}

OpenClBackend::OpenClBackend(const WorldDef& world, const std::string& device, Pipeline pipeline, bool profiling)
    : Backend(world),
      pipeline_(pipeline),
      profiler_(profiling ? std::make_unique<Profiler>() : nullptr),
      device_(selectDevice(device)) {
    cl_int status = CL_SUCCESS;
    context_ = Context(clCreateContext(nullptr, 1, &device_.id, nullptr, nullptr, &status));
    check(status, "clCreateContext");
    queue_ = Queue(clCreateCommandQueue(context_.get(), device_.id, profiling ? CL_QUEUE_PROFILING_ENABLE : 0,
                                        &status));
    check(status, "clCreateCommandQueue");
    program_ = buildProgram(context_.get(), device_, device_.correctlyRoundedDivideSqrt);
    resolveKernel_ = createKernel(program_.get(), "resolveCollisions");
    integrateKernel_ = createKernel(program_.get(), "integrate");
    fusedKernel_ = createKernel(program_.get(), "resolveIntegrateAndCount");
    allPairsKernel_ = createKernel(program_.get(), "resolveAllPairs");
    maxSpeedKernel_ = createKernel(program_.get(), "maxSpeedSquared");
    finishByIdKernel_ = createKernel(program_.get(), "finishStepById");
    finishAndCountKernel_ = createKernel(program_.get(), "finishPairwiseAndCount");
    for (cl_kernel kernel : {resolveKernel_.get(), integrateKernel_.get(), fusedKernel_.get(), allPairsKernel_.get(),
                             finishByIdKernel_.get(), finishAndCountKernel_.get()})
        workGroupSize_ = std::min(workGroupSize_, kernelWorkGroupLimit(kernel, device_.id));
    // The two kernels that reduce in a work-group: maxSpeedSquared and finishPairwiseAndCount.
    const std::size_t reductionLimit =
        std::min({std::size_t{256}, kernelWorkGroupLimit(maxSpeedKernel_.get(), device_.id),
                  kernelWorkGroupLimit(finishAndCountKernel_.get(), device_.id)});
    while (reductionGroupSize_ * 2 <= reductionLimit) reductionGroupSize_ *= 2;
    while (reductionGroupSize_ > reductionLimit) reductionGroupSize_ /= 2;
    groupMax_ = createBuffer(context_.get(), kReductionGroups * sizeof(cl_float), "max speed per group");
    speedBits_ = createBuffer(context_.get(), 2 * sizeof(cl_uint), "largest speed squared");
    firstNonFinite_ = createBuffer(context_.get(), sizeof(kNoneNonFinite), "first non-finite step and particle");
}

std::string OpenClBackend::device() const {
    static const char* const pipelines[] = {"seed", "resident", "all-pairs"};
    return device_.name + " (" + device_.platformName + ", " + device_.version + "), " +
           pipelines[static_cast<int>(pipeline_)] + " pipeline";
}

void OpenClBackend::load(std::vector<Particle> particles) {
    const std::size_t n = particles.size();
    // Free the previous state's buffers first: a state may fill the device.
    hostState_.clear();
    state_.reset();
    next_.reset();
    tallies_.reset();
    sortedIndices_.reset();
    cells_.reset();
    cellOf_.reset();
    pairwise_ = DevicePairwise();
    deviceGrid_ = DeviceGrid();
    ids_.reset();
    sortedIds_.reset();

    state_ = createBuffer(context_.get(), n * sizeof(Particle), "particle state");
    next_ = createBuffer(context_.get(), n * sizeof(Particle), "next particle state");
    tallies_ = createBuffer(context_.get(), n * sizeof(ContactTally), "contact tallies");
    check(clEnqueueWriteBuffer(queue_.get(), state_.get(), CL_TRUE, 0, n * sizeof(Particle), particles.data(), 0,
                               nullptr, nullptr),
          "clEnqueueWriteBuffer(particle state)");
    enqueueZero(queue_.get(), tallies_.get(), n * sizeof(ContactTally), "contact tallies");
    check(clEnqueueWriteBuffer(queue_.get(), firstNonFinite_.get(), CL_TRUE, 0, sizeof(kNoneNonFinite),
                               kNoneNonFinite, 0, nullptr, nullptr),
          "clEnqueueWriteBuffer(first non-finite step and particle)");
    substep_ = nonFiniteBase_ = 0;
    switch (pipeline_) {
        case Pipeline::Seed:
            hostState_ = std::move(particles);
            sortedIndices_ = createBuffer(context_.get(), n * sizeof(cl_uint), "sorted indices");
            cells_ = createBuffer(context_.get(),
                                  std::size_t(grid_.geometry.cols) * grid_.geometry.rows * sizeof(GridCell),
                                  "grid cells");
            if (world_.collisions == CollisionScheme::Pairwise)
                cellOf_ = createBuffer(context_.get(), n * sizeof(cl_uint), "cell of each particle");
            break;
        case Pipeline::Resident:
            loadResident(n);
            break;
        case Pipeline::AllPairs:
            break;
    }
    if (world_.collisions == CollisionScheme::Pairwise) {
        if (pipeline_ == Pipeline::AllPairs) throw Error("the all-pairs pipeline runs the simultaneous scheme only");
        pairwise_ = DevicePairwise(context_.get(), device_, program_.get(), n, queue_.get(), profiler_.get());
        check(clEnqueueWriteBuffer(queue_.get(), pairwise_.lengths(), CL_TRUE,
                                   DevicePairwise::nonFiniteIndex() * sizeof(cl_uint), sizeof(kNoneNonFinite),
                                   kNoneNonFinite, 0, nullptr, nullptr),
              "clEnqueueWriteBuffer(first non-finite step and particle)");
        enqueueZero(queue_.get(), speedBits_.get(), 2 * sizeof(cl_uint), "largest speed squared");
        finishItems_ = std::min((n + reductionGroupSize_ - 1) / reductionGroupSize_,
                                std::max<std::size_t>(1, device_.computeUnits) * kFinishGroupsPerComputeUnit) *
                       reductionGroupSize_;
    }
    speedKnown_ = false;
    unconfirmed_ = false;
    finish();
    if (profiler_) profiler_->clear();  // the profile covers steps only
}

// Slot s holds particle s to begin with; the first step writes them in cell order.
void OpenClBackend::loadResident(std::size_t n) {
    ids_ = createBuffer(context_.get(), n * sizeof(cl_uint), "particle ids");
    sortedIds_ = createBuffer(context_.get(), n * sizeof(cl_uint), "particle ids in cell order");
    std::vector<cl_uint> ids(n);
    std::iota(ids.begin(), ids.end(), cl_uint{0});
    check(clEnqueueWriteBuffer(queue_.get(), ids_.get(), CL_TRUE, 0, n * sizeof(cl_uint), ids.data(), 0, nullptr,
                               nullptr),
          "clEnqueueWriteBuffer(particle ids)");
    deviceGrid_ = DeviceGrid(context_.get(), device_, program_.get(), grid_.geometry, n, profiler_.get());
    deviceGrid_.count(queue_.get(), state_.get());
}

void OpenClBackend::finish() {
    enqueueNonFiniteRead();
    check(clFinish(queue_.get()), "clFinish");
    if (profiler_) profiler_->collect();
    checkNonFinite();
}

void OpenClBackend::enqueueNonFiniteRead() {
    check(clEnqueueReadBuffer(queue_.get(), firstNonFinite_.get(), CL_FALSE, 0, sizeof(firstNonFiniteRead_),
                              firstNonFiniteRead_, 0, nullptr, nullptr),
          "clEnqueueReadBuffer(first non-finite step and particle)");
}

void OpenClBackend::checkNonFinite() {
    if (firstNonFiniteRead_[0] == kNoneNonFinite[0])
        nonFiniteBase_ = substep_;
    else
        recordNonFinite(nonFiniteBase_ + firstNonFiniteRead_[0], firstNonFiniteRead_[1]);
}

// Stops at the first wait that finds a disk non-finite: after every step in
// the seed and resident pairwise pipelines, every kStepsPerSync steps in the
// resident one (whose steps until then stay as cheap, carom_count_into_cell).
void OpenClBackend::advance(std::uint64_t steps, float dt) {
    const bool pairwise = world_.collisions == CollisionScheme::Pairwise;
    // A resident pairwise step ends in a wait of its own (confirmStep).
    const bool waitsEachStep = pipeline_ == Pipeline::Resident && pairwise;
    for (std::uint64_t s = 0; s < steps && !nonFinite(); ++s) {
        switch (pipeline_) {
            case Pipeline::Seed:
                pairwise ? stepSeedPairwise(dt) : stepSeed(dt);
                break;
            case Pipeline::Resident:
                pairwise ? stepResidentPairwise(dt) : stepResident(dt);
                break;
            case Pipeline::AllPairs:
                stepAllPairs(dt);
                break;
        }
        if (!waitsEachStep && (s + 1) % kStepsPerSync == 0) finish();
    }
    if (!waitsEachStep) finish();
}

void OpenClBackend::awaitSteps() {
    confirmStep();
    finish();
}

void OpenClBackend::uploadGrid() {
    Profiler* profiler = profiler_.get();
    const auto gridStart = std::chrono::steady_clock::now();
    buildGrid(hostState_.data(), hostState_.size(), grid_);
    if (profiler)
        profiler->addHostSeconds("buildGrid (host)", std::chrono::duration<double>(
                                                         std::chrono::steady_clock::now() - gridStart)
                                                         .count());
    // Non-blocking writes: the host vectors stay untouched until the
    // blocking read at the end of the step, which the in-order queue runs last.
    cl_command_queue queue = queue_.get();
    check(clEnqueueWriteBuffer(queue, sortedIndices_.get(), CL_FALSE, 0, particleCount_ * sizeof(cl_uint),
                               grid_.sortedIndices.data(), 0, nullptr, eventSlot(profiler, "upload grid")),
          "clEnqueueWriteBuffer(sorted indices)");
    check(clEnqueueWriteBuffer(queue, cells_.get(), CL_FALSE, 0, grid_.cells.size() * sizeof(GridCell),
                               grid_.cells.data(), 0, nullptr, eventSlot(profiler, "upload grid")),
          "clEnqueueWriteBuffer(grid cells)");
    if (cellOf_.get())
        check(clEnqueueWriteBuffer(queue, cellOf_.get(), CL_FALSE, 0, particleCount_ * sizeof(cl_uint),
                                   grid_.cellOf.data(), 0, nullptr, eventSlot(profiler, "upload grid")),
              "clEnqueueWriteBuffer(cell of each particle)");
}

void OpenClBackend::stepSeed(float dt) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    const GridGeometry& g = grid_.geometry;
    cl_command_queue queue = queue_.get();
    Profiler* profiler = profiler_.get();
    uploadGrid();
    setKernelArgs(resolveKernel_.get(), state_.get(), sortedIndices_.get(), cells_.get(), g.cellsPerLengthX,
                  g.cellsPerLengthY, g.cols, g.rows, count, world_.width, world_.height, periodic(), next_.get(),
                  tallies_.get());
    enqueue1d(queue, resolveKernel_.get(), count, workGroupSize_, "resolveCollisions", profiler);
    setKernelArgs(integrateKernel_.get(), next_.get(), count, dt, world_.gravity.x, world_.gravity.y, world_.width,
                  world_.height, periodic(), tallies_.get(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue, integrateKernel_.get(), count, workGroupSize_, "integrate", profiler);
    enqueueNonFiniteRead();
    check(clEnqueueReadBuffer(queue, next_.get(), CL_TRUE, 0, count * sizeof(Particle), hostState_.data(), 0,
                              nullptr, eventSlot(profiler, "download state")),
          "clEnqueueReadBuffer(particle state)");
    checkNonFinite();
    std::swap(state_, next_);
}

// The rounds resolve the events in state_ (stored by id, so sortedIndices
// serves as slots and ids), then every disk finishes the step in place.
void OpenClBackend::stepSeedPairwise(float dt) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    cl_command_queue queue = queue_.get();
    const CaromPairwiseStep step = pairwiseStep(dt);
    uploadGrid();
    pairwise_.enqueueStep(queue, {state_.get(), sortedIndices_.get(), sortedIndices_.get(), cellOf_.get(),
                                  cells_.get(), tallies_.get()},
                          step);
    recordRounds(pairwise_.complete(queue).rounds);
    setKernelArgs(finishByIdKernel_.get(), state_.get(), step, count, tallies_.get(), nextStepIndex(),
                  firstNonFinite_.get());
    enqueue1d(queue, finishByIdKernel_.get(), count, workGroupSize_, "finishStepById", profiler_.get());
    enqueueNonFiniteRead();
    check(clEnqueueReadBuffer(queue, state_.get(), CL_TRUE, 0, count * sizeof(Particle), hostState_.data(), 0,
                              nullptr, eventSlot(profiler_.get(), "download state")),
          "clEnqueueReadBuffer(particle state)");
    checkNonFinite();
}

void OpenClBackend::stepResident(float dt) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    const GridGeometry& g = grid_.geometry;
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get());
    // next_ receives the new state in this step's cell order: slot k holds particle sortedIds_[k].
    setKernelArgs(fusedKernel_.get(), state_.get(), deviceGrid_.cellOrder(), sortedIds_.get(), deviceGrid_.cells(),
                  g.cellsPerLengthX, g.cellsPerLengthY, g.cols, g.rows, count, dt, world_.gravity.x,
                  world_.gravity.y, world_.width, world_.height, periodic(), next_.get(), tallies_.get(),
                  deviceGrid_.nextCounts(), deviceGrid_.cellOf(), deviceGrid_.rankInCell(), nextStepIndex(),
                  firstNonFinite_.get());
    enqueue1d(queue_.get(), fusedKernel_.get(), count, workGroupSize_, "resolveIntegrateAndCount", profiler_.get());
    std::swap(state_, next_);
    std::swap(ids_, sortedIds_);
    deviceGrid_.advance();
}

// The rounds resolve the events in state_ (in the cell order of the step
// before), then every disk finishes the step into slot k of next_, in this
// step's cell order, counted into the next grid, as stepResident does. The
// host does not wait: confirmStep, before anything reads the result, does
// (one wait per step, which also reads the largest speed for the next one).
void OpenClBackend::stepResidentPairwise(float dt) {
    confirmStep();
    if (nonFinite()) return;
    const CaromPairwiseStep step = pairwiseStep(dt);
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get());
    pairwise_.enqueueStep(queue_.get(), {state_.get(), deviceGrid_.cellOrder(), sortedIds_.get(), deviceGrid_.cellOf(),
                                         deviceGrid_.cells(), tallies_.get()},
                          step);
    speedParity_ = 1 - speedParity_;
    unconfirmedStepIndex_ = nextStepIndex();
    enqueueResidentFinish(step, unconfirmedStepIndex_);
    check(clFlush(queue_.get()), "clFlush");
    unconfirmed_ = true;
}

// The kernel records a disk left non-finite in the pairwise lengths, which
// confirmStep reads anyway.
void OpenClBackend::enqueueResidentFinish(const CaromPairwiseStep& step, cl_uint stepIndex) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    setKernelArgs(finishAndCountKernel_.get(), state_.get(), deviceGrid_.cellOrder(), sortedIds_.get(), step, count,
                  next_.get(), tallies_.get(), deviceGrid_.nextCounts(), deviceGrid_.cellOf(),
                  deviceGrid_.rankInCell());
    setLocalArg(finishAndCountKernel_.get(), 10, reductionGroupSize_ * sizeof(cl_float));
    const cl_mem speedBits = speedBits_.get(), lengths = pairwise_.lengths();
    const cl_uint parity = speedParity_, condition = pairwise_.finishCondition();
    check(clSetKernelArg(finishAndCountKernel_.get(), 11, sizeof(cl_mem), &speedBits), "clSetKernelArg");
    check(clSetKernelArg(finishAndCountKernel_.get(), 12, sizeof(cl_uint), &parity), "clSetKernelArg");
    check(clSetKernelArg(finishAndCountKernel_.get(), 13, sizeof(cl_mem), &lengths), "clSetKernelArg");
    check(clSetKernelArg(finishAndCountKernel_.get(), 14, sizeof(cl_uint), &condition), "clSetKernelArg");
    const cl_uint nonFiniteIndex = DevicePairwise::nonFiniteIndex();
    check(clSetKernelArg(finishAndCountKernel_.get(), 15, sizeof(cl_uint), &stepIndex), "clSetKernelArg");
    check(clSetKernelArg(finishAndCountKernel_.get(), 16, sizeof(cl_uint), &nonFiniteIndex), "clSetKernelArg");
    enqueue1d(queue_.get(), finishAndCountKernel_.get(), finishItems_, reductionGroupSize_, "finishPairwiseAndCount",
              profiler_.get());
}

void OpenClBackend::confirmStep() {
    if (!unconfirmed_) return;
    unconfirmed_ = false;
    const DevicePairwise::Completion completion = pairwise_.complete(queue_.get());
    if (completion.finishSkipped) {
        enqueueResidentFinish(pairwise_.step(), unconfirmedStepIndex_);
        pairwise_.readLengths(queue_.get());  // rare: a wait of its own, for the finish's record
    }
    std::copy_n(pairwise_.nonFiniteRecord(), 2, firstNonFiniteRead_);
    checkNonFinite();
    recordRounds(completion.rounds);
    speedKnown_ = true;
    std::swap(state_, next_);
    std::swap(ids_, sortedIds_);
    deviceGrid_.advance();
}

void OpenClBackend::stepAllPairs(float dt) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    setKernelArgs(allPairsKernel_.get(), state_.get(), count, world_.width, world_.height, periodic(), next_.get(),
                  tallies_.get());
    enqueue1d(queue_.get(), allPairsKernel_.get(), count, workGroupSize_, "resolveAllPairs", profiler_.get());
    setKernelArgs(integrateKernel_.get(), next_.get(), count, dt, world_.gravity.x, world_.gravity.y, world_.width,
                  world_.height, periodic(), tallies_.get(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue_.get(), integrateKernel_.get(), count, workGroupSize_, "integrate", profiler_.get());
    std::swap(state_, next_);
}

void OpenClBackend::readParticles(std::vector<Particle>& particles) {
    confirmStep();
    if (pipeline_ == Pipeline::Seed) {
        particles = hostState_;
        return;
    }
    particles.resize(particleCount_);
    if (pipeline_ == Pipeline::AllPairs) {
        check(clEnqueueReadBuffer(queue_.get(), state_.get(), CL_TRUE, 0, particleCount_ * sizeof(Particle),
                                  particles.data(), 0, nullptr, nullptr),
              "clEnqueueReadBuffer(particle state)");
        return;
    }
    // Resident: slot s holds particle ids[s].
    std::vector<Particle> slots(particleCount_);
    std::vector<cl_uint> ids(particleCount_);
    check(clEnqueueReadBuffer(queue_.get(), state_.get(), CL_TRUE, 0, particleCount_ * sizeof(Particle),
                              slots.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(particle state)");
    check(clEnqueueReadBuffer(queue_.get(), ids_.get(), CL_TRUE, 0, particleCount_ * sizeof(cl_uint), ids.data(), 0,
                              nullptr, nullptr),
          "clEnqueueReadBuffer(particle ids)");
    for (std::size_t s = 0; s < particleCount_; ++s) particles[ids[s]] = slots[s];
}

float OpenClBackend::maxSpeedSquared() {
    if (pipeline_ == Pipeline::Seed) return maxSpeedSquaredOf(hostState_.data(), hostState_.size());
    confirmStep();
    if (speedKnown_) {  // the pairwise resident step took it as it finished
        cl_float largest = 0.0f;
        check(clEnqueueReadBuffer(queue_.get(), speedBits_.get(), CL_TRUE, speedParity_ * sizeof(cl_uint),
                                  sizeof(cl_float), &largest, 0, nullptr, nullptr),
              "clEnqueueReadBuffer(largest speed squared)");
        return largest;
    }
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    const std::size_t groups =
        std::min(kReductionGroups, (particleCount_ + reductionGroupSize_ - 1) / reductionGroupSize_);
    setKernelArgs(maxSpeedKernel_.get(), state_.get(), count);
    setLocalArg(maxSpeedKernel_.get(), 2, reductionGroupSize_ * sizeof(cl_float));
    const cl_mem groupMaxBuffer = groupMax_.get();
    check(clSetKernelArg(maxSpeedKernel_.get(), 3, sizeof(cl_mem), &groupMaxBuffer), "clSetKernelArg");
    enqueue1d(queue_.get(), maxSpeedKernel_.get(), groups * reductionGroupSize_, reductionGroupSize_,
              "maxSpeedSquared", profiler_.get());
    std::vector<cl_float> groupMax(groups);
    check(clEnqueueReadBuffer(queue_.get(), groupMax_.get(), CL_TRUE, 0, groups * sizeof(cl_float), groupMax.data(), 0,
                              nullptr, nullptr),
          "clEnqueueReadBuffer(max speed per group)");
    return *std::max_element(groupMax.begin(), groupMax.end());
}

void OpenClBackend::drainTallies(ContactTotals& totals) {
    confirmStep();
    std::vector<ContactTally> tallies(particleCount_);
    check(clEnqueueReadBuffer(queue_.get(), tallies_.get(), CL_TRUE, 0, tallies.size() * sizeof(ContactTally),
                              tallies.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(contact tallies)");
    drainTallyArray(tallies.data(), tallies.size(), totals);
    enqueueZero(queue_.get(), tallies_.get(), tallies.size() * sizeof(ContactTally), "contact tallies");
}

Grid OpenClBackend::readDeviceGrid() {
    if (pipeline_ != Pipeline::Resident) throw Error("readDeviceGrid needs the resident pipeline");
    confirmStep();
    deviceGrid_.build(queue_.get(), ids_.get(), sortedIds_.get());
    return deviceGrid_.read(queue_.get(), sortedIds_.get());
}

}  // namespace carom
