/* The largest work-group OpenCL gives each kernel, against the device's own
 * limit: bench/results/nvidia-h200-small-system.txt explains carom's 256 on
 * NVIDIA's driver with it. Not part of the build:
 *   cc bench/work_group_limit.c -lOpenCL -o /tmp/wg && /tmp/wg [kernels/program.cl]
 * Without an argument it builds five one-line kernels under four sets of
 * options; with a file it builds that (with -Ikernels and carom's options,
 * plus -cl-nv-verbose on NVIDIA, whose log gives each kernel's registers). */
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* kTrivial =
    "__kernel void plain(__global float* a) { a[get_global_id(0)] += 1.0f; }\n"
    "__kernel void withLocal(__global float* a, __local float* s) { s[get_local_id(0)] = a[get_global_id(0)];"
    " barrier(CLK_LOCAL_MEM_FENCE); a[get_global_id(0)] = s[get_local_size(0) - 1 - get_local_id(0)]; }\n"
    "__kernel void withAtomic(__global uint* a) { atomic_inc(a); }\n"
    "__kernel void withDivide(__global float* a) { a[get_global_id(0)] = sqrt(a[get_global_id(0)]) / a[0]; }\n"
    "__kernel __attribute__((reqd_work_group_size(1024, 1, 1))) void required1024(__global float* a)"
    " { a[get_global_id(0)] += 1.0f; }\n";

static void report(cl_context context, cl_device_id device, const char* source, const char* options) {
    cl_program program = clCreateProgramWithSource(context, 1, &source, NULL, NULL);
    const cl_int status = clBuildProgram(program, 1, &device, options, NULL, NULL);
    size_t size = 0;
    clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, NULL, &size);
    char* log = malloc(size + 1);
    clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, log, NULL);
    log[size] = '\0';
    printf(" options '%s': build %d\n%s\n", options, status, strstr(options, "nv-verbose") || status ? log : "");
    free(log);
    cl_kernel kernels[64];
    cl_uint count = 0;
    if (status == CL_SUCCESS) clCreateKernelsInProgram(program, 64, kernels, &count);
    for (cl_uint k = 0; k < count; ++k) {
        char name[128];
        size_t limit = 0;
        clGetKernelInfo(kernels[k], CL_KERNEL_FUNCTION_NAME, sizeof name, name, NULL);
        clGetKernelWorkGroupInfo(kernels[k], device, CL_KERNEL_WORK_GROUP_SIZE, sizeof limit, &limit, NULL);
        printf("  %s: CL_KERNEL_WORK_GROUP_SIZE %zu\n", name, limit);
        clReleaseKernel(kernels[k]);
    }
    clReleaseProgram(program);
}

static char* readFile(const char* path) {
    FILE* file = fopen(path, "rb");
    if (!file) return NULL;
    fseek(file, 0, SEEK_END);
    const long length = ftell(file);
    fseek(file, 0, SEEK_SET);
    char* text = malloc((size_t)length + 1);
    text[fread(text, 1, (size_t)length, file)] = '\0';
    fclose(file);
    return text;
}

int main(int argc, char** argv) {
    char* source = argc > 1 ? readFile(argv[1]) : NULL;
    if (argc > 1 && !source) {
        fprintf(stderr, "work_group_limit: cannot read '%s'; give an OpenCL C file or nothing\n", argv[1]);
        return 2;
    }
    cl_platform_id platforms[8];
    cl_uint platformCount = 0;
    clGetPlatformIDs(8, platforms, &platformCount);
    for (cl_uint p = 0; p < platformCount; ++p) {
        cl_device_id device;
        if (clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 1, &device, NULL) != CL_SUCCESS) continue;
        char name[256], driver[256];
        size_t limit = 0;
        clGetDeviceInfo(device, CL_DEVICE_NAME, sizeof name, name, NULL);
        clGetDeviceInfo(device, CL_DRIVER_VERSION, sizeof driver, driver, NULL);
        clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof limit, &limit, NULL);
        printf("%s (driver %s): CL_DEVICE_MAX_WORK_GROUP_SIZE %zu\n", name, driver, limit);
        cl_context context = clCreateContext(NULL, 1, &device, NULL, NULL, NULL);
        if (source) {
            const int nvidia = strstr(name, "NVIDIA") != NULL;
            report(context, device, source,
                   nvidia ? "-Ikernels -cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt -cl-nv-verbose"
                          : "-Ikernels -cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt");
        } else {
            const char* options[] = {"", "-cl-std=CL1.2", "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt",
                                     "-cl-std=CL3.0"};
            for (int o = 0; o < 4; ++o) report(context, device, kTrivial, options[o]);
        }
        clReleaseContext(context);
    }
    free(source);
    return 0;
}
