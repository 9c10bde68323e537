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

// Both in parallel (engine/disk_conversion.cpp).
std::vector<Particle> particlesOf(const Disk* disks, std::size_t count);
std::vector<Disk> disksOf(const std::vector<Particle>& particles);

}  // namespace carom
