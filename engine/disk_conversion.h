// Between the public carom::Disk and the engine's Particle (kernels/particle.h),
// which adds the pairwise scheme's per-step fields and the GPU alignment.
#pragma once

#include <cstddef>
#include <vector>

#include <carom/types.h>

#include "kernels/particle.h"

namespace carom {

inline Particle particleOf(const Disk& d) {
    Particle p{};
    p.position = d.position;
    p.velocity = d.velocity;
    p.mass = d.mass;
    p.radius = d.radius;
    return p;
}

inline Disk diskOf(const Particle& p) { return Disk{p.position, p.velocity, p.mass, p.radius}; }

inline std::vector<Particle> particlesOf(const Disk* disks, std::size_t count) {
    std::vector<Particle> particles(count);
    for (std::size_t i = 0; i < count; ++i) particles[i] = particleOf(disks[i]);
    return particles;
}

inline std::vector<Disk> disksOf(const std::vector<Particle>& particles) {
    std::vector<Disk> disks(particles.size());
    for (std::size_t i = 0; i < particles.size(); ++i) disks[i] = diskOf(particles[i]);
    return disks;
}

}  // namespace carom
