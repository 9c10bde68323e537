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

    void step(std::uint64_t steps) override;
    void readParticles(std::vector<Particle>& particles) override { particles = state_; }
    std::uint64_t collisions() override;

private:
    void load(const std::vector<Particle>& particles) override;

    std::vector<Particle> state_;  // the state before the step
    std::vector<Particle> next_;   // written by the step, then swapped in
    std::vector<unsigned int> collisionCounts_;
};

}  // namespace carom
