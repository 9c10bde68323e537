#include "bench/all_pairs_cpu.h"

#include <numeric>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "kernels/physics.h"

namespace carom::bench {

std::string AllPairsCpuBackend::device() const {
#ifdef _OPENMP
    return "CPU, OpenMP with " + std::to_string(omp_get_max_threads()) + " threads, all pairs";
#else
    return "CPU, single thread, all pairs";
#endif
}

void AllPairsCpuBackend::load(const std::vector<Particle>& particles) {
    state_ = particles;
    next_.resize(particles.size());
    collisionCounts_.assign(particles.size(), 0);
}

void AllPairsCpuBackend::step(std::uint64_t steps) {
    const auto count = static_cast<std::int64_t>(state_.size());
    const WorldDef& w = world_;
    for (std::uint64_t s = 0; s < steps; ++s) {
        const Particle* in = state_.data();
        Particle* out = next_.data();
        unsigned int* counts = collisionCounts_.data();
        // Rows of the N x N pair matrix cost the same: a static schedule balances them.
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < count; ++i) {
            const auto id = static_cast<unsigned int>(i);
            const CaromResponse sum = carom_collect_response_all_pairs(id, in[i], in, static_cast<unsigned int>(count));
            out[i] = carom_integrate(carom_apply_response(in[i], sum), w.dt, w.gravity.x, w.gravity.y, w.width,
                                     w.height);
            counts[i] += sum.impulses;
        }
        std::swap(state_, next_);
    }
}

std::uint64_t AllPairsCpuBackend::collisions() {
    return std::accumulate(collisionCounts_.begin(), collisionCounts_.end(), std::uint64_t{0});
}

}  // namespace carom::bench
