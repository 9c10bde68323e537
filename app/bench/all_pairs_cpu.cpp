#include "app/bench/all_pairs_cpu.h"

#include <utility>

#include "kernels/physics.h"

namespace carom::bench {

AllPairsCpuBackend::AllPairsCpuBackend(const WorldDef& world) : CpuBackend(world) {
    if (world.collisions != CollisionScheme::Simultaneous)
        throw Error("the all-pairs baseline runs the simultaneous scheme only");
}

std::uint64_t AllPairsCpuBackend::advance(std::uint64_t substeps, float dt) {
    const auto count = static_cast<std::int64_t>(state_->size());
    const WorldDef& w = world_;
    const CaromBox box = caromBoxOf(w);
    for (std::uint64_t s = 0; s < substeps; ++s) {
        const Particle* in = state_->data();
        Particle* out = next_->data();
        ContactTally* tallies = tallies_.data();
        // Rows of the N x N pair matrix cost the same: a static schedule balances them.
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < count; ++i) {
            const auto id = static_cast<unsigned int>(i);
            const CaromResponse sum =
                carom_collect_response_all_pairs(id, in[i], in, static_cast<unsigned int>(count), box);
            out[i] = carom_apply_response(in[i], sum);
            carom_record_collisions(&tallies[i], sum);
            carom_integrate_into(id, out, dt, w.gravity.x, w.gravity.y, box, tallies);
        }
        std::swap(state_, next_);
    }
    return substeps;
}

}  // namespace carom::bench
