#include "backends/opencl/runtime.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>

namespace carom::opencl {
namespace {

#define CAROM_CL_ERROR(code) \
    case code: return #code;

const char* errorSymbol(cl_int status) {
    switch (status) {
        CAROM_CL_ERROR(CL_SUCCESS)
        CAROM_CL_ERROR(CL_DEVICE_NOT_FOUND)
        CAROM_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
        CAROM_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
        CAROM_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        CAROM_CL_ERROR(CL_OUT_OF_RESOURCES)
        CAROM_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
        CAROM_CL_ERROR(CL_PROFILING_INFO_NOT_AVAILABLE)
        CAROM_CL_ERROR(CL_MEM_COPY_OVERLAP)
        CAROM_CL_ERROR(CL_IMAGE_FORMAT_MISMATCH)
        CAROM_CL_ERROR(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        CAROM_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
        CAROM_CL_ERROR(CL_MAP_FAILURE)
        CAROM_CL_ERROR(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        CAROM_CL_ERROR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        CAROM_CL_ERROR(CL_COMPILE_PROGRAM_FAILURE)
        CAROM_CL_ERROR(CL_LINKER_NOT_AVAILABLE)
        CAROM_CL_ERROR(CL_LINK_PROGRAM_FAILURE)
        CAROM_CL_ERROR(CL_DEVICE_PARTITION_FAILED)
        CAROM_CL_ERROR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        CAROM_CL_ERROR(CL_INVALID_VALUE)
        CAROM_CL_ERROR(CL_INVALID_DEVICE_TYPE)
        CAROM_CL_ERROR(CL_INVALID_PLATFORM)
        CAROM_CL_ERROR(CL_INVALID_DEVICE)
        CAROM_CL_ERROR(CL_INVALID_CONTEXT)
        CAROM_CL_ERROR(CL_INVALID_QUEUE_PROPERTIES)
        CAROM_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
        CAROM_CL_ERROR(CL_INVALID_HOST_PTR)
        CAROM_CL_ERROR(CL_INVALID_MEM_OBJECT)
        CAROM_CL_ERROR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        CAROM_CL_ERROR(CL_INVALID_IMAGE_SIZE)
        CAROM_CL_ERROR(CL_INVALID_SAMPLER)
        CAROM_CL_ERROR(CL_INVALID_BINARY)
        CAROM_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
        CAROM_CL_ERROR(CL_INVALID_PROGRAM)
        CAROM_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
        CAROM_CL_ERROR(CL_INVALID_KERNEL_NAME)
        CAROM_CL_ERROR(CL_INVALID_KERNEL_DEFINITION)
        CAROM_CL_ERROR(CL_INVALID_KERNEL)
        CAROM_CL_ERROR(CL_INVALID_ARG_INDEX)
        CAROM_CL_ERROR(CL_INVALID_ARG_VALUE)
        CAROM_CL_ERROR(CL_INVALID_ARG_SIZE)
        CAROM_CL_ERROR(CL_INVALID_KERNEL_ARGS)
        CAROM_CL_ERROR(CL_INVALID_WORK_DIMENSION)
        CAROM_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
        CAROM_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
        CAROM_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
        CAROM_CL_ERROR(CL_INVALID_EVENT_WAIT_LIST)
        CAROM_CL_ERROR(CL_INVALID_EVENT)
        CAROM_CL_ERROR(CL_INVALID_OPERATION)
        CAROM_CL_ERROR(CL_INVALID_GL_OBJECT)
        CAROM_CL_ERROR(CL_INVALID_BUFFER_SIZE)
        CAROM_CL_ERROR(CL_INVALID_MIP_LEVEL)
        CAROM_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
        CAROM_CL_ERROR(CL_INVALID_PROPERTY)
        CAROM_CL_ERROR(CL_INVALID_IMAGE_DESCRIPTOR)
        CAROM_CL_ERROR(CL_INVALID_COMPILER_OPTIONS)
        CAROM_CL_ERROR(CL_INVALID_LINKER_OPTIONS)
        CAROM_CL_ERROR(CL_INVALID_DEVICE_PARTITION_COUNT)
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "unknown OpenCL error";
    }
}
#undef CAROM_CL_ERROR

std::string platformString(cl_platform_id platform, cl_platform_info what) {
    std::size_t size = 0;
    check(clGetPlatformInfo(platform, what, 0, nullptr, &size), "clGetPlatformInfo");
    std::string value(size, '\0');
    check(clGetPlatformInfo(platform, what, size, value.data(), nullptr), "clGetPlatformInfo");
    return value.c_str();  // drop the terminating NUL
}

std::string deviceString(cl_device_id device, cl_device_info what) {
    std::size_t size = 0;
    check(clGetDeviceInfo(device, what, 0, nullptr, &size), "clGetDeviceInfo");
    std::string value(size, '\0');
    check(clGetDeviceInfo(device, what, size, value.data(), nullptr), "clGetDeviceInfo");
    return value.c_str();
}

template <class T>
T deviceValue(cl_device_id device, cl_device_info what) {
    T value{};
    check(clGetDeviceInfo(device, what, sizeof value, &value, nullptr), "clGetDeviceInfo");
    return value;
}

std::string typeName(cl_device_type type) {
    if (type & CL_DEVICE_TYPE_GPU) return "GPU";
    if (type & CL_DEVICE_TYPE_CPU) return "CPU";
    if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

std::string lowercase(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

const char* const kNoOpenCl =
    "install an OpenCL driver (on Debian: pocl-opencl-icd for CPUs, or your GPU vendor's), "
    "or run on the CPU (ComputeEngine::Cpu; on the command line --backend cpu)";

}  // namespace

std::string errorName(cl_int status) { return std::string(errorSymbol(status)) + " (" + std::to_string(status) + ")"; }

void check(cl_int status, const char* call) {
    if (status != CL_SUCCESS) throw Error(std::string("OpenCL: ") + call + " failed: " + errorName(status));
}

std::vector<DeviceInfo> listDevices() {
    cl_uint platformCount = 0;
    const cl_int status = clGetPlatformIDs(0, nullptr, &platformCount);
    if (status == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (status == CL_SUCCESS && platformCount == 0))
        throw Error(std::string("no OpenCL platform found: ") + kNoOpenCl);
    check(status, "clGetPlatformIDs");
    std::vector<cl_platform_id> platforms(platformCount);
    check(clGetPlatformIDs(platformCount, platforms.data(), nullptr), "clGetPlatformIDs");

    std::vector<DeviceInfo> devices;
    for (cl_platform_id platform : platforms) {
        cl_uint deviceCount = 0;
        const cl_int found = clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &deviceCount);
        if (found == CL_DEVICE_NOT_FOUND) continue;
        check(found, "clGetDeviceIDs");
        std::vector<cl_device_id> ids(deviceCount);
        check(clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, deviceCount, ids.data(), nullptr), "clGetDeviceIDs");
        const std::string platformName = platformString(platform, CL_PLATFORM_NAME);
        for (cl_device_id id : ids) {
            DeviceInfo d;
            d.index = static_cast<int>(devices.size());
            d.platform = platform;
            d.id = id;
            d.platformName = platformName;
            d.name = deviceString(id, CL_DEVICE_NAME);
            d.version = deviceString(id, CL_DEVICE_VERSION);
            d.driverVersion = deviceString(id, CL_DRIVER_VERSION);
            d.type = typeName(deviceValue<cl_device_type>(id, CL_DEVICE_TYPE));
            d.correctlyRoundedDivideSqrt = (deviceValue<cl_device_fp_config>(id, CL_DEVICE_SINGLE_FP_CONFIG) &
                                            CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
            d.globalMemoryBytes = deviceValue<cl_ulong>(id, CL_DEVICE_GLOBAL_MEM_SIZE);
            d.localMemoryBytes = deviceValue<cl_ulong>(id, CL_DEVICE_LOCAL_MEM_SIZE);
            d.computeUnits = deviceValue<cl_uint>(id, CL_DEVICE_MAX_COMPUTE_UNITS);
            devices.push_back(d);
        }
    }
    if (devices.empty()) throw Error(std::string("OpenCL platforms exist but offer no device: ") + kNoOpenCl);
    return devices;
}

bool forcedChoice(const char* variable, const std::string& yes, const std::string& no, bool otherwise) {
    const char* forced = std::getenv(variable);
    if (!forced) return otherwise;
    if (forced == yes) return true;
    if (forced == no) return false;
    throw Error(std::string(variable) + " is \"" + forced + "\"; it may be " + yes + " or " + no + " (or unset)");
}

DeviceInfo selectDevice(const std::string& selector) {
    const std::vector<DeviceInfo> devices = listDevices();
    if (selector.empty()) {
        for (const DeviceInfo& d : devices)
            if (d.type == "GPU") return d;
        return devices.front();
    }
    if (selector.find_first_not_of("0123456789") == std::string::npos && selector.size() < 10) {
        const std::size_t index = std::stoul(selector);
        if (index < devices.size()) return devices[index];
        throw Error("device " + selector + " (WorldDef::device, --device): no such device index; allowed: 0.." +
                    std::to_string(devices.size() - 1) + " (see `carom devices`)");
    }
    const std::string wanted = lowercase(selector);
    for (const DeviceInfo& d : devices)
        if (lowercase(d.name).find(wanted) != std::string::npos ||
            lowercase(d.platformName).find(wanted) != std::string::npos)
            return d;
    std::string names;
    for (const DeviceInfo& d : devices) names += "\n  [" + std::to_string(d.index) + "] " + d.name;
    throw Error(
        "device '" + selector +
        "' (WorldDef::device, --device) matches no OpenCL device; allowed: an index or part of a name:" + names);
}

Program buildProgram(cl_context context, const DeviceInfo& device, const char* source, bool exactArithmetic) {
    cl_int status = CL_SUCCESS;
    Program program(clCreateProgramWithSource(context, 1, &source, nullptr, &status));
    check(status, "clCreateProgramWithSource");
    // OpenCL C 1.2 is the level Apple offers; nothing newer may creep in.
    std::string options = "-cl-std=CL1.2";
    if (exactArithmetic) options += " -cl-fp32-correctly-rounded-divide-sqrt";
    status = clBuildProgram(program.get(), 1, &device.id, options.c_str(), nullptr, nullptr);
    if (status == CL_BUILD_PROGRAM_FAILURE) {
        std::size_t size = 0;
        clGetProgramBuildInfo(program.get(), device.id, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
        std::string log(size, '\0');
        clGetProgramBuildInfo(program.get(), device.id, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
        throw Error("OpenCL: clBuildProgram failed for " + device.name + ": " + errorName(status) + "\nbuild log:\n" +
                    log.c_str());
    }
    check(status, "clBuildProgram");
    return program;
}

Kernel createKernel(cl_program program, const char* name) {
    cl_int status = CL_SUCCESS;
    Kernel kernel(clCreateKernel(program, name, &status));
    check(status, (std::string("clCreateKernel(") + name + ")").c_str());
    return kernel;
}

namespace {

// The counts of the tracked contexts, and the share of each counted buffer
// the engine holds. A share is taken back when the engine releases the
// buffer, not when the driver frees it (after the commands that use it,
// on its own thread): so the count is the same on every run. It holds its
// count, which a context may stop tracking first.
struct BufferCount {
    unsigned long long live = 0, peak = 0;
};
struct BufferShare {
    std::shared_ptr<BufferCount> count;
    unsigned long long bytes;
};
std::mutex trackedMutex;
std::map<cl_context, std::shared_ptr<BufferCount>> tracked;
std::map<cl_mem, BufferShare> shares;

}  // namespace

cl_int releaseMem(cl_mem buffer) {
    {
        const std::lock_guard<std::mutex> lock(trackedMutex);
        if (const auto found = shares.find(buffer); found != shares.end()) {
            found->second.count->live -= found->second.bytes;
            shares.erase(found);
        }
    }
    return clReleaseMemObject(buffer);
}

Buffer createBuffer(cl_context context, std::size_t bytes, const char* what) {
    cl_int status = CL_SUCCESS;
    Buffer buffer(clCreateBuffer(context, CL_MEM_READ_WRITE, std::max<std::size_t>(bytes, 1), nullptr, &status));
    check(status, (std::string("clCreateBuffer(") + what + ", " + std::to_string(bytes) + " bytes)").c_str());
    const std::lock_guard<std::mutex> lock(trackedMutex);
    if (const auto found = tracked.find(context); found != tracked.end()) {
        BufferCount& count = *found->second;
        shares.emplace(buffer.get(), BufferShare{found->second, bytes});
        count.live += bytes;
        count.peak = std::max(count.peak, count.live);
    }
    return buffer;
}

void trackBuffers(cl_context context) {
    const std::lock_guard<std::mutex> lock(trackedMutex);
    tracked[context] = std::make_shared<BufferCount>();
}

void untrackBuffers(cl_context context) {
    const std::lock_guard<std::mutex> lock(trackedMutex);
    tracked.erase(context);
}

BufferBytes bufferBytes(cl_context context) {
    const std::lock_guard<std::mutex> lock(trackedMutex);
    const auto found = tracked.find(context);
    return found == tracked.end() ? BufferBytes{} : BufferBytes{found->second->live, found->second->peak};
}

std::size_t kernelWorkGroupLimit(cl_kernel kernel, cl_device_id device) {
    std::size_t limit = 0;
    check(clGetKernelWorkGroupInfo(kernel, device, CL_KERNEL_WORK_GROUP_SIZE, sizeof limit, &limit, nullptr),
          "clGetKernelWorkGroupInfo");
    return limit;
}

Profiler::~Profiler() {
    for (auto& [name, event] : pending_)
        if (event) clReleaseEvent(event);
}

cl_event* Profiler::slot(const char* name) {
    pending_.emplace_back(name, nullptr);
    return &pending_.back().second;
}

void Profiler::addHostSeconds(const std::string& name, double seconds) { seconds_[name] += seconds; }

void Profiler::collect() {
    for (auto& [name, event] : pending_) {
        if (!event) continue;
        cl_ulong start = 0, end = 0;
        check(clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_START, sizeof start, &start, nullptr),
              "clGetEventProfilingInfo");
        check(clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_END, sizeof end, &end, nullptr),
              "clGetEventProfilingInfo");
        seconds_[name] += double(end - start) * 1e-9;
        clReleaseEvent(event);
    }
    pending_.clear();
}

void enqueue1d(cl_command_queue queue, cl_kernel kernel, std::size_t items, std::size_t groupSize, const char* name,
               Profiler* profiler) {
    if (items == 0) return;
    const std::size_t global = (items + groupSize - 1) / groupSize * groupSize;
    check(clEnqueueNDRangeKernel(queue, kernel, 1, nullptr, &global, &groupSize, 0, nullptr, eventSlot(profiler, name)),
          (std::string("clEnqueueNDRangeKernel(") + name + ")").c_str());
}

void enqueueZero(cl_command_queue queue, cl_mem buffer, std::size_t bytes, const char* what) {
    const cl_uint zero = 0;
    check(clEnqueueFillBuffer(queue, buffer, &zero, sizeof zero, 0, bytes, 0, nullptr, nullptr),
          (std::string("clEnqueueFillBuffer(") + what + ")").c_str());
}

void enqueueCopy(cl_command_queue queue, cl_mem from, cl_mem to, std::size_t bytes, const char* what) {
    check(clEnqueueCopyBuffer(queue, from, to, 0, 0, bytes, 0, nullptr, nullptr),
          (std::string("clEnqueueCopyBuffer(") + what + ")").c_str());
}

void setLocalArg(cl_kernel kernel, cl_uint index, std::size_t bytes) {
    check(clSetKernelArg(kernel, index, bytes, nullptr), "clSetKernelArg(local)");
}

}  // namespace carom::opencl
