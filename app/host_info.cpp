#include "app/host_info.h"

#include <ctime>
#include <fstream>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace carom::app {

std::string utcNow() {
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return text;
}

std::string hostCpu() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

double hostLoad() {
    std::ifstream loadavg("/proc/loadavg");
    double load = -1;
    loadavg >> load;
    return loadavg ? load : -1;
}

int hostThreads() {
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

}  // namespace carom::app
