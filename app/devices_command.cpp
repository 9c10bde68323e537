#include <cstdio>

#include "app/commands.h"
#ifdef CAROM_HAVE_OPENCL
#include "backends/opencl_runtime.h"
#endif

namespace carom::app {

int devicesCommand() {
#ifdef CAROM_HAVE_OPENCL
    for (const opencl::DeviceInfo& d : opencl::listDevices()) {
        std::printf("[%d] %s\n    platform %s, %s, %s, %.1f GiB, correctly rounded divide/sqrt: %s\n", d.index,
                    d.name.c_str(), d.platformName.c_str(), d.type.c_str(), d.version.c_str(),
                    d.globalMemoryBytes / 1073741824.0, d.correctlyRoundedDivideSqrt ? "yes" : "no");
    }
    return 0;
#else
    throw Error("this carom was built without OpenCL; only --backend cpu is available");
#endif
}

}  // namespace carom::app
