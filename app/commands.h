// The carom subcommands.
#pragma once

#include <cstdint>
#include <string>

#include "app/scene_options.h"

namespace carom::app {

struct RunOptions {
    SceneOptions scene;
    std::uint64_t steps = 1000;
    std::string outputState;
    bool json = false;
};

void addRunOptions(CLI::App& command, RunOptions& options);

// `carom run`: simulate, then print a summary (or JSON) and write the state.
int runCommand(const RunOptions& options);

// `carom devices`: list the OpenCL platforms and devices with their index.
int devicesCommand();

}  // namespace carom::app
