#include "backends/opencl/backend.h"

#include <algorithm>
#include <utility>

#include "engine/parallel.h"

namespace carom {

using namespace opencl;

namespace {

// Steps enqueued between waits for the device: bounds the commands in flight
// on a long run, while one wait per batch costs the GPU almost no idle time.
constexpr std::uint64_t kStepsPerSync = 64;

}  // namespace

OpenClBackend::OpenClBackend(const WorldDef& world, const std::string& device, const char* programSource,
                             bool profiling)
    : Backend(world), profiler_(profiling ? std::make_unique<Profiler>() : nullptr), device_(selectDevice(device)) {
    cl_int status = CL_SUCCESS;
    context_ = Context(clCreateContext(nullptr, 1, &device_.id, nullptr, nullptr, &status));
    check(status, "clCreateContext");
    trackBuffers(context_.get());
    try {  // a constructor that throws runs no destructor, which would untrack the context
        queue_ =
            Queue(clCreateCommandQueue(context_.get(), device_.id, profiling ? CL_QUEUE_PROFILING_ENABLE : 0, &status));
        check(status, "clCreateCommandQueue");
        program_ = buildProgram(context_.get(), device_, programSource, device_.correctlyRoundedDivideSqrt);
        views_ = DeviceViews(context_.get(), device_, program_.get(), profiler_.get());
        firstNonFinite_ = createBuffer(context_.get(), sizeof(kNoneNonFinite), "first non-finite step and particle");
        const cl_uint halt[2] = {kRunning, 0};  // running; the grid built each step (kernels/params.h)
        halt_ = createBuffer(context_.get(), sizeof halt, "halt");
        check(clEnqueueWriteBuffer(queue_.get(), halt_.get(), CL_TRUE, 0, sizeof halt, halt, 0, nullptr, nullptr),
              "clEnqueueWriteBuffer(halt)");
    } catch (...) {
        untrackBuffers(context_.get());
        throw;
    }
}

OpenClBackend::~OpenClBackend() { untrackBuffers(context_.get()); }

DeviceMemoryUse OpenClBackend::deviceMemory() const {
    const BufferBytes bytes = bufferBytes(context_.get());
    return {bytes.live, bytes.peak};
}

std::string OpenClBackend::device() const {
    return device_.name + " (" + device_.platformName + ", " + device_.version + "), " + pipelineName() + " pipeline";
}

void OpenClBackend::fitWorkGroups(std::initializer_list<cl_kernel> perParticle,
                                  std::initializer_list<cl_kernel> reducing) {
    for (cl_kernel kernel : perParticle)
        workGroupSize_ = std::min(workGroupSize_, kernelWorkGroupLimit(kernel, device_.id));
    for (cl_kernel kernel : reducing)
        while (reductionGroupSize_ > kernelWorkGroupLimit(kernel, device_.id)) reductionGroupSize_ /= 2;
}

void OpenClBackend::load(const std::vector<Particle>& particles) {
    const std::size_t n = particles.size();
    createState(n);
    check(clEnqueueWriteBuffer(queue_.get(), state_.get(), CL_TRUE, 0, n * sizeof(Particle), particles.data(), 0,
                               nullptr, nullptr),
          "clEnqueueWriteBuffer(particle state)");
    loadState(particles);
    finish();
    if (profiler_) profiler_->clear();  // the profile covers steps only
}

void OpenClBackend::createState(std::size_t n, bool keepRoom) {
    startState_.reset();  // made for particleCount_ at the first keepStepStart
    startIds_.reset();
    startTallies_.reset();
    views_.release();
    if (!keepRoom || !state_.get() || stateRoom_ < n) {
        // Free the previous state's buffers first: a state may fill the device.
        releaseState();
        state_.reset();
        next_.reset();
        tallies_.reset();
        stateRoom_ = keepRoom ? n + n / 4 : n;
        state_ = createBuffer(context_.get(), stateRoom_ * sizeof(Particle), "particle state");
        next_ = createBuffer(context_.get(), stateRoom_ * sizeof(Particle), "next particle state");
        tallies_ = createBuffer(context_.get(), stateRoom_ * sizeof(ContactTally), "contact tallies");
    }
    enqueueZero(queue_.get(), tallies_.get(), n * sizeof(ContactTally), "contact tallies");
    check(clEnqueueWriteBuffer(queue_.get(), firstNonFinite_.get(), CL_TRUE, 0, sizeof(kNoneNonFinite), kNoneNonFinite,
                               0, nullptr, nullptr),
          "clEnqueueWriteBuffer(first non-finite step and particle)");
    substep_ = nonFiniteBase_ = substepsTaken();  // 0 but where a step returns to its start
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
// the pipelines that wait each step, every kStepsPerSync steps in the others
// (whose steps until then stay as cheap, carom_count_into_cell).
// A stop is looked for at those waits, where the host is not ahead of the device.
std::uint64_t OpenClBackend::advance(std::uint64_t steps, float dt) {
    const bool waits = waitsEachStep();
    std::uint64_t s = 0;
    while (s < steps && !nonFinite()) {
        s += enqueueSteps(std::min(steps - s, waits ? 1 : kStepsPerSync - s % kStepsPerSync), dt);
        if (waits || s % kStepsPerSync == 0) {
            if (!waits) finish();
            if (s < steps && stopHere()) break;
        }
    }
    if (!waits) finish();
    return s;
}

void OpenClBackend::keepStepStart() {
    const std::size_t n = particleCount_;
    cl_mem ids = slotIds();
    if (!startState_.get()) {
        startState_ = createBuffer(context_.get(), n * sizeof(Particle), "the step's start");
        startTallies_ = createBuffer(context_.get(), n * sizeof(ContactTally), "the step's start tallies");
        if (ids) startIds_ = createBuffer(context_.get(), n * sizeof(cl_uint), "the step's start ids");
    }
    enqueueCopy(queue_.get(), state_.get(), startState_.get(), n * sizeof(Particle), "the step's start");
    enqueueCopy(queue_.get(), tallies_.get(), startTallies_.get(), n * sizeof(ContactTally),
                "the step's start tallies");
    if (ids) enqueueCopy(queue_.get(), ids, startIds_.get(), n * sizeof(cl_uint), "the step's start ids");
}

void OpenClBackend::returnToStepStart() {
    std::vector<Particle> particles;
    readInIdOrder(startState_.get(), startIds_.get(), particles);
    // The copy of the tallies outlives the load, which frees the others.
    opencl::Buffer tallies = std::move(startTallies_);
    load(particles);
    enqueueCopy(queue_.get(), tallies.get(), tallies_.get(), particleCount_ * sizeof(ContactTally), "contact tallies");
    finish();
}

void OpenClBackend::awaitSteps() { finish(); }

void OpenClBackend::readParticles(std::vector<Particle>& particles) {
    readInIdOrder(state_.get(), slotIds(), particles);
}

void OpenClBackend::readInIdOrder(cl_mem state, cl_mem ids, std::vector<Particle>& particles) {
    const std::size_t n = particleCount_;
    particles.resize(n);
    if (!ids) {
        check(clEnqueueReadBuffer(queue_.get(), state, CL_TRUE, 0, n * sizeof(Particle), particles.data(), 0, nullptr,
                                  nullptr),
              "clEnqueueReadBuffer(particle state)");
        return;
    }
    // Written first by the reads; then scattered into id order in parallel.
    UninitialisedVector<Particle> slots(n);
    UninitialisedVector<cl_uint> idOfSlot(n);
    check(clEnqueueReadBuffer(queue_.get(), state, CL_TRUE, 0, n * sizeof(Particle), slots.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(particle state)");
    check(clEnqueueReadBuffer(queue_.get(), ids, CL_TRUE, 0, n * sizeof(cl_uint), idOfSlot.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(particle ids)");
    parallelFor(n, [&](std::size_t s) { particles[idOfSlot[s]] = slots[s]; });
}

std::optional<ViewSums> OpenClBackend::readView(ViewValue value, DiskView* out) {
    if (particleCount_ == 0) return ViewSums{};
    return views_.read(queue_.get(), state_.get(), slotIds(), particleCount_, value, world().gravity, out);
}

float OpenClBackend::maxSpeedSquared() { return views_.maxSpeedSquared(queue_.get(), state_.get(), particleCount_); }

void OpenClBackend::readTallies(std::vector<ContactTally>& tallies) {
    tallies.resize(particleCount_);
    check(clEnqueueReadBuffer(queue_.get(), tallies_.get(), CL_TRUE, 0, tallies.size() * sizeof(ContactTally),
                              tallies.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(contact tallies)");
}

void OpenClBackend::writeTallies(const std::vector<ContactTally>& tallies) {
    check(clEnqueueWriteBuffer(queue_.get(), tallies_.get(), CL_TRUE, 0, tallies.size() * sizeof(ContactTally),
                               tallies.data(), 0, nullptr, nullptr),
          "clEnqueueWriteBuffer(contact tallies)");
}

void OpenClBackend::drainTallies(ContactTotals& totals) {
    std::vector<ContactTally> tallies;
    readTallies(tallies);
    drainTallyArray(tallies.data(), tallies.size(), totals, images_.data());
    enqueueZero(queue_.get(), tallies_.get(), tallies.size() * sizeof(ContactTally), "contact tallies");
}

}  // namespace carom
