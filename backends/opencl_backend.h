// The OpenCL backend, seed pipeline: each step the host builds the grid with
// the shared builder from its copy of the state, uploads it, runs the
// resolveCollisions and integrate kernels (kernels/step.cl) and reads the new
// state back.
#pragma once

#include "backends/backend.h"
#include "backends/opencl_runtime.h"

namespace carom {

class OpenClBackend final : public Backend {
public:
    // `device`: see opencl::selectDevice.
    OpenClBackend(const WorldDef& world, const std::string& device);

    std::string name() const override { return "opencl"; }
    std::string device() const override;
    bool exactArithmetic() const override { return device_.correctlyRoundedDivideSqrt; }

    void step(std::uint64_t steps) override;
    void readParticles(std::vector<Particle>& particles) override { particles = hostState_; }
    std::uint64_t collisions() override;

private:
    void load(const std::vector<Particle>& particles) override;
    std::size_t globalSize() const;

    opencl::DeviceInfo device_;
    opencl::Context context_;
    opencl::Queue queue_;
    opencl::Program program_;
    opencl::Kernel resolveKernel_;
    opencl::Kernel integrateKernel_;
    std::size_t workGroupSize_ = 64;

    std::vector<Particle> hostState_;  // the state the host builds the grid from
    opencl::Buffer state_;             // the state before the step
    opencl::Buffer next_;              // written by the step, then swapped in
    opencl::Buffer sortedIndices_;
    opencl::Buffer cells_;
    opencl::Buffer collisionCounts_;
};

}  // namespace carom
