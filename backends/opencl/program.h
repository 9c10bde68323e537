// The OpenCL C source of kernels/, embedded at build time
// (kernels/embed.cmake), so carom runs from any directory.
#pragma once

namespace carom::opencl {
const char* kernelSource();
}
