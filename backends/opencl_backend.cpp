#include "backends/opencl_backend.h"

#include <algorithm>
#include <numeric>

namespace carom {

using namespace opencl;

OpenClBackend::OpenClBackend(const WorldDef& world, const std::string& device)
    : Backend(world), device_(selectDevice(device)) {
    cl_int status = CL_SUCCESS;
    context_ = Context(clCreateContext(nullptr, 1, &device_.id, nullptr, nullptr, &status));
    check(status, "clCreateContext");
    queue_ = Queue(clCreateCommandQueue(context_.get(), device_.id, 0, &status));
    check(status, "clCreateCommandQueue");
    program_ = buildProgram(context_.get(), device_, device_.correctlyRoundedDivideSqrt);
    resolveKernel_ = createKernel(program_.get(), "resolveCollisions");
    integrateKernel_ = createKernel(program_.get(), "integrate");
    for (cl_kernel kernel : {resolveKernel_.get(), integrateKernel_.get()}) {
        std::size_t limit = 0;
        check(clGetKernelWorkGroupInfo(kernel, device_.id, CL_KERNEL_WORK_GROUP_SIZE, sizeof limit, &limit, nullptr),
              "clGetKernelWorkGroupInfo");
        workGroupSize_ = std::min(workGroupSize_, limit);
    }
}

std::string OpenClBackend::device() const {
    return device_.name + " (" + device_.platformName + ", " + device_.version + ")";
}

void OpenClBackend::load(const std::vector<Particle>& particles) {
    const std::size_t n = particles.size();
    hostState_ = particles;
    state_ = createBuffer(context_.get(), n * sizeof(Particle), "particle state");
    next_ = createBuffer(context_.get(), n * sizeof(Particle), "next particle state");
    sortedIndices_ = createBuffer(context_.get(), n * sizeof(cl_uint), "sorted indices");
    cells_ = createBuffer(context_.get(),
                          std::size_t(grid_.geometry.cols) * grid_.geometry.rows * sizeof(GridCell), "grid cells");
    collisionCounts_ = createBuffer(context_.get(), n * sizeof(cl_uint), "collision counts");
    const std::vector<cl_uint> zeros(n, 0);
    check(clEnqueueWriteBuffer(queue_.get(), state_.get(), CL_TRUE, 0, n * sizeof(Particle), particles.data(), 0,
                               nullptr, nullptr),
          "clEnqueueWriteBuffer(particle state)");
    check(clEnqueueWriteBuffer(queue_.get(), collisionCounts_.get(), CL_TRUE, 0, n * sizeof(cl_uint), zeros.data(),
                               0, nullptr, nullptr),
          "clEnqueueWriteBuffer(collision counts)");
}

std::size_t OpenClBackend::globalSize() const {
    return (particleCount_ + workGroupSize_ - 1) / workGroupSize_ * workGroupSize_;
}

void OpenClBackend::step(std::uint64_t steps) {
    const cl_uint count = static_cast<cl_uint>(particleCount_);
    const GridGeometry& g = grid_.geometry;
    const std::size_t global = globalSize();
    cl_command_queue queue = queue_.get();
    for (std::uint64_t s = 0; s < steps; ++s) {
        buildGrid(hostState_.data(), hostState_.size(), grid_);
        // Non-blocking writes: the host vectors stay untouched until the
        // blocking read below, which the in-order queue runs last.
        check(clEnqueueWriteBuffer(queue, sortedIndices_.get(), CL_FALSE, 0, count * sizeof(cl_uint),
                                   grid_.sortedIndices.data(), 0, nullptr, nullptr),
              "clEnqueueWriteBuffer(sorted indices)");
        check(clEnqueueWriteBuffer(queue, cells_.get(), CL_FALSE, 0, grid_.cells.size() * sizeof(GridCell),
                                   grid_.cells.data(), 0, nullptr, nullptr),
              "clEnqueueWriteBuffer(grid cells)");
        setKernelArgs(resolveKernel_.get(), state_.get(), sortedIndices_.get(), cells_.get(), g.cellsPerLengthX,
                      g.cellsPerLengthY, g.cols, g.rows, count, next_.get(), collisionCounts_.get());
        check(clEnqueueNDRangeKernel(queue, resolveKernel_.get(), 1, nullptr, &global, &workGroupSize_, 0, nullptr,
                                     nullptr),
              "clEnqueueNDRangeKernel(resolveCollisions)");
        setKernelArgs(integrateKernel_.get(), next_.get(), count, world_.dt, world_.gravity.x, world_.gravity.y,
                      world_.width, world_.height);
        check(clEnqueueNDRangeKernel(queue, integrateKernel_.get(), 1, nullptr, &global, &workGroupSize_, 0, nullptr,
                                     nullptr),
              "clEnqueueNDRangeKernel(integrate)");
        check(clEnqueueReadBuffer(queue, next_.get(), CL_TRUE, 0, count * sizeof(Particle), hostState_.data(), 0,
                                  nullptr, nullptr),
              "clEnqueueReadBuffer(particle state)");
        std::swap(state_, next_);
    }
}

std::uint64_t OpenClBackend::collisions() {
    std::vector<cl_uint> counts(particleCount_);
    check(clEnqueueReadBuffer(queue_.get(), collisionCounts_.get(), CL_TRUE, 0, counts.size() * sizeof(cl_uint),
                              counts.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(collision counts)");
    return std::accumulate(counts.begin(), counts.end(), std::uint64_t{0});
}

}  // namespace carom
