// The scene, world and backend options that every carom command shares
// (`run` now, `view` and `bench` later), and how they become a world and its
// initial particles.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <carom/carom.h>

namespace carom::app {

// --backend, --device and --pipeline as given.
struct BackendOptions {
    std::string kind = "auto";      // "cpu" (OpenMP), "opencl", or "auto": carom::chooseEngine's
    std::string device;             // OpenCL only: index from `carom devices` or part of the
                                    //   device name; empty = first GPU, else first device
    std::string pipeline = "auto";  // OpenCL only: "host-grid" (host builds the grid, state read
                                    //   back each step), "resident" (grid and state stay on the
                                    //   device), or "auto": resident on a GPU, host-grid elsewhere
};

struct SceneOptions {
    SceneDef scene;
    WorldDef world;
    BackendOptions backend;
    std::vector<float> box;      // W H, when given
    std::vector<float> gravity;  // GX GY, when given
    bool dtAuto = false;         // --dt auto: substeps of at most --max-travel (default 0.2) radii
    std::string inputState;
    std::string sceneFile;        // --scene: a TOML scene file (io::readSceneFile)
    std::set<std::string> given;  // the options given on the command line ("--dt", ...):
                                  //   these override the scene file's values
};

// The --backend values this build has: "cpu", and "opencl" where it was
// built with OpenCL (addSceneOptions adds "auto", its default).
std::vector<std::string> backendKinds();

// Adds --backend, --device, --pipeline, --particles, --packing, --box, --radius...,
// --mass..., --speed, --seed, --dt, --max-travel, --skin, --gravity, --boundary,
// --input-state and --scene.
void addSceneOptions(CLI::App& command, SceneOptions& options);

// Adds --pipeline auto|host-grid|resident into `pipeline`; "seed", the former
// name of host-grid, is read as host-grid with a notice on stderr.
CLI::Option* addPipelineOption(CLI::App& command, std::string& pipeline, const std::string& description);

// Records `option`'s name in `given` when it appears on the command line.
CLI::Option* tracked(CLI::Option* option, std::set<std::string>& given);

struct Setup {
    WorldDef world;
    std::vector<Disk> disks;
    std::string source = "the scene";       // what the disks came from, for World::setDisks' messages
    std::optional<SceneFileDef> sceneFile;  // the --scene file with the command line's overrides
                                            //   applied (its steps and outputs), when given
};

// The world and particles the options describe: from --input-state, from
// --scene with the options given on the command line overriding the file's
// values, or built from the options. Throws Error for values out of range
// and for requests that cannot fit in memory, before allocating them.
Setup makeSetup(const SceneOptions& options);
// The setup of a scene file after the command line's overrides: its world
// and disks as io::loadScene places them, and the file itself (its steps and
// outputs); throws Error as makeSetup.
Setup sceneFileSetup(SceneFileDef scene);

// The engine --backend KIND --pipeline PIPELINE --device DEVICE name
// (the values CLI11 has already checked); --pipeline auto is the device's
// carom::openClEngineFor, so it throws Error when no device matches.
EngineDef engineOf(const BackendOptions& backend);

// The compute engine and device the options ask for, and why: --backend
// cpu or opencl (with --pipeline and --device) as given; --backend auto (the
// default) on OpenCL where --device or --pipeline asks for it, on the CPU
// for the events scheme, else carom::chooseEngine's. Refuses an OpenCL
// --backend, --device or --pipeline with the events scheme.
EngineChoice engineChoiceOf(const WorldDef& world, const SceneOptions& options);
// `world` on that engine.
WorldDef withEngine(WorldDef world, const SceneOptions& options);

// The events scheme has no steps to split: throws Error, naming `asked` (what
// asked for the substeps: "--max-travel 0.5", "--dt auto", a scene file),
// when `world` has it with substeps (maxTravel > 0).
void refuseSubstepsWithEvents(const WorldDef& world, const std::string& asked);
// "--max-travel 0.5", for messages.
std::string maxTravelOption(float maxTravel);

}  // namespace carom::app
