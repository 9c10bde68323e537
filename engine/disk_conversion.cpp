#include "engine/disk_conversion.h"

#include "engine/parallel.h"

namespace carom {

std::vector<Particle> particlesOf(const Disk* disks, std::size_t count) {
    std::vector<Particle> particles(count);
    parallelFor(count, [&](std::size_t i) { particles[i] = particleOf(disks[i]); });
    return particles;
}

std::vector<Disk> disksOf(const std::vector<Particle>& particles) {
    std::vector<Disk> disks(particles.size());
    parallelFor(disks.size(), [&](std::size_t i) { disks[i] = diskOf(particles[i]); });
    return disks;
}

}  // namespace carom
