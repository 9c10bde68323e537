// `carom view`: the interactive SDL2 + OpenGL viewer, and its headless mode
// (--frames K with --screenshot, --record, --events or --output-state) for
// tests and recordings.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <utility>
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
    // Headless: switch to collision scheme SCHEME before frame FRAME (as the
    // panel's selector does), for tests of the live switch.
    std::optional<std::pair<std::uint64_t, CollisionScheme>> switchCollisions;
    // Headless: the input events in this file (keys, mouse buttons, motion,
    // wheel; viewer.cpp's readEventScript) reach the viewer before their frames.
    std::string events;
    std::string outputState;  // headless: write the final disks to this CSV
};

void addViewOptions(class CLI::App& command, ViewOptions& options);

// Opens the window and runs until Esc or the window closes (or, headless,
// for options.frames frames). Throws Error when there is no display.
int runViewer(const ViewOptions& options);

struct Control {
    const char* keys;
    const char* action;
};

// The controls, as printed at start-up and shown in the panels.
inline constexpr Control kControls[] = {
    {"Space/P", "pause and resume"},
    {"N", "single step while paused"},
    {"R", "reset to the initial scene"},
    {"G", "gravity on/off"},
    {"C", "cycle colouring (speed, mass, radius, id)"},
    {"H", "hide/show the panels"},
    {"F", "fit the box to the view (undo zoom and pan)"},
    {"S", "save a PNG screenshot"},
    {"Left drag", "grab the nearest disk, release to throw it"},
    {"Right click", "spawn a burst of disks at the cursor"},
    {"Wheel", "zoom about the cursor"},
    {"Middle/right drag", "pan"},
    {"Esc", "quit"},
};

}  // namespace carom::viewer
