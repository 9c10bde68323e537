// The OpenMP CPU backend: the shared grid builder, then resolveCollisions and
// integrate from kernels/physics.h in one parallel loop over particles.
#pragma once

#include "backends/backend.h"

namespace carom {

class CpuBackend final : public Backend {
public:
    explicit CpuBackend(const WorldDef& world);

    std::string name() const override { return "cpu"; }
    std::string device() const override;
    bool exactArithmetic() const override { return true; }

    void readParticles(std::vector<Particle>& particles) override { particles = state_; }

private:
    void load(const std::vector<Particle>& particles) override;
    void advance(std::uint64_t substeps, float dt) override;
    float maxSpeedSquared() override { return maxSpeedSquaredOf(state_.data(), state_.size()); }
    void drainTallies(ContactTotals& totals) override { drainTallyArray(tallies_.data(), tallies_.size(), totals); }

    std::vector<Particle> state_;  // the state before the step
    std::vector<Particle> next_;   // written by the step, then swapped in
    std::vector<ContactTally> tallies_;  // by particle id
};

}  // namespace carom
