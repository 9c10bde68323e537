// How much memory carom may count on before it allocates a large request.
#pragma once

#include <cstdint>

namespace carom::app {

// The memory available to a new allocation now, in bytes: Linux's
// MemAvailable (free memory plus the caches it can drop), else the free
// physical pages, else (macOS) the physical memory; Windows' available
// physical memory. 0 where the platform does not say.
std::uint64_t availableMemoryBytes();

}  // namespace carom::app
