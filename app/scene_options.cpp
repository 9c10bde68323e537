#include "app/scene_options.h"

#include <carom/io.h>

#include <cctype>

#include "app/number_options.h"
#include "app/output_plan.h"
#include "app/renamed_value.h"
#include <carom/world.h>

namespace carom::app {
namespace {

// The options that describe the one particle group of a scene file.
const char* const kGroupOptions[] = {"--particles", "--radius",   "--radius-min", "--radius-max",
                                     "--mass",      "--mass-min", "--mass-max",   "--speed"};

void applyOverrides(const SceneOptions& o, SceneFileDef& scene) {
    auto given = [&o](const char* option) { return o.given.count(option) > 0; };
    if (given("--box")) {
        scene.world.width = o.box[0];
        scene.world.height = o.box[1];
        scene.packing = 0.0f;
    }
    if (given("--packing")) {
        scene.packing = o.scene.packing;
        scene.world.width = scene.world.height = 0.0f;
    }
    if (given("--dt") && !o.dtAuto) scene.world.dt = o.world.dt;
    if (given("--max-travel")) scene.world.maxTravel = o.world.maxTravel;
    if (given("--skin")) scene.world.skin = o.world.skin;
    if (o.dtAuto && scene.world.maxTravel == 0.0f) scene.world.maxTravel = kDefaultMaxTravel;
    if (given("--boundary")) scene.world.boundary = o.world.boundary;
    if (given("--collisions")) scene.world.collisions = o.world.collisions;
    if (given("--gravity")) scene.world.gravity = Vec2{o.gravity[0], o.gravity[1]};
    if (given("--seed")) scene.seed = o.scene.seed;
    for (const char* option : kGroupOptions) {
        if (given(option) && scene.groups.size() != 1)
            throw Error(std::string(option) + " sets the particle group of a scene, but '" + scene.path + "' has " +
                        std::to_string(scene.groups.size()) + " [[group]] tables; edit the file instead");
    }
    if (scene.groups.size() != 1) return;
    GroupDef& group = scene.groups.front();
    if (given("--particles")) group.count = o.scene.particles;
    if (given("--radius") || given("--radius-min")) {
        group.radiusMin = o.scene.radiusMin;
        group.radiusMax = o.scene.radiusMax;
    }
    if (given("--mass") || given("--mass-min")) {
        group.massMin = o.scene.massMin;
        group.massMax = o.scene.massMax;
    }
    if (given("--speed")) {
        group.speed = o.scene.speed;
        group.temperature = 0.0f;
    }
}

Setup setupFromSceneFile(const SceneOptions& o) {
    SceneFileDef scene = io::readSceneFile(o.sceneFile);
    applyOverrides(o, scene);
    return sceneFileSetup(std::move(scene));
}

struct UniformRange {
    CLI::Option *value, *min, *max;
};

// --NAME (every disk alike), or --NAME-min with --NAME-max (drawn uniformly
// between them): the one value excludes the range, each bound needs the other.
UniformRange addUniformRange(CLI::App& command, const std::string& name, float& min, float& max) {
    std::string capitalized = name;
    capitalized[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
    auto* value =
        command
            .add_option_function<float>(
                "--" + name, [&min, &max](float v) { min = max = v; }, capitalized + " of every disk (default 1)")
            ->transform(realNumber());
    auto* low =
        command.add_option("--" + name + "-min", min, "Smallest " + name + " (uniform range)")->transform(realNumber());
    auto* high =
        command.add_option("--" + name + "-max", max, "Largest " + name + " (uniform range)")->transform(realNumber());
    value->excludes(low)->excludes(high);
    low->needs(high);
    high->needs(low);
    return {value, low, high};
}

}  // namespace

CLI::Option* tracked(CLI::Option* option, std::set<std::string>& given) {
    const std::string name = "--" + option->get_single_name();
    return option->each([&given, name](const std::string&) { given.insert(name); });
}

CLI::Option* addPipelineOption(CLI::App& command, std::string& pipeline, const std::string& description) {
    return command.add_option("--pipeline", pipeline, description)
        ->transform(renamedValue("--pipeline", "seed", "host-grid"))
        ->check(CLI::IsMember({"auto", "host-grid", "resident"}))
        ->capture_default_str();
}

std::vector<std::string> backendKinds() {
    std::vector<std::string> kinds = {"cpu"};
    if (engineAvailable(ComputeEngine::OpenClHostGrid)) kinds.push_back("opencl");
    return kinds;
}

void addSceneOptions(CLI::App& command, SceneOptions& o) {
    std::vector<std::string> backends = backendKinds();
    backends.insert(backends.begin(), "auto");
    tracked(command
                .add_option("--backend", o.backend.kind,
                            "Compute backend, or auto: OpenCL on a GPU, else cpu (which outruns OpenCL on CPU "
                            "devices such as PoCL); --device or --pipeline asks for OpenCL, --collisions events "
                            "and --skin for the CPU")
                ->check(CLI::IsMember(backends))
                ->capture_default_str(),
            o.given);
    // CLI11 validates options in the order they are added, so --backend is
    // known when --device and --pipeline are checked.
    auto forOpenCL = [&o](const char* cpuHas) {
        return CLI::Validator(
            [&o, cpuHas](const std::string& value) {
                return o.backend.kind == "cpu" ? "'" + value + "' needs --backend opencl; the cpu backend has " + cpuHas
                                               : std::string();
            },
            "");
    };
    command
        .add_option("--device", o.backend.device,
                    "OpenCL device: index from `carom devices` or part of its name (default: first GPU, "
                    "else first device)")
        ->check(forOpenCL("no devices to choose from"));
    addPipelineOption(command, o.backend.pipeline,
                      "OpenCL pipeline: host-grid (the host builds the grid, state read back each step), resident "
                      "(grid and state stay on the device: the fast one on GPUs), or auto: resident on a GPU, "
                      "host-grid on other devices (on CPUs, e.g. PoCL, host-grid is faster)")
        ->check(forOpenCL("one pipeline"));

    auto* particles = command.add_option("--particles", o.scene.particles, "Number of disks")
                          ->transform(particleCount(1, kMaxParticles))
                          ->capture_default_str();
    auto* packing = command.add_option("--packing", o.scene.packing, "Area fraction of the disks; sizes a square box")
                        ->transform(realNumber())
                        ->capture_default_str();
    auto* box = command.add_option("--box", o.box, "Box size W H: the world is [0,W]x[0,H]")
                    ->expected(2)
                    ->transform(realNumber());
    packing->excludes(box);

    const auto [radius, radiusMin, radiusMax] =
        addUniformRange(command, "radius", o.scene.radiusMin, o.scene.radiusMax);
    const auto [mass, massMin, massMax] = addUniformRange(command, "mass", o.scene.massMin, o.scene.massMax);

    auto* speed = command.add_option("--speed", o.scene.speed, "Initial speed of every disk, random directions")
                      ->transform(realNumber())
                      ->capture_default_str();
    auto* seed =
        command.add_option("--seed", o.scene.seed, "Random seed")->transform(wholeNumber(0))->capture_default_str();
    auto* dt = command.add_option_function<std::string>(
        "--dt",
        [&o](const std::string& text) {
            if (text == "auto") {
                o.dtAuto = true;
                return;
            }
            try {
                o.world.dt = io::parseFloat(text);
            } catch (const Error& e) {  // thrown while parsing: CLI11 reports it as a usage error
                throw CLI::ValidationError("--dt", std::string(e.what()) + " (--dt also takes auto)");
            }
        },
        "Time step, or auto: the default step (0.01), split into substeps of at most --max-travel radii");
    auto* maxTravel =
        command
            .add_option(
                "--max-travel", o.world.maxTravel,
                "Split each step into substeps so that no disk moves more than this fraction of the smallest radius in "
                "one (0 = off; --dt auto uses 0.2)")
            ->transform(realNumber());
    auto* skin = command
                     .add_option("--skin", o.world.skin,
                                 "The CPU engine's neighbour lists (pairwise scheme): each disk lists the disks "
                                 "within contact plus this distance, again once the disks have moved about half of "
                                 "it (0 = automatic, about the largest radius); changes the speed, never a result")
                     ->transform(realNumber());
    auto* boundary = command
                         .add_option_function<std::string>(
                             "--boundary", [&o](const std::string& name) { o.world.boundary = parseBoundary(name); },
                             "walls (reflective, the default) or periodic (the box repeats)")
                         ->check(CLI::IsMember({"walls", "periodic"}));
    auto* gravity = command.add_option("--gravity", o.gravity, "Constant acceleration GX GY (default off)")
                        ->expected(2)
                        ->transform(realNumber());
    auto* collisions = command.add_option_function<std::string>(
        "--collisions",
        [&o](const std::string& name) {
            try {
                o.world.collisions = parseCollisionScheme(name);
            } catch (const Error& e) {  // thrown while parsing: CLI11 reports it as a usage error
                throw CLI::ValidationError("--collisions", e.what());
            }
        },
        "How collisions are resolved: pairwise (binary elastic collisions at their exact contact times; energy "
        "is conserved), simultaneous (the seed's scheme: impulses from the state before the step, summed) or "
        "events (exact event-driven dynamics in double on one CPU thread; --dt only sets when the state is "
        "sampled)");

    auto* input = fileOption(command.add_option(
        "--input-state", o.inputState, "Start from the particles in this CSV (id,x,y,vx,vy,mass,radius); needs --box"));
    input->needs(box);
    for (CLI::Option* generated :
         {particles, packing, radius, radiusMin, radiusMax, mass, massMin, massMax, speed, seed})
        input->excludes(generated);

    fileOption(command.add_option("--scene", o.sceneFile,
                                  "Start from this TOML scene file; the options above that are given override its "
                                  "values"))
        ->excludes(input);
    for (CLI::Option* overriding : {particles, packing, box, radius, radiusMin, radiusMax, mass, massMin, massMax,
                                    speed, seed, dt, gravity, maxTravel, skin, boundary, collisions})
        tracked(overriding, o.given);
}

EngineChoice engineChoiceOf(const WorldDef& world, const SceneOptions& o) {
    BackendOptions def = o.backend;
    const bool openclAsked = def.kind == "opencl" || !def.device.empty() || def.pipeline != "auto";
    if (world.collisions == CollisionScheme::Events && def.kind != "cpu" && openclAsked)
        throw Error(
            "--collisions events runs on the CPU only (one thread, double precision): use --backend cpu "
            "with it, or --collisions pairwise on --backend opencl");
    if (def.kind != "auto") return {engineOf(def), "--backend " + def.kind};
    if (openclAsked) {
        def.kind = "opencl";
        return {engineOf(def), "--backend auto: OpenCL, which --device or --pipeline asks for"};
    }
    if (world.collisions == CollisionScheme::Events)
        return {EngineDef{}, "--backend auto: the events scheme runs on the CPU"};
    if (world.skin > 0.0f) return {EngineDef{}, "--backend auto: --skin sizes the CPU engine's neighbour lists"};
    EngineChoice choice = chooseEngine();
    choice.reason = "--backend auto: " + choice.reason;
    return choice;
}

WorldDef withEngine(WorldDef world, const SceneOptions& o) { return onEngine(world, engineChoiceOf(world, o).engine); }

EngineDef engineOf(const BackendOptions& backend) {
    if (backend.kind == "cpu") return EngineDef{};
    if (backend.pipeline == "auto") return EngineDef{openClEngineFor(findDevice(backend.device)), backend.device};
    return EngineDef{backend.pipeline == "resident" ? ComputeEngine::OpenClResident : ComputeEngine::OpenClHostGrid,
                     backend.device};
}

void refuseSubstepsWithEvents(const WorldDef& world, const std::string& asked) {
    if (world.collisions != CollisionScheme::Events || world.maxTravel == 0.0f) return;
    throw Error(asked +
                " splits steps into substeps, but the events scheme has no steps to split (it moves the "
                "disks exactly from event to event; --dt only sets when the state is sampled): leave it "
                "out, or use --collisions pairwise");
}

std::string maxTravelOption(float maxTravel) { return "--max-travel " + io::shortestText(maxTravel); }

namespace {

// What asked a setup's world for substeps, for refuseSubstepsWithEvents.
std::string substepsSource(const SceneOptions& o) {
    if (o.given.count("--max-travel")) return maxTravelOption(o.world.maxTravel);
    if (o.dtAuto) return "--dt auto";
    return "the scene file '" + o.sceneFile + "' (max_travel or dt = \"auto\")";
}

Setup makeSetupOf(const SceneOptions& o) {
    if (o.dtAuto && o.given.count("--max-travel") && o.world.maxTravel == 0.0f) {
        throw Error(
            "--dt auto splits each step so that no disk moves more than --max-travel radii; "
            "--max-travel 0 turns that off: give --max-travel > 0 (without it, " +
            io::shortestText(kDefaultMaxTravel) + ") or a fixed --dt");
    }
    if (!o.sceneFile.empty()) return setupFromSceneFile(o);
    Setup setup;
    setup.world = o.world;
    if (o.dtAuto && setup.world.maxTravel == 0.0f) setup.world.maxTravel = kDefaultMaxTravel;
    if (!o.gravity.empty()) setup.world.gravity = Vec2{o.gravity[0], o.gravity[1]};
    if (!o.inputState.empty()) {
        setup.world.width = o.box[0];
        setup.world.height = o.box[1];
        validate(setup.world);
        setup.disks = io::readState(o.inputState);
        setup.source = o.inputState;
        return setup;
    }
    SceneDef scene = o.scene;
    if (!o.box.empty()) {
        scene.width = o.box[0];
        scene.height = o.box[1];
        // A zero would silently mean "size the box from the packing".
        if (!(scene.width > 0.0f && scene.height > 0.0f))
            throw Error("--box must be two finite numbers > 0, got " + io::shortestText(o.box[0]) + " " +
                        io::shortestText(o.box[1]));
    }
    requireRoomFor(scene.particles, "--particles", availableMemoryBytes(),
                   o.backend.kind == "opencl" ? kOpenClHostBytesPerDisk : kHostBytesPerDisk);
    Scene placed = makeScene(scene);
    setup.world.width = placed.width;
    setup.world.height = placed.height;
    validate(setup.world);
    setup.disks = std::move(placed.disks);
    return setup;
}

}  // namespace

Setup sceneFileSetup(SceneFileDef scene) {
    io::SceneFile placed = io::loadScene(scene);
    Setup setup;
    setup.world = placed.world;
    setup.disks = std::move(placed.disks);
    setup.sceneFile = std::move(scene);
    return setup;
}

Setup makeSetup(const SceneOptions& o) {
    Setup setup = makeSetupOf(o);
    refuseSubstepsWithEvents(setup.world, substepsSource(o));
    return setup;
}

}  // namespace carom::app
