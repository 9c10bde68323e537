// The Viewer class behind runViewer (viewer.cpp: window, loop, input;
// panels.cpp: the Dear ImGui panels).
#pragma once

#include <array>
#include <chrono>
#include <deque>
#include <functional>
#include <optional>

#include <carom/world.h>

#include "app/viewer/viewer.h"

namespace carom::viewer {

struct ScriptedEvent;  // viewer.cpp: one line of --events

struct EnergySample {
    double kinetic = 0, potential = 0;
};

// What the readouts show of the state, measured once per frame.
struct Motion {
    double kinetic = 0, potential = 0;
    std::array<double, 2> momentum{};
    double mass = 0;
};

class Viewer {
public:
    explicit Viewer(const ViewOptions& options);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    int run();

private:
    static constexpr double kTickSeconds = 1.0 / 60.0;  // one batch of stepsPerFrame steps
    static constexpr int kMaxTicksPerFrame = 4;         // a slow frame drops time instead of stalling
    static constexpr std::size_t kHistoryLength = 300;

    // Setup.
    void openWindow();
    void start(app::Setup setup);
    // A world with the viewer's settings (dt, gravity, collision scheme, the
    // options' engine) holding `disks`; throws Error when the engine refuses.
    World makeWorld(WorldDef def, const std::vector<Disk>& disks, const std::string& source) const;
    // Fits the camera to the window and what the panels leave free of it.
    void layOut();
    // drawableWidth_, drawableHeight_ and pixelRatio_ from the window.
    void readDrawableSize();

    // One frame.
    void handleEvent(const SDL_Event& event);
    void applyGrab(double realSeconds);
    void advance(int ticks);
    // Reads what the frame shows of the state: the disks and the readouts.
    void readBack(double realSeconds);
    // views_ and viewSums_ (and motion_ from them) from the world as it is now.
    void readView();
    // The views with speeds as values, for the speed histogram: views_
    // coloured by speed, else a read of its own.
    const std::vector<DiskView>& speedViews();
    DiskColours diskColours() const;
    void render();
    void drawPanels();  // panels.cpp

    // Actions.
    void reset();
    // Starts the panel's scene: one group from the command line's options,
    // or the edited groups of the --scene file.
    void applyScene(const SceneDef& scene);
    void applySceneFile(const SceneFileDef& scene);
    // Starts what `makeSetup` makes; an Error it throws is shown in the
    // panels and keeps the current scene running.
    void startFrom(const std::function<app::Setup()>& makeSetup);
    void drawScenePanel();      // panels.cpp
    void drawSceneFilePanel();  // panels.cpp
    // Changes dt and switches gravity (gravity_) on or off; a change the
    // world refuses is shown in the panels and leaves both as they were.
    void setMotion(float dt, bool gravityOn);
    // Rebuilds the world with another scheme from the disks as they are now;
    // a scheme the engine refuses is shown in the panels and changes nothing.
    void setCollisions(CollisionScheme scheme);
    void spawnBurst(Vec2 world);
    void grabNearest(Vec2 world);
    // The energy changed from outside (a new state, gravity, a grab): the
    // total's drift is measured from the state as it is now.
    void restartEnergyDrift();
    void saveScreenshot(const std::string& path);
    // Where the last mouse event put the cursor, in drawable pixels.
    Vec2 cursorPixel() const;
    double simulatedSecondsPerSecond() const;
    // "total energy drift %+.3g": (E - E0) / |E0| of the total energy since
    // restartEnergyDrift (in a periodic box under gravity, of the kinetic
    // energy in the centre-of-mass frame, which that names); E - E0 where E0
    // is 0 (a relative change is undefined there).
    std::string energyDriftText() const;

    ViewOptions options_;
    app::Setup initial_;                         // what R resets to
    SceneDef sceneEdit_;                         // the scene panel's values without --scene
    std::optional<SceneFileDef> sceneFileEdit_;  // and with it: the file's groups
    std::optional<World> world_;
    std::vector<DiskView> views_;  // read back once per frame, in the engine's order
    ViewSums viewSums_;            // of views_
    std::vector<DiskView> speedViews_;

    SDL_Window* window_ = nullptr;
    void* glContext_ = nullptr;
    std::unique_ptr<Renderer> renderer_;
    Camera camera_;
    int drawableWidth_ = 0, drawableHeight_ = 0;
    double pixelRatio_ = 1.0;  // drawable pixels per window point (HiDPI)
    std::string glRenderer_;   // OpenGL's name for what draws (GL_RENDERER)

    Colouring colouring_ = Colouring::Speed;
    bool headless_ = false;
    bool running_ = true;
    bool paused_ = false;
    bool stepOnce_ = false;
    bool hidePanels_ = false;
    bool panelsCollapsed_ = false;  // as ImGui last drew them
    std::string settingsFile_;      // ImGui's, where the collapsed state is remembered; empty headless
    int stepsPerFrame_ = 1;
    double accumulator_ = 0.0;
    float dt_ = 0.01f;
    bool gravityOn_ = false;
    CollisionScheme collisions_ = CollisionScheme::Pairwise;
    std::string eventsRefusal_;         // why the events scheme cannot run with these options; empty if it can
    carom::Vec2 gravity_{0.0f, -1.0f};  // used while gravity is on

    std::vector<ScriptedEvent> script_;  // --events, in frame order
    std::size_t nextScripted_ = 0;

    Vec2 cursorPoint_;     // [window points], from the mouse events
    int grabbed_ = -1;     // id of the disk held by the mouse
    Disk grabbedDisk_;     // as it was when grabbed, then where the mouse puts it
    Vec2 cursorVelocity_;  // [world units per real second], smoothed
    Vec2 lastCursorWorld_;
    bool rightDown_ = false, rightDragged_ = false, middleDown_ = false;

    std::uint64_t collisionsBeforeReset_ = 0;  // the worlds' before the last reset, scene or switch
    std::uint64_t collisionsAtLastReadout_ = 0;
    double secondsSinceReadout_ = 0.0;
    double collisionsPerSecond_ = 0.0;
    double simMsPerStep_ = 0.0;
    Motion motion_;              // of views_, once per frame
    Motion motionAtDriftStart_;  // motion_ when the drift started being measured
    double driftTime_ = 0.0;     // simulated time since then
    std::deque<EnergySample> energyHistory_;
    std::deque<float> momentumHistory_;
    std::string message_;  // the last error or notice, shown in the panels
};

}  // namespace carom::viewer
