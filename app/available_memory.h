// How much memory carom may count on before it allocates a large request.
#pragma once

#include <cstdint>

namespace carom::app {

// The memory available to a new allocation now, in bytes: Linux's
// MemAvailable (free memory plus the caches it can drop), else the free
// physical pages, else (macOS) the physical memory; Windows' available
// physical memory. Less where the process is limited: what its cgroup's
// memory.max leaves (Linux, cgroup v2: containers, Slurm jobs) and the
// address-space limit (ulimit -v). 0 where none of these is known.
std::uint64_t availableMemoryBytes();

}  // namespace carom::app
