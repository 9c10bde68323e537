// The scene, world and backend options that every carom command shares
// (`run` now, `view` and `bench` later), and how they become a world and its
// initial particles.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/carom.h"

namespace carom::app {

struct SceneOptions {
    SceneDef scene;
    WorldDef world;
    BackendDef backend;
    std::vector<float> box;      // W H, when given
    std::vector<float> gravity;  // GX GY, when given
    std::string inputState;
};

// Adds --backend, --device, --particles, --packing, --box, --radius...,
// --mass..., --speed, --seed, --dt, --gravity and --input-state.
void addSceneOptions(CLI::App& command, SceneOptions& options);

struct Setup {
    WorldDef world;
    std::vector<Particle> particles;
};

// The world and particles the options describe: from --input-state, or built
// from the scene. Throws Error for values out of range.
Setup makeSetup(const SceneOptions& options);

}  // namespace carom::app
