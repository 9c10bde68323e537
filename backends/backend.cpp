#include "backends/backend.h"

#include <algorithm>

#include "backends/cpu_backend.h"
#ifdef CAROM_HAVE_OPENCL
#include "backends/opencl_backend.h"
#endif

namespace carom {

Backend::Backend(const WorldDef& world) : world_(world) { validate(world_); }

void Backend::setParticles(const std::vector<Particle>& particles) {
    validateParticles(particles, world_, "particles");
    float maxRadius = 0.0f;
    for (const Particle& p : particles) maxRadius = std::max(maxRadius, p.radius);
    grid_.geometry = gridGeometryFor(world_.width, world_.height, maxRadius, particles.size());
    particleCount_ = particles.size();
    load(particles);
}

void Backend::setMotion(float dt, float2 gravity) {
    WorldDef changed = world_;
    changed.dt = dt;
    changed.gravity = gravity;
    validate(changed);
    world_ = changed;
}

std::vector<std::string> availableBackends() {
#ifdef CAROM_HAVE_OPENCL
    return {"cpu", "opencl"};
#else
    return {"cpu"};
#endif
}

std::unique_ptr<Backend> makeBackend(const BackendDef& def, const WorldDef& world) {
    if (def.kind == "cpu") {
        if (def.pipeline != "seed")
            throw Error("--pipeline " + def.pipeline + " needs --backend opencl; the CPU backend has one pipeline");
        return std::make_unique<CpuBackend>(world);
    }
#ifdef CAROM_HAVE_OPENCL
    if (def.kind == "opencl") return std::make_unique<OpenClBackend>(world, def.device, parsePipeline(def.pipeline));
#else
    if (def.kind == "opencl")
        throw Error("this carom was built without OpenCL (no OpenCL headers or loader were found); "
                    "use --backend cpu");
#endif
    throw Error("unknown backend '" + def.kind + "'; allowed: cpu, opencl");
}

}  // namespace carom
