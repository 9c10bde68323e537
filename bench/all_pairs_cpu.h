// The naive baseline of `carom bench` on the CPU: every particle checks
// every other one, O(N^2) per step, with the per-pair physics of
// kernels/physics.h and OpenMP over particles. It finds the same pairs as the
// grid search but sums them in id order, so it is not bitwise equal to it.
#pragma once

#include "backends/backend.h"

namespace carom::bench {

class AllPairsCpuBackend final : public Backend {
public:
    explicit AllPairsCpuBackend(const WorldDef& world) : Backend(world) {}

    std::string name() const override { return "cpu"; }
    std::string device() const override;
    bool exactArithmetic() const override { return true; }

    void readParticles(std::vector<Particle>& particles) override { particles = state_; }

private:
    void load(std::vector<Particle> particles) override;
    void advance(std::uint64_t substeps, float dt) override;
    float maxSpeedSquared() override { return maxSpeedSquaredOf(state_.data(), state_.size()); }
    void drainTallies(ContactTotals& totals) override { drainTallyArray(tallies_.data(), tallies_.size(), totals); }

    std::vector<Particle> state_;
    std::vector<Particle> next_;
    std::vector<ContactTally> tallies_;
};

}  // namespace carom::bench
