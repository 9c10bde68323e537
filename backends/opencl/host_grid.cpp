#include "backends/opencl/host_grid.h"

#include <chrono>
#include <utility>

#include "backends/opencl/program.h"

namespace carom {

using namespace opencl;

OpenClHostGridBackend::OpenClHostGridBackend(const WorldDef& world, const std::string& device, bool profiling)
    : OpenClBackend(world, device, kernelSource(), profiling) {
    resolveKernel_ = createKernel(program_.get(), "resolveCollisions");
    integrateKernel_ = createKernel(program_.get(), "integrate");
    finishByIdKernel_ = createKernel(program_.get(), "finishStepById");
    fitWorkGroups({resolveKernel_.get(), integrateKernel_.get(), finishByIdKernel_.get()}, {});
}

void OpenClHostGridBackend::releaseState() {
    hostState_.clear();
    sortedIndices_.reset();
    cells_.reset();
    cellOf_.reset();
    pairwise_ = DevicePairwise();
}

void OpenClHostGridBackend::loadState(const std::vector<Particle>& particles) {
    const std::size_t n = particles.size();
    hostState_ = particles;
    sortedIndices_ = createBuffer(context_.get(), n * sizeof(cl_uint), "sorted indices");
    cells_ = createBuffer(context_.get(), std::size_t(grid_.geometry.cols) * grid_.geometry.rows * sizeof(GridCell),
                          "grid cells");
    if (world_.collisions != CollisionScheme::Pairwise) return;
    cellOf_ = createBuffer(context_.get(), n * sizeof(cl_uint), "cell of each particle");
    pairwise_ = DevicePairwise(context_.get(), device_, program_.get(), n, queue_.get(), profiler_.get());
}

void OpenClHostGridBackend::enqueueStep(float dt) {
    world_.collisions == CollisionScheme::Pairwise ? stepPairwise(dt) : stepSimultaneous(dt);
}

void OpenClHostGridBackend::uploadGrid() {
    Profiler* profiler = profiler_.get();
    const auto gridStart = std::chrono::steady_clock::now();
    buildGrid(hostState_.data(), hostState_.size(), grid_);
    if (profiler)
        profiler->addHostSeconds("buildGrid (host)",
                                 std::chrono::duration<double>(std::chrono::steady_clock::now() - gridStart).count());
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

void OpenClHostGridBackend::stepSimultaneous(float dt) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    const CaromStepParams step = stepParams(dt);
    cl_command_queue queue = queue_.get();
    Profiler* profiler = profiler_.get();
    uploadGrid();
    setKernelArgs(resolveKernel_.get(), state_.get(), sortedIndices_.get(), cells_.get(), step, next_.get(),
                  tallies_.get());
    enqueue1d(queue, resolveKernel_.get(), count, workGroupSize_, "resolveCollisions", profiler);
    setKernelArgs(integrateKernel_.get(), next_.get(), step, tallies_.get(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue, integrateKernel_.get(), count, workGroupSize_, "integrate", profiler);
    enqueueNonFiniteRead();
    check(clEnqueueReadBuffer(queue, next_.get(), CL_TRUE, 0, count * sizeof(Particle), hostState_.data(), 0, nullptr,
                              eventSlot(profiler, "download state")),
          "clEnqueueReadBuffer(particle state)");
    checkNonFinite();
    std::swap(state_, next_);
}

// The rounds resolve the events in state_ (stored by id, so sortedIndices
// serves as slots and ids), then every disk finishes the step in place.
void OpenClHostGridBackend::stepPairwise(float dt) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    cl_command_queue queue = queue_.get();
    const CaromStepParams step = stepParams(dt);
    uploadGrid();
    pairwise_.enqueueStart(queue, halt_.get(), {}, step);
    pairwise_.enqueueStep(queue,
                          {state_.get(), sortedIndices_.get(), sortedIndices_.get(), cellOf_.get(), cells_.get(),
                           tallies_.get(), halt_.get()},
                          step);
    // The rounds finish on the device, so the finish and the download follow
    // them in the queue; the lengths are read once all of it is done.
    setKernelArgs(finishByIdKernel_.get(), state_.get(), step, tallies_.get(), nextStepIndex(), firstNonFinite_.get());
    enqueue1d(queue, finishByIdKernel_.get(), count, workGroupSize_, "finishStepById", profiler_.get());
    enqueueNonFiniteRead();
    check(clEnqueueReadBuffer(queue, state_.get(), CL_TRUE, 0, count * sizeof(Particle), hostState_.data(), 0, nullptr,
                              eventSlot(profiler_.get(), "download state")),
          "clEnqueueReadBuffer(particle state)");
    recordRounds(pairwise_.complete(queue));
    checkNonFinite();
}

// The rounds' sorted positions are the host grid's (sortedIndices_).
void OpenClHostGridBackend::readLastRounds(std::vector<unsigned int>& rounds) {
    if (world_.collisions == CollisionScheme::Pairwise)
        pairwise_.readLastRounds(queue_.get(), sortedIndices_.get(), rounds);
    else
        rounds.assign(particleCount_, 0u);
}

}  // namespace carom
