// The memory functions of include/carom/world.h: what is available, and the
// refusal of requests that cannot fit.
#include <carom/types.h>

#ifdef _WIN32
#define NOMINMAX
#include <windows.h>
#elif __has_include(<unistd.h>)
#include <sys/resource.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <fstream>
#include <initializer_list>
#include <string>

namespace carom {
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

// What the memory limit of this process's cgroup (v2: a container, a Slurm
// job) leaves, 0 without one. The machine's free memory says nothing of it.
std::uint64_t linuxCgroupMemoryLeft() {
    std::ifstream membership("/proc/self/cgroup");
    for (std::string line; std::getline(membership, line);) {
        if (line.rfind("0::", 0) != 0) continue;
        const std::string group = "/sys/fs/cgroup" + line.substr(3);
        std::ifstream maxFile(group + "/memory.max"), currentFile(group + "/memory.current");
        std::uint64_t max = 0, current = 0;
        if (maxFile >> max && currentFile >> current) return max > current ? max - current : 1;  // "max": none
    }
    return 0;
}
#endif

#if __has_include(<unistd.h>) && !defined(_WIN32)
// The address-space limit (ulimit -v), 0 without one.
std::uint64_t addressSpaceLimit() {
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
    return std::uint64_t(limit.rlim_cur);
}
#endif

// The smallest of the limits that are known (non-zero); 0 if none is.
std::uint64_t tightest(std::initializer_list<std::uint64_t> limits) {
    std::uint64_t least = 0;
    for (std::uint64_t limit : limits)
        if (limit > 0 && (least == 0 || limit < least)) least = limit;
    return least;
}

std::uint64_t pagesToBytes(long pages, long pageSize) {
    return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : 0;
}

// The machine's memory available now, whatever this process's limits.
std::uint64_t machineMemoryAvailable() {
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

}  // namespace

std::uint64_t availableMemoryBytes() {
#if defined(__linux__)
    return tightest({machineMemoryAvailable(), linuxCgroupMemoryLeft(), addressSpaceLimit()});
#elif __has_include(<unistd.h>) && !defined(_WIN32)
    return tightest({machineMemoryAvailable(), addressSpaceLimit()});
#else
    return machineMemoryAvailable();
#endif
}

std::uint64_t peakResidentBytes() {
#if __has_include(<unistd.h>) && !defined(_WIN32)
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss <= 0) return 0;
#ifdef __APPLE__
    return std::uint64_t(usage.ru_maxrss);  // bytes on macOS
#else
    return std::uint64_t(usage.ru_maxrss) * 1024;  // KiB on Linux and the BSDs
#endif
#else
    return 0;
#endif
}

void requireRoomFor(std::uint64_t disks, const std::string& what, std::uint64_t availableBytes,
                    std::uint64_t bytesPerDisk) {
    if (disks > kMaxParticles)
        throw Error(what + ": " + std::to_string(disks) + " particles; allowed: 1 to " + std::to_string(kMaxParticles));
    const std::uint64_t needed = disks * bytesPerDisk;
    if (availableBytes > 0 && needed > availableBytes)
        throw Error(what + ": " + std::to_string(disks) + " particles need about " + std::to_string(needed >> 20) +
                    " MiB of memory, more than the " + std::to_string(availableBytes >> 20) +
                    " MiB available; use fewer particles");
}

}  // namespace carom
