// `carom view`: the interactive SDL2 + OpenGL viewer, and its headless mode
// (--frames K with --screenshot or --record) for tests and recordings.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "app/scene_options.h"
#include "app/viewer/camera.h"
#include "app/viewer/palette.h"
#include "app/viewer/renderer.h"

struct SDL_Window;
union SDL_Event;

namespace carom::viewer {

struct ViewOptions {
    app::SceneOptions scene;
    std::vector<int> window{1280, 800};  // W H [pixels]
    int stepsPerFrame = 4;               // simulation steps per 1/60 s tick (a frame at 60 FPS)
    std::uint64_t frames = 0;            // headless: render this many frames, then exit
    std::string screenshot;              // headless: write the last frame here (PNG)
    std::string record;                  // headless: write every frame into this folder
    std::string colouring = "speed";     // speed, mass, radius or id
    bool hidePanels = false;
};

void addViewOptions(class CLI::App& command, ViewOptions& options);

// Opens the window and runs until Esc or the window closes (or, headless,
// for options.frames frames). Throws Error when there is no display.
int runViewer(const ViewOptions& options);

// The controls, as printed at start-up and shown in the help panel.
extern const char* const kControls;

}  // namespace carom::viewer
