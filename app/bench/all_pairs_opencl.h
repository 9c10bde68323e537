// The naive baseline of `carom bench` on the OpenCL device: every particle
// checks every other one, O(N^2) per step (resolveAllPairs, kernels/bench.cl),
// then integrate as in the host-grid pipeline; the state stays on the device,
// stored by id. It finds the same pairs as the grid search but sums them in
// id order, so it is not bitwise equal to it. Simultaneous scheme only.
#pragma once

#include "backends/opencl/backend.h"

namespace carom::bench {

class AllPairsOpenClBackend final : public OpenClBackend {
public:
    // See OpenClBackend; the program is built from kernels/bench.cl.
    AllPairsOpenClBackend(const WorldDef& world, const std::string& device, bool profiling = false);

private:
    const char* pipelineName() const override { return "all-pairs"; }
    void releaseState() override {}
    void loadState(const std::vector<Particle>&) override {}
    void enqueueStep(float dt) override;

    opencl::Kernel allPairsKernel_;   // resolveAllPairs
    opencl::Kernel integrateKernel_;  // integrate
};

}  // namespace carom::bench
