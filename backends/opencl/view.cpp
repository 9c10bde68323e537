#include "backends/opencl/view.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace carom::opencl {
namespace {

// Work-groups of a reduction: enough to fill a GPU, few enough for the host
// to finish the reduction at once.
constexpr std::size_t kReductionGroups = 256;

}  // namespace

DeviceViews::DeviceViews(cl_context context, const DeviceInfo& device, cl_program program, Profiler* profiler)
    : context_(context), profiler_(profiler) {
    viewKernel_ = createKernel(program, "writeDiskViews");
    maxSpeedKernel_ = createKernel(program, "maxSpeedSquared");
    for (cl_kernel kernel : {maxSpeedKernel_.get(), viewKernel_.get()})
        while (groupSize_ > kernelWorkGroupLimit(kernel, device.id)) groupSize_ /= 2;
    groupSums_ =
        createBuffer(context, kReductionGroups * CAROM_VIEW_SUM_COUNT * sizeof(cl_float), "view sums per group");
    groupMax_ = createBuffer(context, kReductionGroups * sizeof(cl_float), "max speed per group");
}

std::size_t DeviceViews::groups(std::size_t count) const {
    return std::min(kReductionGroups, (count + groupSize_ - 1) / groupSize_);
}

ViewSums DeviceViews::read(cl_command_queue queue, cl_mem state, cl_mem ids, std::size_t count, ViewValue value,
                           Vec2 gravity, DiskView* out) {
    if (!views_.get()) views_ = createBuffer(context_, count * sizeof(DiskView), "disk views");
    const std::size_t groupCount = groups(count);
    setKernelArgs(viewKernel_.get(), state, ids, cl_uint(count), cl_uint(value), gravity, views_.get(),
                  groupSums_.get());
    setLocalArg(viewKernel_.get(), 7, groupSize_ * 2 * sizeof(cl_float));
    enqueue1d(queue, viewKernel_.get(), groupCount * groupSize_, groupSize_, "writeDiskViews", profiler_);
    std::vector<cl_float> groupSums(groupCount * CAROM_VIEW_SUM_COUNT);
    check(clEnqueueReadBuffer(queue, views_.get(), CL_FALSE, 0, count * sizeof(DiskView), out, 0, nullptr, nullptr),
          "clEnqueueReadBuffer(disk views)");
    check(clEnqueueReadBuffer(queue, groupSums_.get(), CL_TRUE, 0, groupSums.size() * sizeof(cl_float),
                              groupSums.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(view sums per group)");
    ViewSums result;
    result.minValue = HUGE_VALF;
    result.maxValue = -HUGE_VALF;
    for (std::size_t g = 0; g < groupCount; ++g) {
        const cl_float* group = groupSums.data() + g * CAROM_VIEW_SUM_COUNT;
        auto pair = [&](int at) { return double(group[at]) + double(group[at + 1]); };
        result.kineticEnergy += pair(CAROM_VIEW_SUM_KINETIC);
        result.potentialEnergy += pair(CAROM_VIEW_SUM_POTENTIAL);
        result.momentum[0] += pair(CAROM_VIEW_SUM_MOMENTUM_X);
        result.momentum[1] += pair(CAROM_VIEW_SUM_MOMENTUM_Y);
        result.mass += pair(CAROM_VIEW_SUM_MASS);
        result.speedSquared += pair(CAROM_VIEW_SUM_SPEED_SQUARED);
        result.minValue = std::min(result.minValue, group[CAROM_VIEW_SUM_MIN_VALUE]);
        result.maxValue = std::max(result.maxValue, group[CAROM_VIEW_SUM_MAX_VALUE]);
    }
    return result;
}

float DeviceViews::maxSpeedSquared(cl_command_queue queue, cl_mem state, std::size_t count) {
    const std::size_t groupCount = groups(count);
    setKernelArgs(maxSpeedKernel_.get(), state, cl_uint(count));
    setLocalArg(maxSpeedKernel_.get(), 2, groupSize_ * sizeof(cl_float));
    const cl_mem groupMax = groupMax_.get();
    check(clSetKernelArg(maxSpeedKernel_.get(), 3, sizeof(cl_mem), &groupMax), "clSetKernelArg");
    enqueue1d(queue, maxSpeedKernel_.get(), groupCount * groupSize_, groupSize_, "maxSpeedSquared", profiler_);
    std::vector<cl_float> groupMaxima(groupCount);
    check(clEnqueueReadBuffer(queue, groupMax_.get(), CL_TRUE, 0, groupCount * sizeof(cl_float), groupMaxima.data(), 0,
                              nullptr, nullptr),
          "clEnqueueReadBuffer(max speed per group)");
    return *std::max_element(groupMaxima.begin(), groupMaxima.end());
}

}  // namespace carom::opencl
