#include "backends/cpu_backend.h"

#include <cstdint>
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
    tallies_.assign(particles.size(), ContactTally{});
}

void CpuBackend::advance(std::uint64_t substeps, float dt) {
    const auto count = static_cast<std::int64_t>(state_.size());
    const WorldDef& w = world_;
    const CaromBox box = caromBoxOf(w);
    for (std::uint64_t s = 0; s < substeps; ++s) {
        buildGrid(state_.data(), state_.size(), grid_);
        const Particle* in = state_.data();
        Particle* out = next_.data();
        const unsigned int* sorted = grid_.sortedIndices.data();
        const GridCell* cells = grid_.cells.data();
        ContactTally* tallies = tallies_.data();
        const GridGeometry geometry = grid_.geometry;
        // resolveCollisions and integrate fused per particle: integrate only
        // reads the particle that resolveCollisions just wrote, so this equals
        // two separate passes bit for bit.
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < count; ++i) {
            const auto id = static_cast<unsigned int>(i);
            carom_resolve_collisions(id, in, sorted, cells, geometry, box, out, tallies);
            carom_integrate_into(id, out, dt, w.gravity.x, w.gravity.y, box, tallies);
        }
        std::swap(state_, next_);
    }
}

}  // namespace carom
