#include "app/scene_options.h"

#include "backends/backend.h"
#include "engine/state_csv.h"

namespace carom::app {

void addSceneOptions(CLI::App& command, SceneOptions& o) {
    const std::vector<std::string> backends = availableBackends();
    o.backend.kind = backends.back();  // OpenCL when this build has it
    command.add_option("--backend", o.backend.kind, "Compute backend")
        ->check(CLI::IsMember(backends))
        ->capture_default_str();
    command.add_option("--device", o.backend.device,
                       "OpenCL device: index from `carom devices` or part of its name (default: first GPU, "
                       "else first device)");

    auto* particles = command.add_option("--particles", o.scene.particles, "Number of disks")->capture_default_str();
    auto* packing = command.add_option("--packing", o.scene.packing, "Area fraction of the disks; sizes a square box")
                        ->capture_default_str();
    auto* box = command.add_option("--box", o.box, "Box size W H: the world is [0,W]x[0,H]")->expected(2);
    packing->excludes(box);

    auto* radius = command.add_option_function<float>(
        "--radius", [&o](float r) { o.scene.radiusMin = o.scene.radiusMax = r; }, "Radius of every disk (default 1)");
    auto* radiusMin = command.add_option("--radius-min", o.scene.radiusMin, "Smallest radius (uniform range)");
    auto* radiusMax = command.add_option("--radius-max", o.scene.radiusMax, "Largest radius (uniform range)");
    radius->excludes(radiusMin)->excludes(radiusMax);
    radiusMin->needs(radiusMax);
    radiusMax->needs(radiusMin);

    auto* mass = command.add_option_function<float>(
        "--mass", [&o](float m) { o.scene.massMin = o.scene.massMax = m; }, "Mass of every disk (default 1)");
    auto* massMin = command.add_option("--mass-min", o.scene.massMin, "Smallest mass (uniform range)");
    auto* massMax = command.add_option("--mass-max", o.scene.massMax, "Largest mass (uniform range)");
    mass->excludes(massMin)->excludes(massMax);
    massMin->needs(massMax);
    massMax->needs(massMin);

    auto* speed = command.add_option("--speed", o.scene.speed, "Initial speed of every disk, random directions")
                      ->capture_default_str();
    auto* seed = command.add_option("--seed", o.scene.seed, "Random seed")->capture_default_str();
    command.add_option("--dt", o.world.dt, "Time step")->capture_default_str();
    command.add_option("--gravity", o.gravity, "Constant acceleration GX GY (default off)")->expected(2);

    auto* input = command.add_option("--input-state", o.inputState,
                                     "Start from the particles in this CSV (id,x,y,vx,vy,mass,radius); needs --box");
    input->needs(box);
    for (CLI::Option* generated : {particles, packing, radius, radiusMin, radiusMax, mass, massMin, massMax, speed, seed})
        input->excludes(generated);
}

Setup makeSetup(const SceneOptions& o) {
    Setup setup;
    setup.world = o.world;
    if (!o.gravity.empty()) setup.world.gravity = float2{o.gravity[0], o.gravity[1]};
    if (!o.inputState.empty()) {
        setup.world.width = o.box[0];
        setup.world.height = o.box[1];
        validate(setup.world);
        setup.particles = readStateCsv(o.inputState);
        validateParticles(setup.particles, setup.world, o.inputState);
        return setup;
    }
    SceneDef scene = o.scene;
    if (!o.box.empty()) {
        scene.width = o.box[0];
        scene.height = o.box[1];
        // A zero would silently mean "size the box from the packing".
        if (!(scene.width > 0.0f && scene.height > 0.0f))
            throw Error("--box must be two finite numbers > 0, got " + std::to_string(o.box[0]) + " " +
                        std::to_string(o.box[1]));
    }
    InitialState initial = makeInitialState(scene);
    setup.world.width = initial.width;
    setup.world.height = initial.height;
    validate(setup.world);
    setup.particles = std::move(initial.particles);
    return setup;
}

}  // namespace carom::app
