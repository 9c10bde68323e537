#include "engine/resources.h"

#include <string>

#include "engine/carom.h"

namespace carom {

void requireRoomFor(std::uint64_t particles, std::uint64_t availableBytes, const char* what) {
    if (particles > kMaxParticles)
        throw Error(std::string(what) + ": " + std::to_string(particles) + " particles; allowed: 1 to " +
                    std::to_string(kMaxParticles));
    const std::uint64_t needed = particles * kHostBytesPerParticle;
    if (availableBytes > 0 && needed > availableBytes)
        throw Error(std::string(what) + ": " + std::to_string(particles) + " particles need about " +
                    std::to_string(needed >> 20) + " MiB of memory, more than the " +
                    std::to_string(availableBytes >> 20) + " MiB available; use fewer particles");
}

}  // namespace carom
