// The naive baseline of `carom bench` on the CPU: every particle checks
// every other one, O(N^2) per step, with the per-pair physics of
// kernels/physics.h and OpenMP over particles. It finds the same pairs as the
// grid search but sums them in id order, so it is not bitwise equal to it.
// The CPU backend with another step (the simultaneous scheme only).
#pragma once

#include "backends/cpu.h"

namespace carom::bench {

class AllPairsCpuBackend final : public CpuBackend {
public:
    explicit AllPairsCpuBackend(const WorldDef& world);

    std::string device() const override { return CpuBackend::device() + ", all pairs"; }

private:
    std::uint64_t advance(std::uint64_t substeps, float dt) override;
};

}  // namespace carom::bench
