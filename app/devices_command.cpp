#include <cstdio>

#include <carom/world.h>

#include "app/commands.h"

namespace carom::app {

int devicesCommand() {
    if (!engineAvailable(ComputeEngine::OpenClHostGrid))
        throw Error("this carom was built without OpenCL; only --backend cpu is available");
    const std::vector<Device> devices = listDevices();
    for (const Device& d : devices) {
        std::printf("[%d] %s\n    platform %s, %s, %s, %.1f GiB, correctly rounded divide/sqrt: %s\n", d.index,
                    d.name.c_str(), d.platform.c_str(), d.type.c_str(), d.version.c_str(),
                    double(d.memoryBytes) / 1073741824.0, d.correctlyRoundedDivideSqrt ? "yes" : "no");
    }
    const EngineChoice choice = chooseEngine(devices);
    std::printf("--backend auto picks %s: %s\n", choice.engine.engine == ComputeEngine::Cpu ? "cpu" : "opencl",
                choice.reason.c_str());
    return 0;
}

}  // namespace carom::app
