#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "backends/backend.h"
#include "engine/atomic_file.h"
#include "engine/diagnostics.h"
#include "engine/state_csv.h"

namespace carom::app {

void addRunOptions(CLI::App& command, RunOptions& o) {
    addSceneOptions(command, o.scene);
    command.add_option("--steps", o.steps, "Number of steps")->capture_default_str();
    command.add_option("--output-state", o.outputState, "Write the final state to this CSV");
    command.add_flag("--json", o.json, "Print a JSON summary on stdout instead of the text summary");
}

namespace {

nlohmann::json pair(double x, double y) { return nlohmann::json::array({x, y}); }

void printSummary(const Backend& backend, std::uint64_t steps, double seconds, const Diagnostics& initial,
                  const Diagnostics& final, std::uint64_t collisions) {
    const WorldDef& w = backend.world();
    const double energyChange = initial.kineticEnergy > 0
                                    ? (final.kineticEnergy - initial.kineticEnergy) / initial.kineticEnergy
                                    : 0.0;
    std::printf("carom run: %zu disks, %llu steps of dt %g in a %g x %g box\n", backend.particleCount(),
                static_cast<unsigned long long>(steps), w.dt, w.width, w.height);
    std::printf("  backend      %s on %s\n", backend.name().c_str(), backend.device().c_str());
    std::printf("  wall time    %.3f s, %.3g particle-steps/s\n", seconds,
                seconds > 0 ? double(backend.particleCount()) * steps / seconds : 0.0);
    std::printf("  energy       %.9g -> %.9g (relative change %+.2e)\n", initial.kineticEnergy, final.kineticEnergy,
                energyChange);
    std::printf("  momentum     (%.6g, %.6g) -> (%.6g, %.6g)\n", initial.momentum[0], initial.momentum[1],
                final.momentum[0], final.momentum[1]);
    std::printf("  collisions   %llu, max overlap %.3g, escaped %zu\n", static_cast<unsigned long long>(collisions),
                final.maxOverlap, final.escaped);
}

}  // namespace

int runCommand(const RunOptions& o) {
    const Setup setup = makeSetup(o.scene);
    // Refuse an unwritable output path before the simulation, not after it.
    std::optional<AtomicFile> outputProbe;
    if (!o.outputState.empty()) outputProbe.emplace(o.outputState);
    outputProbe.reset();

    std::unique_ptr<Backend> backend = makeBackend(o.scene.backend, setup.world);
    backend->setParticles(setup.particles);
    const Diagnostics initial = measure(setup.particles, setup.world);

    std::vector<Particle> particles;
    const auto start = std::chrono::steady_clock::now();
    backend->step(o.steps);
    backend->readParticles(particles);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const Diagnostics final = measure(particles, setup.world);
    const std::uint64_t collisions = backend->collisions();
    if (!o.outputState.empty()) writeStateCsv(o.outputState, particles);
    if (final.escaped > 0)
        std::cerr << "carom: warning: " << final.escaped
                  << " particles left the box or became non-finite: the step is unstable at this dt "
                     "(try a smaller --dt)\n";

    if (!o.json) {
        printSummary(*backend, o.steps, seconds, initial, final, collisions);
        return 0;
    }
    const WorldDef& w = setup.world;
    const nlohmann::json summary = {
        {"backend", backend->name()},
        {"device", backend->device()},
        {"exact_arithmetic", backend->exactArithmetic()},
        {"particles", particles.size()},
        {"steps", o.steps},
        {"dt", w.dt},
        {"box", pair(w.width, w.height)},
        {"gravity", pair(w.gravity.x, w.gravity.y)},
        {"wall_seconds", seconds},
        {"particle_steps_per_second", seconds > 0 ? double(particles.size()) * o.steps / seconds : 0.0},
        {"kinetic_energy", {{"initial", initial.kineticEnergy}, {"final", final.kineticEnergy}}},
        {"momentum",
         {{"initial", pair(initial.momentum[0], initial.momentum[1])},
          {"final", pair(final.momentum[0], final.momentum[1])}}},
        {"collisions", collisions},
        {"max_overlap", final.maxOverlap},
        {"escaped", final.escaped},
    };
    std::cout << summary.dump(2) << '\n';
    return 0;
}

}  // namespace carom::app
