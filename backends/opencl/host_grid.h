// The OpenCL host-grid pipeline (--pipeline host-grid): each step the host builds the
// grid with the shared builder from its copy of the state, uploads it, runs
// the collision scheme's kernels (simultaneous: resolveCollisions and
// integrate, kernels/host_grid.cl; pairwise: the rounds of kernels/pairwise.cl,
// then finishStepById, kernels/host_grid.cl) and reads the new state back.
// The state stays stored by id.
#pragma once

#include "backends/opencl/backend.h"
#include "backends/opencl/pairwise.h"

namespace carom {

class OpenClHostGridBackend final : public OpenClBackend {
public:
    // See OpenClBackend.
    OpenClHostGridBackend(const WorldDef& world, const std::string& device, bool profiling = false);

    void readParticles(std::vector<Particle>& particles) override { particles = hostState_; }

private:
    const char* pipelineName() const override { return "host-grid"; }
    void releaseState() override;
    void loadState(const std::vector<Particle>& particles) override;
    void enqueueStep(float dt) override;
    float maxSpeedSquared() override { return maxSpeedSquaredOf(hostState_.data(), hostState_.size()); }
    void readLastRounds(std::vector<unsigned int>& rounds) override;
    void stepSimultaneous(float dt);
    void stepPairwise(float dt);
    void uploadGrid();  // the host's grid of hostState_

    opencl::Kernel resolveKernel_;     // resolveCollisions
    opencl::Kernel integrateKernel_;   // integrate
    opencl::Kernel finishByIdKernel_;  // pairwise: finishStepById
    std::vector<Particle> hostState_;  // the state the host builds the grid from
    opencl::Buffer sortedIndices_;     // uploaded each step
    opencl::Buffer cells_;             // uploaded each step
    opencl::Buffer cellOf_;            // pairwise: uploaded each step
    opencl::DevicePairwise pairwise_;  // pairwise
};

}  // namespace carom
