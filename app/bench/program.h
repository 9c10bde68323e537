// The OpenCL C source of kernels/bench.cl, the kernels of `carom bench`
// only, embedded at build time (kernels/embed.cmake) into the carom_bench
// library: the production program (backends/opencl/program.h) has none of them.
#pragma once

namespace carom::bench {
const char* kernelSource();
}
