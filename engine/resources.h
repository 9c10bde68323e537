// Requests that cannot fit are refused before anything is allocated.
#pragma once

#include <cstdint>

namespace carom {

// Host memory a run needs per particle, about: the initial particles, the
// backend's two state buffers, the read-back copy, the grid (ids and up to 4
// cells per particle) and the diagnostics' own grid.
constexpr std::uint64_t kHostBytesPerParticle = 256;

// Throws Error if `particles` exceeds kMaxParticles or, when availableBytes
// > 0 (0: unknown), its estimated host memory exceeds availableBytes (the
// command line passes the memory available now: app/available_memory.h).
// `what` names the request in the message (a file, an option).
void requireRoomFor(std::uint64_t particles, std::uint64_t availableBytes, const char* what);

}  // namespace carom
