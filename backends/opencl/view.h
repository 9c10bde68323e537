// What the host reads of a state on an OpenCL device without reading it
// whole (kernels/view.cl), for every pipeline (OpenClBackend owns one): the
// viewer's 16 bytes a disk with its readouts' sums, and the largest speed,
// which sizes substeps. Each is one launch of work-groups that reduce, whose
// per-group results the host finishes.
#pragma once

#include <cstddef>

#include <carom/types.h>

#include "backends/opencl/runtime.h"

namespace carom::opencl {

class DeviceViews {
public:
    DeviceViews() = default;
    // Kernels and per-group buffers from `program`; launches are recorded in
    // `profiler` when given.
    DeviceViews(cl_context context, const DeviceInfo& device, cl_program program, Profiler* profiler = nullptr);

    // writeDiskViews: the views of the `count` (>= 1) disks of `state`, slot
    // s holding disk ids[s] (s where `ids` is null), into out[0..count) in
    // slot order, and their sums, added in double. The first read makes the
    // views' buffer, for `count` disks until release().
    ViewSums read(cl_command_queue queue, cl_mem state, cl_mem ids, std::size_t count, ViewValue value, Vec2 gravity,
                  DiskView* out);
    // maxSpeedSquared: the largest v.x^2 + v.y^2 of the `count` (>= 1)
    // disks of `state`.
    float maxSpeedSquared(cl_command_queue queue, cl_mem state, std::size_t count);
    // Frees the views' buffer, made for the state loaded before.
    void release() { views_.reset(); }

private:
    std::size_t groups(std::size_t count) const;

    cl_context context_ = nullptr;
    Profiler* profiler_ = nullptr;
    std::size_t groupSize_ = 256;  // a power of two
    Kernel viewKernel_, maxSpeedKernel_;
    Buffer views_;      // writeDiskViews' views, made at the first read
    Buffer groupSums_;  // and its per-group sums
    Buffer groupMax_;   // maxSpeedSquared's per-group results
};

}  // namespace carom::opencl
