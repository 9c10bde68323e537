#include "app/available_memory.h"

#ifdef _WIN32
#define NOMINMAX
#include <windows.h>
#elif __has_include(<unistd.h>)
#include <unistd.h>
#endif

#include <fstream>
#include <string>

namespace carom::app {
namespace {

#ifdef __linux__
// MemAvailable from /proc/meminfo (Linux 3.14 and later), 0 if absent. Free
// pages alone would count the page cache as used and refuse runs that fit.
std::uint64_t linuxMemAvailable() {
    std::ifstream meminfo("/proc/meminfo");
    for (std::string key; meminfo >> key;) {
        std::uint64_t kib = 0;
        if (key == "MemAvailable:" && meminfo >> kib) return kib * 1024;
        meminfo.ignore(256, '\n');
    }
    return 0;
}
#endif

std::uint64_t pagesToBytes(long pages, long pageSize) {
    return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : 0;
}

}  // namespace

std::uint64_t availableMemoryBytes() {
#ifdef _WIN32
    MEMORYSTATUSEX status{};
    status.dwLength = sizeof status;
    return GlobalMemoryStatusEx(&status) ? status.ullAvailPhys : 0;
#else
#ifdef __linux__
    if (const std::uint64_t available = linuxMemAvailable()) return available;
#endif
#if defined(_SC_AVPHYS_PAGES) && defined(_SC_PAGESIZE)
    if (const std::uint64_t free = pagesToBytes(sysconf(_SC_AVPHYS_PAGES), sysconf(_SC_PAGESIZE))) return free;
#endif
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
    return pagesToBytes(sysconf(_SC_PHYS_PAGES), sysconf(_SC_PAGESIZE));
#else
    return 0;
#endif
#endif
}

}  // namespace carom::app
