// Thin, checked access to the OpenCL C API: error names, device discovery
// and selection, and owning handles. Every call's status is checked; a
// failure throws Error naming the call and the error code.
#pragma once

#define CL_TARGET_OPENCL_VERSION 120
#ifdef __APPLE__
#include <OpenCL/opencl.h>
#else
#include <CL/cl.h>
#endif

#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene.h"

namespace carom::opencl {

// "CL_OUT_OF_RESOURCES (-5)"
std::string errorName(cl_int status);

// Throws Error("<call> failed: <error name>") unless status is CL_SUCCESS.
void check(cl_int status, const char* call);

struct DeviceInfo {
    int index = 0;  // position in `carom devices`, across all platforms
    cl_platform_id platform = nullptr;
    cl_device_id id = nullptr;
    std::string platformName;
    std::string name;
    std::string version;        // CL_DEVICE_VERSION
    std::string driverVersion;  // CL_DRIVER_VERSION
    std::string type;           // "GPU", "CPU", "accelerator", ...
    bool correctlyRoundedDivideSqrt = false;
    unsigned long long globalMemoryBytes = 0;
    unsigned long long localMemoryBytes = 0;
    unsigned int computeUnits = 1;  // CL_DEVICE_MAX_COMPUTE_UNITS
};

// Every device of every platform. Throws Error, suggesting --backend cpu,
// when there is no OpenCL platform or no device at all.
std::vector<DeviceInfo> listDevices();

// An index from listDevices, or a case-insensitive part of the device or
// platform name; empty selects the first GPU, else the first device.
DeviceInfo selectDevice(const std::string& selector);

// A choice that the environment variable `variable` may force (the tests
// run both ways): true where it is `yes`, false where it is `no`, and
// `otherwise` where it is unset; any other value is refused.
bool forcedChoice(const char* variable, const std::string& yes, const std::string& no, bool otherwise);

// An owning OpenCL object handle, released on destruction.
template <class T, cl_int (*Release)(T)>
class Handle {
public:
    Handle() = default;
    explicit Handle(T handle) : handle_(handle) {}
    ~Handle() { reset(); }
    Handle(Handle&& other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
    Handle& operator=(Handle&& other) noexcept {
        if (this != &other) {
            reset();
            handle_ = std::exchange(other.handle_, nullptr);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;

    T get() const { return handle_; }
    void reset() {
        if (handle_) Release(handle_);
        handle_ = nullptr;
    }

private:
    T handle_ = nullptr;
};

inline cl_int releaseContext(cl_context h) { return clReleaseContext(h); }
inline cl_int releaseQueue(cl_command_queue h) { return clReleaseCommandQueue(h); }
inline cl_int releaseProgram(cl_program h) { return clReleaseProgram(h); }
inline cl_int releaseKernel(cl_kernel h) { return clReleaseKernel(h); }
// Takes back the buffer's share of its context's BufferBytes, if counted.
cl_int releaseMem(cl_mem h);

using Context = Handle<cl_context, releaseContext>;
using Queue = Handle<cl_command_queue, releaseQueue>;
using Program = Handle<cl_program, releaseProgram>;
using Kernel = Handle<cl_kernel, releaseKernel>;
using Buffer = Handle<cl_mem, releaseMem>;

// Builds an embedded program (`source`: backends/opencl/program.h, or the
// benchmark's, app/bench/program.h) for the device. With exactArithmetic,
// divide and sqrt are built correctly rounded. A build failure throws Error
// with the compiler's log.
Program buildProgram(cl_context context, const DeviceInfo& device, const char* source, bool exactArithmetic);

Kernel createKernel(cl_program program, const char* name);
// A buffer of `bytes` in `context`; counted in the context's BufferBytes
// until released, where the context is tracked.
Buffer createBuffer(cl_context context, std::size_t bytes, const char* what);

// The bytes of a context's buffers alive now, and the most alive at once.
struct BufferBytes {
    unsigned long long live = 0, peak = 0;
};
// Counts the buffers createBuffer makes in `context` from now on, until
// untrackBuffers; bufferBytes reads the count ({} for a context not tracked).
void trackBuffers(cl_context context);
void untrackBuffers(cl_context context);
BufferBytes bufferBytes(cl_context context);

// Device time per command name, read from the events of a queue created
// with CL_QUEUE_PROFILING_ENABLE, plus host work timed by the caller. For
// explaining where a step's time goes; timings for the record come from
// wall clocks on a queue without profiling.
class Profiler {
public:
    Profiler() = default;
    ~Profiler();
    Profiler(const Profiler&) = delete;
    Profiler& operator=(const Profiler&) = delete;

    // Where the next command named `name` stores its event.
    cl_event* slot(const char* name);
    void addHostSeconds(const std::string& name, double seconds);
    // Adds the device times of the recorded commands, which must have
    // finished (after clFinish), and releases their events.
    void collect();
    // Seconds per name since the last clear(), in collect()ed commands.
    const std::map<std::string, double>& seconds() const { return seconds_; }
    void clear() { seconds_.clear(); }

private:
    std::deque<std::pair<std::string, cl_event>> pending_;  // a deque keeps slots in place
    std::map<std::string, double> seconds_;
};

// `profiler`'s event slot for a command, or none when not profiling.
inline cl_event* eventSlot(Profiler* profiler, const char* name) { return profiler ? profiler->slot(name) : nullptr; }

// The largest work-group the kernel can run with on the device.
std::size_t kernelWorkGroupLimit(cl_kernel kernel, cl_device_id device);

// Runs a 1D kernel over `items` work-items in groups of `groupSize` (the
// global size rounded up; kernels skip the excess ids).
void enqueue1d(cl_command_queue queue, cl_kernel kernel, std::size_t items, std::size_t groupSize, const char* name,
               Profiler* profiler = nullptr);

// Sets `bytes` bytes of the buffer to zero (clEnqueueFillBuffer).
void enqueueZero(cl_command_queue queue, cl_mem buffer, std::size_t bytes, const char* what);
// Copies the first `bytes` bytes of `from` into `to` on the device (clEnqueueCopyBuffer).
void enqueueCopy(cl_command_queue queue, cl_mem from, cl_mem to, std::size_t bytes, const char* what);

// Sets all arguments of a kernel in order.
template <class... Args>
void setKernelArgs(cl_kernel kernel, const Args&... args) {
    cl_uint index = 0;
    (check(clSetKernelArg(kernel, index++, sizeof(Args), &args), "clSetKernelArg"), ...);
}

// Makes argument `index` a __local buffer of `bytes` bytes.
void setLocalArg(cl_kernel kernel, cl_uint index, std::size_t bytes);

}  // namespace carom::opencl
