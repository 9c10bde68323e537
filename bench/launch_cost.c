/* What a kernel launch costs the host on an OpenCL device, by the kinds of
 * arguments the kernel takes: docs/architecture.md explains with it why a
 * pairwise step's lists share one buffer. Not part of the build:
 *   cc bench/launch_cost.c -lOpenCL -o /tmp/launch && /tmp/launch [PLATFORM]
 * It enqueues 4 000 launches of one work-group of a kernel that does nothing,
 * back to back, for each set of arguments, and prints the time per launch of
 * the second of two runs: the enqueues alone, and until the queue finished.
 * PLATFORM (default NVIDIA) is part of the OpenCL platform's name. */
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

enum { kBuffers = 20, kLaunches = 4000 };

static const char* kSource =
    "typedef struct { uint v[16]; } Block;\n"
    "__kernel void scalars(__global uint* a, uint b, uint c, uint d, uint e, uint f, uint g, uint h, uint i, uint j,"
    " uint k, uint l, uint m, uint n, uint o, uint p, uint q, uint r, uint s, uint t)"
    " { if (get_global_id(0) == 100000u) a[0] = b + c + d + e + f + g + h + i + j + k + l + m + n + o + p + q + r + s"
    " + t; }\n"
    "__kernel void buffers4(__global uint* a, __global uint* b, __global uint* c, __global uint* d)"
    " { if (get_global_id(0) == 100000u) a[0] = b[0] + c[0] + d[0]; }\n"
    "__kernel void buffers20(__global uint* a, __global uint* b, __global uint* c, __global uint* d, __global uint* e,"
    " __global uint* f, __global uint* g, __global uint* h, __global uint* i, __global uint* j, __global uint* k,"
    " __global uint* l, __global uint* m, __global uint* n, __global uint* o, __global uint* p, __global uint* q,"
    " __global uint* r, __global uint* s, __global uint* t)"
    " { if (get_global_id(0) == 100000u) a[0] = b[0] + c[0] + d[0] + e[0] + f[0] + g[0] + h[0] + i[0] + j[0] + k[0]"
    " + l[0] + m[0] + n[0] + o[0] + p[0] + q[0] + r[0] + s[0] + t[0]; }\n"
    "__kernel void block(__global uint* a, Block b) { if (get_global_id(0) == 100000u) a[0] = b.v[3]; }\n";

int main(int argc, char** argv) {
    const char* wanted = argc > 1 ? argv[1] : "NVIDIA";
    cl_platform_id platforms[8];
    cl_uint platformCount = 0;
    clGetPlatformIDs(8, platforms, &platformCount);
    cl_device_id device = 0;
    for (cl_uint p = 0; p < platformCount && !device; ++p) {
        char name[256] = "";
        clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof name, name, 0);
        if (strstr(name, wanted)) clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 1, &device, 0);
    }
    if (!device) {
        fprintf(stderr, "launch_cost: no OpenCL platform named like '%s'\n", wanted);
        return 1;
    }
    cl_int err;
    cl_context context = clCreateContext(0, 1, &device, 0, 0, &err);
    cl_program program = clCreateProgramWithSource(context, 1, &kSource, 0, &err);
    if (clBuildProgram(program, 1, &device, "", 0, 0) != CL_SUCCESS) {
        fprintf(stderr, "launch_cost: the kernels do not build\n");
        return 1;
    }
    cl_mem buffers[kBuffers];
    for (int b = 0; b < kBuffers; ++b) buffers[b] = clCreateBuffer(context, CL_MEM_READ_WRITE, 1 << 20, 0, &err);
    cl_command_queue queue = clCreateCommandQueue(context, device, 0, &err);
    const char* kernels[] = {"scalars", "buffers4", "buffers20", "block"};
    const char* what[] = {"1 buffer, 19 uints", "4 buffers", "20 buffers", "1 buffer, a 64-byte struct"};
    for (int v = 0; v < 4; ++v) {
        cl_kernel kernel = clCreateKernel(program, kernels[v], &err);
        clSetKernelArg(kernel, 0, sizeof(cl_mem), &buffers[0]);
        const int buffersUsed = v == 1 ? 4 : v == 2 ? kBuffers : 1;
        for (int a = 1; a < buffersUsed; ++a) clSetKernelArg(kernel, a, sizeof(cl_mem), &buffers[a]);
        const cl_uint values[16] = {0};
        if (v == 0)
            for (int a = 1; a < 20; ++a) clSetKernelArg(kernel, a, sizeof(cl_uint), &values[0]);
        if (v == 3) clSetKernelArg(kernel, 1, sizeof values, values);
        const size_t items = 64;
        for (int run = 0; run < 2; ++run) {
            clFinish(queue);
            const double start = now();
            for (int i = 0; i < kLaunches; ++i) clEnqueueNDRangeKernel(queue, kernel, 1, 0, &items, &items, 0, 0, 0);
            const double enqueued = now() - start;
            clFinish(queue);
            const double finished = now() - start;
            if (run == 1)
                printf("%-28s %5.2f us a launch to enqueue, %5.2f us until finished\n", what[v],
                       1e6 * enqueued / kLaunches, 1e6 * finished / kLaunches);
        }
        clReleaseKernel(kernel);
    }
    return 0;
}
