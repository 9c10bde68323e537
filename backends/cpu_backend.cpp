#include "backends/cpu_backend.h"

#include <cstdint>
#include <numeric>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "kernels/physics.h"

namespace carom {

CpuBackend::CpuBackend(const WorldDef& world) : Backend(world) {}

std::string CpuBackend::device() const {
#ifdef _OPENMP
    return "CPU, OpenMP with " + std::to_string(omp_get_max_threads()) + " threads";
#else
    return "CPU, single thread (built without OpenMP)";
#endif
}

void CpuBackend::load(const std::vector<Particle>& particles) {
    state_ = particles;
    next_.resize(particles.size());
    collisionCounts_.assign(particles.size(), 0);
}

void CpuBackend::step(std::uint64_t steps) {
    const auto count = static_cast<std::int64_t>(state_.size());
    const WorldDef& w = world_;
    for (std::uint64_t s = 0; s < steps; ++s) {
        buildGrid(state_.data(), state_.size(), grid_);
        const Particle* in = state_.data();
        Particle* out = next_.data();
        const unsigned int* sorted = grid_.sortedIndices.data();
        const GridCell* cells = grid_.cells.data();
        unsigned int* counts = collisionCounts_.data();
        const GridGeometry geometry = grid_.geometry;
        // resolveCollisions and integrate fused per particle: integrate only
        // reads the particle that resolveCollisions just wrote, so this equals
        // two separate passes bit for bit.
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < count; ++i) {
            carom_resolve_collisions(static_cast<unsigned int>(i), in, sorted, cells, geometry, out, counts);
            out[i] = carom_integrate(out[i], w.dt, w.gravity.x, w.gravity.y, w.width, w.height);
        }
        std::swap(state_, next_);
    }
}

std::uint64_t CpuBackend::collisions() {
    return std::accumulate(collisionCounts_.begin(), collisionCounts_.end(), std::uint64_t{0});
}

}  // namespace carom
