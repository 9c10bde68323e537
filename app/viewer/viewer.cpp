#include "app/viewer/viewer_app.h"

#include <SDL.h>
#include <backends/imgui_impl_opengl3.h>
#include <backends/imgui_impl_sdl.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iterator>
#include <limits>
#include <sstream>

#include <carom/io.h>
#include <carom/types.h>

#include "app/number_options.h"
#include "app/output_plan.h"
#include "app/stop_signals.h"
#include "app/viewer/layout.h"
#include "app/viewer/png.h"

namespace carom::viewer {

struct ScriptedEvent {
    std::uint64_t frame;  // handled before this frame, counting from 1
    SDL_Event event;
};

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double millisecondsBetween(Clock::time_point start, Clock::time_point end) {
    return std::chrono::duration<double, std::milli>(end - start).count();
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    return values[values.size() / 2];
}

Colouring parseColouring(const std::string& name) {
    for (int i = 0; i < kColouringCount; ++i)
        if (name == colouringName(Colouring(i))) return Colouring(i);
    throw Error("--color '" + name + "' is not a colouring; allowed: speed, mass, radius, id");
}

// "group[1] 'light' 30, group[2] 17": what the groups hold.
std::string groupsText(const SceneFileDef& scene) {
    std::string text;
    for (const GroupDef& group : scene.groups)
        text += (text.empty() ? "" : ", ") + group.name + " " + std::to_string(group.count);
    return text;
}

bool isKeyboardOrMouse(Uint32 type) {
    switch (type) {
        case SDL_KEYDOWN:
        case SDL_KEYUP:
        case SDL_TEXTEDITING:
        case SDL_TEXTINPUT:
        case SDL_MOUSEMOTION:
        case SDL_MOUSEBUTTONDOWN:
        case SDL_MOUSEBUTTONUP:
        case SDL_MOUSEWHEEL: return true;
        default: return false;
    }
}

// An --events line's number, its field named in the refusal.
std::uint64_t parseField(const char* field, const std::string& text, std::uint64_t min, std::uint64_t max) {
    try {
        return io::parseWholeNumber(text, min, max);
    } catch (const Error& e) {
        throw Error(std::string(field) + " " + e.what());
    }
}

// "-3" of `wheel -3`: whole steps, negative ones zoom out.
int parseWheelSteps(const std::string& text) {
    const bool out = !text.empty() && text[0] == '-';
    try {
        const int steps = int(io::parseWholeNumber(std::string_view(text).substr(out ? 1 : 0), 1, 100));
        return out ? -steps : steps;
    } catch (const Error&) {
        throw Error("wheel steps '" + io::printable(text) + "' are not a whole number from -100 to 100 other than 0");
    }
}

Uint8 parseButton(const std::string& name) {
    if (name == "left") return SDL_BUTTON_LEFT;
    if (name == "middle") return SDL_BUTTON_MIDDLE;
    if (name == "right") return SDL_BUTTON_RIGHT;
    throw Error("'" + io::printable(name) + "' is not a mouse button; allowed: left, middle, right");
}

// The SDL event of one --events line's words after the frame; `cursor` is
// where the previous mouse line left the cursor (motion is relative to it).
SDL_Event parseScriptedEvent(const std::vector<std::string>& words, const std::vector<int>& window,
                             std::array<int, 2>& cursor) {
    const std::string& action = words[1];
    const auto expectArguments = [&](std::size_t count, const char* names) {
        if (words.size() != count + 2) throw Error(action + " takes " + names);
    };
    const auto parsePoint = [&](std::size_t first) {
        for (int axis = 0; axis < 2; ++axis)
            cursor[axis] =
                int(parseField(axis == 0 ? "X" : "Y", words[first + axis], 0, std::uint64_t(window[axis] - 1)));
    };
    SDL_Event event{};
    if (action == "key") {
        expectArguments(1, "a key name (SDL's: Space, P, N, R, F, ...)");
        event.type = SDL_KEYDOWN;
        event.key.state = SDL_PRESSED;
        event.key.keysym.sym = SDL_GetKeyFromName(words[2].c_str());
        if (event.key.keysym.sym == SDLK_UNKNOWN)
            throw Error("'" + io::printable(words[2]) +
                        "' is not a key; allowed: SDL's key names (Space, P, N, R, F, ...)");
        event.key.keysym.scancode = SDL_GetScancodeFromKey(event.key.keysym.sym);
    } else if (action == "press" || action == "release") {
        expectArguments(3, "BUTTON X Y");
        event.type = action == "press" ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP;
        event.button.button = parseButton(words[2]);
        event.button.state = action == "press" ? SDL_PRESSED : SDL_RELEASED;
        event.button.clicks = 1;
        parsePoint(3);
        event.button.x = cursor[0];
        event.button.y = cursor[1];
    } else if (action == "move") {
        expectArguments(2, "X Y");
        event.type = SDL_MOUSEMOTION;
        const std::array<int, 2> from = cursor;
        parsePoint(2);
        event.motion.x = cursor[0];
        event.motion.y = cursor[1];
        event.motion.xrel = cursor[0] - from[0];
        event.motion.yrel = cursor[1] - from[1];
    } else if (action == "wheel") {
        expectArguments(1, "STEPS (at the cursor; negative ones zoom out)");
        event.type = SDL_MOUSEWHEEL;
        event.wheel.y = parseWheelSteps(words[2]);
        event.wheel.direction = SDL_MOUSEWHEEL_NORMAL;
    } else {
        throw Error("'" + io::printable(action) + "' is not an action; allowed: key, press, release, move, wheel");
    }
    return event;
}

const char* const kEventsFile = "--events file";
constexpr int kSmallestWindowSide = 64, kLargestWindowSide = 16384;  // pixels
constexpr int kMostStepsPerFrame = 100000;

// --events FILE: one input event a line, "FRAME ACTION ARGUMENTS", handled
// before frame FRAME (1 to `frames`); points are window points; '#' starts a
// comment. Read before the window opens, so a bad line costs no frames.
std::vector<ScriptedEvent> readEventScript(const std::string& path, std::uint64_t frames,
                                           const std::vector<int>& window) {
    io::TextFile file(path, kEventsFile);
    io::TextLines lines(file.stream(), path, kEventsFile);
    std::vector<ScriptedEvent> script;
    std::array<int, 2> cursor{};
    std::string line;
    while (lines.next(line)) {
        std::istringstream text(line.substr(0, line.find('#')));
        const std::vector<std::string> words{std::istream_iterator<std::string>(text), {}};
        if (words.empty()) continue;
        try {
            if (words.size() < 2) throw Error("a line is FRAME ACTION ARGUMENTS");
            const std::uint64_t frame = parseField("FRAME", words[0], 1, frames);
            const SDL_Event event = parseScriptedEvent(words, window, cursor);
            script.push_back({frame, event});
            if (event.type == SDL_KEYDOWN) {  // a key line is a press and a release, as a keyboard sends them
                SDL_Event release = event;
                release.type = SDL_KEYUP;
                release.key.state = SDL_RELEASED;
                script.push_back({frame, release});
            }
        } catch (const Error& e) {
            throw Error("--events " + path + " line " + std::to_string(lines.number()) + " '" + io::printable(line) +
                        "': " + e.what());
        }
    }
    std::stable_sort(script.begin(), script.end(),
                     [](const ScriptedEvent& a, const ScriptedEvent& b) { return a.frame < b.frame; });
    return script;
}

std::string timestampedScreenshotName() {
    const std::time_t now = std::time(nullptr);
    char name[64];
    std::strftime(name, sizeof name, "carom-%Y%m%d-%H%M%S.png", std::localtime(&now));
    return name;
}

}  // namespace

void addViewOptions(CLI::App& command, ViewOptions& o) {
    app::addSceneOptions(command, o.scene);
    command.add_option("--window", o.window, "Window size W H in pixels")
        ->expected(2)
        ->transform(app::wholeNumber(kSmallestWindowSide, kLargestWindowSide))
        ->capture_default_str();
    command
        .add_option("--steps-per-frame", o.stepsPerFrame,
                    "Simulation steps per 1/60 s frame (the speed of the animation)")
        ->transform(app::wholeNumber(0, kMostStepsPerFrame))
        ->capture_default_str();
    command.add_option("--color", o.colouring, "Colouring: speed, mass, radius or id")->capture_default_str();
    command.add_flag("--hide-panels", o.hidePanels, "Start with the panels hidden (as H)");
    auto* frames = command.add_option("--frames", o.frames, "Headless: render K frames (one tick each), then exit")
                       ->transform(app::wholeNumber(1));
    app::fileOption(command.add_option("--screenshot", o.screenshot, "Headless: write the last frame as PNG"))
        ->needs(frames);
    app::fileOption(command.add_option("--record", o.record, "Headless: write every frame as DIR/frame_00000.png ..."))
        ->needs(frames);
    command
        .add_option_function<std::vector<std::string>>(
            "--switch-collisions",
            [&o](const std::vector<std::string>& frameAndScheme) {
                try {
                    o.switchCollisions.emplace(
                        io::parseWholeNumber(frameAndScheme[0], 1, std::numeric_limits<std::uint64_t>::max()),
                        parseCollisionScheme(frameAndScheme[1]));
                } catch (const Error& e) {  // thrown while parsing: CLI11 reports it as a usage error
                    throw CLI::ValidationError("--switch-collisions", e.what());
                }
            },
            "Headless: switch to collision scheme SCHEME before frame FRAME (counting from 1), as the panel's "
            "selector does")
        ->expected(2)
        ->type_name("FRAME SCHEME")
        ->needs(frames);
    app::fileOption(command.add_option("--events", o.events,
                                       "Headless: input events from FILE, a line each: FRAME key NAME | press|release "
                                       "left|middle|right X Y | move X Y | wheel STEPS"))
        ->type_name("FILE")
        ->needs(frames);
    app::fileOption(command.add_option("--output-state", o.outputState, "Headless: write the final disks to this CSV"))
        ->type_name("FILE")
        ->needs(frames);
}

Viewer::Viewer(const ViewOptions& options) : options_(options) {
    // The command line checks the same ranges; a program may fill ViewOptions itself.
    for (const int side : options_.window)
        if (side < kSmallestWindowSide || side > kLargestWindowSide)
            throw Error("--window " + std::to_string(options_.window[0]) + " " + std::to_string(options_.window[1]) +
                        ": " + io::wholeNumbersAllowed(kSmallestWindowSide, kLargestWindowSide) + " pixels each");
    if (options_.stepsPerFrame < 0 || options_.stepsPerFrame > kMostStepsPerFrame)
        throw Error("--steps-per-frame " + std::to_string(options_.stepsPerFrame) + ": " +
                    io::wholeNumbersAllowed(0, kMostStepsPerFrame));
    colouring_ = parseColouring(options_.colouring);
    headless_ = options_.frames > 0;
    hidePanels_ = options_.hidePanels;
    stepsPerFrame_ = options_.stepsPerFrame;
    sceneEdit_ = options_.scene.scene;

    app::Setup setup = app::makeSetup(options_.scene);
    dt_ = setup.world.dt;
    gravityOn_ = setup.world.gravity.x != 0.0f || setup.world.gravity.y != 0.0f;
    if (gravityOn_) gravity_ = setup.world.gravity;
    collisions_ = setup.world.collisions;
    try {
        WorldDef events = setup.world;
        events.collisions = CollisionScheme::Events;
        app::withEngine(events, options_.scene);
        app::refuseSubstepsWithEvents(events, app::maxTravelOption(events.maxTravel));
    } catch (const Error& e) {
        eventsRefusal_ = e.what();
    }
    if (!options_.events.empty()) script_ = readEventScript(options_.events, options_.frames, options_.window);
    if (options_.switchCollisions && options_.switchCollisions->first > options_.frames)
        throw Error("--switch-collisions frame " + std::to_string(options_.switchCollisions->first) +
                    " is after the last one; allowed: 1 to --frames (" + std::to_string(options_.frames) + ")");
    if (!options_.record.empty()) app::createFolder("--record", options_.record);

    sceneFileEdit_ = setup.sceneFile;
    openWindow();
    start(std::move(setup));
}

Viewer::~Viewer() {
    if (glContext_) {
        renderer_.reset();
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplSDL2_Shutdown();
        ImGui::DestroyContext();
        SDL_GL_DeleteContext(glContext_);
    }
    if (window_) SDL_DestroyWindow(window_);
    SDL_Quit();
}

void Viewer::openWindow() {
    // SIGINT and SIGTERM are StopSignals' (runViewer): SDL's own handlers
    // would turn them into a quit event that cannot tell them apart.
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        throw Error(std::string("carom view needs a display, and SDL found none (") + SDL_GetError() +
                    "); use `carom run` to simulate headless, or run under xvfb-run");
    // Without a display SDL falls back to drivers that draw where nobody can
    // see: fine for --frames, not for a person.
    const std::string driver = SDL_GetCurrentVideoDriver();
    if (!headless_ && (driver == "offscreen" || driver == "dummy"))
        throw Error("carom view needs a display and found none (SDL fell back to its '" + driver +
                    "' driver); use `carom run` to simulate headless, or --frames K --screenshot FILE");
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
#ifdef __APPLE__
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_FLAGS, SDL_GL_CONTEXT_FORWARD_COMPATIBLE_FLAG);
#endif
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    window_ = SDL_CreateWindow("carom", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, options_.window[0],
                               options_.window[1], SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
    if (!window_) throw Error(std::string("carom view could not open a window: ") + SDL_GetError());
    SDL_SetWindowMinimumSize(window_, std::min(options_.window[0], kSmallestWindowWidth),
                             std::min(options_.window[1], kSmallestWindowHeight));
    glContext_ = SDL_GL_CreateContext(window_);
    if (!glContext_) throw Error(std::string("carom view needs OpenGL 3.3 (core profile): ") + SDL_GetError());
    SDL_GL_MakeCurrent(window_, glContext_);
    SDL_GL_SetSwapInterval(headless_ ? 0 : 1);  // vsync when a person watches
    const GLubyte* renderer = glGetString(GL_RENDERER);
    glRenderer_ = renderer ? reinterpret_cast<const char*>(renderer) : "an unnamed OpenGL renderer";

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    // ImGui's settings file remembers whether the panels are collapsed, per
    // user; headless runs neither read nor write it, so tests never depend on it.
    ImGui::GetIO().IniFilename = nullptr;
    if (char* folder = headless_ ? nullptr : SDL_GetPrefPath("carom", "view")) {
        settingsFile_ = std::string(folder) + "imgui.ini";
        SDL_free(folder);
        ImGui::GetIO().IniFilename = settingsFile_.c_str();
    }
    // Headless, ImGui would read the pointer of the virtual display, which
    // stands at no fixed place: the panels take no mouse input, so every
    // scripted mouse event (--events) reaches the box.
    if (headless_) ImGui::GetIO().ConfigFlags |= ImGuiConfigFlags_NoMouse;
    ImGui::StyleColorsDark();
    ImGui_ImplSDL2_InitForOpenGL(window_, glContext_);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    renderer_ = std::make_unique<Renderer>();
}

World Viewer::makeWorld(WorldDef def, const std::vector<Disk>& disks, const std::string& source) const {
    def.dt = dt_;
    def.gravity = gravityOn_ ? gravity_ : carom::Vec2{0, 0};
    def.collisions = collisions_;
    if (def.collisions != CollisionScheme::Pairwise) def.skin = 0.0f;  // --skin: the pairwise scheme's lists only
    World world(app::withEngine(def, options_.scene));
    world.setStopCheck(&app::StopSignals::received);  // a frame's steps may take long
    world.setDisks(disks, source);
    for (const std::string& warning : world.warnings()) std::cerr << "carom: warning: " << warning << '\n';
    return world;
}

void Viewer::start(app::Setup setup) {
    World world = makeWorld(setup.world, setup.disks, setup.source);
    initial_ = std::move(setup);
    world_.emplace(std::move(world));
    grabbed_ = -1;
    collisionsBeforeReset_ = collisionsAtLastReadout_ = 0;
    energyHistory_.clear();
    momentumHistory_.clear();
    restartEnergyDrift();
    readDrawableSize();
    layOut();
    camera_.fit(world_->def().width, world_->def().height);
}

// Both change when the window is resized or moves to a display of another scale.
void Viewer::readDrawableSize() {
    SDL_GL_GetDrawableSize(window_, &drawableWidth_, &drawableHeight_);
    int windowWidth = 0, windowHeight = 0;
    SDL_GetWindowSize(window_, &windowWidth, &windowHeight);
    pixelRatio_ = windowWidth > 0 ? double(drawableWidth_) / windowWidth : 1.0;
}

void Viewer::layOut() {
    const Panels panels = hidePanels_ ? Panels::Hidden : panelsCollapsed_ ? Panels::Collapsed : Panels::Shown;
    const Rect points =
        freeView(drawableWidth_ / pixelRatio_, drawableHeight_ / pixelRatio_, panels, ImGui::GetFrameHeight());
    camera_.setLayout(
        {double(drawableWidth_), double(drawableHeight_)},
        {points.x * pixelRatio_, points.y * pixelRatio_, points.width * pixelRatio_, points.height * pixelRatio_});
}

void Viewer::restartEnergyDrift() {
    readView();
    motionAtDriftStart_ = motion_;
    driftTime_ = 0.0;
}

std::string Viewer::energyDriftText() const {
    // A periodic box under gravity has no floor: what is conserved there is
    // the kinetic energy in the centre-of-mass frame.
    const bool fallsFreely = gravityOn_ && world_->def().boundary == Boundary::Periodic;
    const auto conserved = [&](const Motion& m) {
        return fallsFreely ? centreOfMassFrameKinetic(m.kinetic, m.momentum, m.mass) : m.kinetic + m.potential;
    };
    const double start = conserved(motionAtDriftStart_);
    const double change = conserved(motion_) - start;
    const char* name = fallsFreely ? "kinetic energy in the centre-of-mass frame" : "total energy";
    char text[128];
    if (start == 0.0)
        std::snprintf(text, sizeof text, "%s drift n/a (from 0, change %+.3g)", name, change);
    else
        std::snprintf(text, sizeof text, "%s drift %+.3g", name, change / std::abs(start));
    return text;
}

void Viewer::reset() {
    collisionsBeforeReset_ += world_->collisionCount();
    world_->setDisks(initial_.disks, initial_.source);
    restartEnergyDrift();
    grabbed_ = -1;
    message_ = "reset to the initial scene";
}

void Viewer::startFrom(const std::function<app::Setup()>& makeSetup) {
    try {
        start(makeSetup());
        message_.clear();
    } catch (const Error& e) {
        message_ = e.what();  // keep the current scene running
    }
}

void Viewer::applyScene(const SceneDef& scene) {
    startFrom([&] {
        app::SceneOptions options = options_.scene;
        options.scene = scene;
        // The panel's values replace whatever the scene came from.
        options.box.clear();
        options.inputState.clear();
        options.sceneFile.clear();
        return app::makeSetup(options);
    });
}

void Viewer::applySceneFile(const SceneFileDef& scene) {
    startFrom([&] { return app::sceneFileSetup(scene); });
}

void Viewer::setCollisions(CollisionScheme scheme) {
    if (scheme == CollisionScheme::Events && !eventsRefusal_.empty()) {
        message_ = eventsRefusal_;
        return;
    }
    const CollisionScheme previous = collisions_;
    collisions_ = scheme;
    try {
        World world = makeWorld(world_->def(), world_->disks(), "the disks at the switch");
        collisionsBeforeReset_ += world_->collisionCount();
        world_.emplace(std::move(world));
        restartEnergyDrift();
        message_ = std::string(collisionSchemeName(scheme)) + " collisions from here; the drift restarts";
    } catch (const Error& e) {
        collisions_ = previous;
        message_ = e.what();  // keep the world running as it was
    }
}

void Viewer::setMotion(float dt, bool gravityOn) {
    try {
        world_->setMotion(dt, gravityOn ? gravity_ : carom::Vec2{0, 0});
        dt_ = dt;
        gravityOn_ = gravityOn;
        restartEnergyDrift();
    } catch (const Error& e) {
        message_ = e.what();  // out of range for these disks: keep the motion as it was
    }
}

double Viewer::simulatedSecondsPerSecond() const { return paused_ ? 0.0 : stepsPerFrame_ * double(dt_) / kTickSeconds; }

Vec2 Viewer::cursorPixel() const { return {cursorPoint_.x * pixelRatio_, cursorPoint_.y * pixelRatio_}; }

void Viewer::grabNearest(Vec2 world) {
    // The frame's views are in the engine's order: the ids come from a read of the disks.
    const std::vector<Disk> disks = world_->disks();
    double best = 1e300;
    grabbed_ = -1;
    for (std::size_t i = 0; i < disks.size(); ++i) {
        const double dx = disks[i].position.x - world.x, dy = disks[i].position.y - world.y;
        const double d = std::sqrt(dx * dx + dy * dy) - disks[i].radius;
        if (d < best) {
            best = d;
            grabbed_ = int(i);
        }
    }
    if (grabbed_ >= 0) grabbedDisk_ = disks[std::size_t(grabbed_)];
    cursorVelocity_ = {0, 0};
    lastCursorWorld_ = world;
}

// While a disk is held it follows the cursor, moving at the cursor's speed so
// that releasing it throws it.
void Viewer::applyGrab(double realSeconds) {
    const Vec2 cursor = camera_.toWorld(cursorPixel());
    if (realSeconds > 0) {
        const Vec2 v{(cursor.x - lastCursorWorld_.x) / realSeconds, (cursor.y - lastCursorWorld_.y) / realSeconds};
        cursorVelocity_ = {0.7 * cursorVelocity_.x + 0.3 * v.x, 0.7 * cursorVelocity_.y + 0.3 * v.y};
    }
    lastCursorWorld_ = cursor;
    if (grabbed_ < 0 || grabbed_ >= int(world_->diskCount())) return;
    Disk& p = grabbedDisk_;
    const WorldDef& w = world_->def();
    p.position.x = float(std::clamp(cursor.x, double(p.radius), double(w.width - p.radius)));
    p.position.y = float(std::clamp(cursor.y, double(p.radius), double(w.height - p.radius)));
    const double perSimSecond = simulatedSecondsPerSecond();
    p.velocity.x = perSimSecond > 0 ? float(cursorVelocity_.x / perSimSecond) : 0.0f;
    p.velocity.y = perSimSecond > 0 ? float(cursorVelocity_.y / perSimSecond) : 0.0f;
    world_->setDisk(std::size_t(grabbed_), p);
    restartEnergyDrift();
}

void Viewer::spawnBurst(Vec2 world) {
    constexpr int kCount = 12;
    // Disks like the scene's: the panel's values, or the scene file's first group.
    float radius = sceneEdit_.radiusMax;
    float mass = 0.5f * (sceneEdit_.massMin + sceneEdit_.massMax);
    float speed = sceneEdit_.speed;
    if (sceneFileEdit_ && !sceneFileEdit_->groups.empty()) {
        const GroupDef& group = sceneFileEdit_->groups.front();
        radius = group.radiusMax;
        mass = 0.5f * (group.massMin + group.massMax);
        speed = group.temperature > 0 ? std::sqrt(2.0f * group.temperature / mass) : group.speed;  // rms speed in 2D
    }
    speed = std::max(1.0f, 2.0f * speed);
    const WorldDef& w = world_->def();
    if (2 * radius > std::min(w.width, w.height)) return;
    // A ring whose neighbours do not touch, flying outwards.
    const double ring = 1.1 * radius / std::sin(kPi / kCount);
    std::vector<Disk> burst(kCount);
    for (int k = 0; k < kCount; ++k) {
        const double angle = 2 * kPi * k / kCount;
        Disk& p = burst[k];
        p.radius = radius;
        p.mass = mass;
        p.position.x = float(std::clamp(world.x + ring * std::cos(angle), double(radius), double(w.width - radius)));
        p.position.y = float(std::clamp(world.y + ring * std::sin(angle), double(radius), double(w.height - radius)));
        p.velocity = carom::Vec2{float(speed * std::cos(angle)), float(speed * std::sin(angle))};
    }
    world_->addDisks(burst.data(), burst.size());
    restartEnergyDrift();
}

void Viewer::handleEvent(const SDL_Event& event) {
    ImGui_ImplSDL2_ProcessEvent(&event);
    const ImGuiIO& io = ImGui::GetIO();
    switch (event.type) {
        case SDL_QUIT: running_ = false; break;
        case SDL_WINDOWEVENT:
            if (event.window.event == SDL_WINDOWEVENT_SIZE_CHANGED ||
                event.window.event == SDL_WINDOWEVENT_DISPLAY_CHANGED)
                readDrawableSize();  // render() lays out anew
            break;
        case SDL_KEYDOWN:
            if (io.WantCaptureKeyboard) break;
            switch (event.key.keysym.sym) {
                case SDLK_ESCAPE: running_ = false; break;
                case SDLK_SPACE:
                case SDLK_p: paused_ = !paused_; break;
                case SDLK_n:
                    if (paused_) stepOnce_ = true;
                    break;
                case SDLK_r: reset(); break;
                case SDLK_g: setMotion(dt_, !gravityOn_); break;
                case SDLK_c: colouring_ = Colouring((int(colouring_) + 1) % kColouringCount); break;
                case SDLK_h: hidePanels_ = !hidePanels_; break;
                case SDLK_f: camera_.refit(); break;
                case SDLK_s: {
                    const std::string name = timestampedScreenshotName();
                    saveScreenshot(name);
                    message_ = "saved " + name;
                    std::printf("carom view: saved %s\n", name.c_str());
                    break;
                }
                default: break;
            }
            break;
        case SDL_MOUSEBUTTONDOWN:
            cursorPoint_ = {double(event.button.x), double(event.button.y)};
            if (io.WantCaptureMouse) break;
            if (event.button.button == SDL_BUTTON_LEFT) grabNearest(camera_.toWorld(cursorPixel()));
            if (event.button.button == SDL_BUTTON_RIGHT) rightDown_ = true, rightDragged_ = false;
            if (event.button.button == SDL_BUTTON_MIDDLE) middleDown_ = true;
            break;
        case SDL_MOUSEBUTTONUP:
            cursorPoint_ = {double(event.button.x), double(event.button.y)};
            if (event.button.button == SDL_BUTTON_LEFT) grabbed_ = -1;  // released at the cursor's speed
            if (event.button.button == SDL_BUTTON_RIGHT) {
                if (rightDown_ && !rightDragged_) spawnBurst(camera_.toWorld(cursorPixel()));
                rightDown_ = false;
            }
            if (event.button.button == SDL_BUTTON_MIDDLE) middleDown_ = false;
            break;
        case SDL_MOUSEMOTION:
            cursorPoint_ = {double(event.motion.x), double(event.motion.y)};
            if (rightDown_ || middleDown_) {
                if (std::abs(event.motion.xrel) + std::abs(event.motion.yrel) > 0) rightDragged_ = true;
                camera_.pan(event.motion.xrel * pixelRatio_, event.motion.yrel * pixelRatio_);
            }
            break;
        case SDL_MOUSEWHEEL:
            if (io.WantCaptureMouse) break;
            camera_.zoomAbout(cursorPixel(), std::pow(1.15, event.wheel.y));
            break;
        default: break;
    }
}

void Viewer::advance(int ticks) {
    const std::uint64_t steps = stepOnce_ ? 1 : paused_ ? 0 : std::uint64_t(ticks) * stepsPerFrame_;
    stepOnce_ = false;
    if (steps > 0) {
        const auto start = Clock::now();
        const std::uint64_t before = world_->stepCount();
        try {
            world_->step(steps);
            const std::uint64_t taken = world_->stepCount() - before;  // fewer after a stop signal
            if (taken > 0) simMsPerStep_ = secondsSince(start) * 1e3 / double(taken);
            driftTime_ += double(taken) * dt_;
        } catch (const Error& e) {
            if (headless_) throw;
            // A blow-up (the simultaneous scheme under strong gravity, too
            // long a dt) stops the backend at that step: say why, pause, and
            // keep the window for a reset (R) or another setting.
            message_ = e.what();
            paused_ = true;
        }
    }
}

void Viewer::readView() {
    static_assert(int(Colouring::Speed) == int(ViewValue::Speed) && int(Colouring::Mass) == int(ViewValue::Mass) &&
                      int(Colouring::Radius) == int(ViewValue::Radius) && int(Colouring::Id) == int(ViewValue::Id),
                  "a colouring is the value it colours by");
    views_.resize(world_->diskCount());
    viewSums_ = world_->readView(ViewValue(colouring_), views_.data(), views_.size());
    motion_ = {viewSums_.kineticEnergy, viewSums_.potentialEnergy, viewSums_.momentum, viewSums_.mass};
}

const std::vector<DiskView>& Viewer::speedViews() {
    if (colouring_ == Colouring::Speed) return views_;
    speedViews_.resize(world_->diskCount());
    world_->readView(ViewValue::Speed, speedViews_.data(), speedViews_.size());
    return speedViews_;
}

void Viewer::readBack(double realSeconds) {
    readView();
    energyHistory_.push_back({motion_.kinetic, motion_.potential});
    momentumHistory_.push_back(float(std::hypot(motion_.momentum[0], motion_.momentum[1])));
    if (energyHistory_.size() > kHistoryLength) energyHistory_.pop_front();
    if (momentumHistory_.size() > kHistoryLength) momentumHistory_.pop_front();

    // Reading the collision counters costs a device read: twice a second.
    secondsSinceReadout_ += realSeconds;
    if (secondsSinceReadout_ >= 0.5) {
        const std::uint64_t total = collisionsBeforeReset_ + world_->collisionCount();
        collisionsPerSecond_ = (total - std::min(total, collisionsAtLastReadout_)) / secondsSinceReadout_;
        collisionsAtLastReadout_ = total;
        secondsSinceReadout_ = 0;
    }
}

DiskColours Viewer::diskColours() const {
    switch (colouring_) {
        case Colouring::Speed: {
            // Speeds map to colour up to 2.5 times the rms speed, so the
            // scale follows the temperature.
            const double meanSquare = viewSums_.speedSquared / double(std::max<std::size_t>(1, views_.size()));
            return {false, 0.0f, float(std::max(1e-12, 2.5 * std::sqrt(meanSquare)))};
        }
        case Colouring::Mass:
        case Colouring::Radius: return {false, viewSums_.minValue, viewSums_.maxValue};
        case Colouring::Id: break;
    }
    return {true, 0.0f, 0.0f};
}

void Viewer::render() {
    // The panels first: whether they are shown or collapsed decides the view
    // the box is drawn in this frame.
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplSDL2_NewFrame();
    ImGui::NewFrame();
    if (!hidePanels_) drawPanels();
    layOut();
    const WorldDef& w = world_->def();
    renderer_->draw(camera_, w.width, w.height, views_, diskColours());
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void Viewer::saveScreenshot(const std::string& path) { writeFramePng(path, drawableWidth_, drawableHeight_); }

int Viewer::run() {
    std::printf("carom view: %zu disks on %s, %s collisions, drawn by %s\n", world_->diskCount(),
                world_->deviceName().c_str(), collisionSchemeName(collisions_), glRenderer_.c_str());
    if (!headless_)
        for (const Control& control : kControls) std::printf("  %-18s %s\n", control.keys, control.action);
    std::vector<double> frameMs, steppingMs, readingMs, drawingMs;
    auto last = Clock::now();
    std::uint64_t rendered = 0;
    int signal = 0;
    while (running_ && (!headless_ || rendered < options_.frames)) {
        const std::uint64_t frame = rendered;
        const auto frameStart = Clock::now();
        const double realSeconds = std::chrono::duration<double>(frameStart - last).count();
        last = frameStart;
        for (SDL_Event event; SDL_PollEvent(&event);) {
            // Headless, the input is the --events script's alone: input from
            // the virtual display (its pointer entering the window) would
            // arrive at no fixed frame.
            if (!headless_ || !isKeyboardOrMouse(event.type)) handleEvent(event);
        }
        for (; nextScripted_ < script_.size() && script_[nextScripted_].frame == frame + 1; ++nextScripted_)
            handleEvent(script_[nextScripted_].event);
        if (options_.switchCollisions && options_.switchCollisions->first == frame + 1) {
            setCollisions(options_.switchCollisions->second);
            std::printf("carom view: %s\n", message_.c_str());
        }

        // Headless frames are one tick each, so a recording is the same on
        // every machine; a window keeps real time with the accumulator.
        int ticks = 1;
        if (!headless_) {
            accumulator_ += realSeconds;
            ticks = std::min(int(accumulator_ / kTickSeconds), kMaxTicksPerFrame);
            accumulator_ = std::min(accumulator_ - ticks * kTickSeconds, kTickSeconds);
        }
        const auto stepStart = Clock::now();
        applyGrab(headless_ ? kTickSeconds : realSeconds);  // headless: a throw's speed the same on every machine
        advance(ticks);
        const auto readStart = Clock::now();
        readBack(realSeconds);
        const auto drawStart = Clock::now();

        render();
        if (!options_.record.empty()) {
            char name[32];
            std::snprintf(name, sizeof name, "frame_%05llu.png", static_cast<unsigned long long>(frame));
            saveScreenshot((std::filesystem::path(options_.record) / name).string());
        }
        // A stop signal makes this frame the last: the screenshot shows it.
        signal = app::StopSignals::received();
        ++rendered;
        if (headless_ && (rendered == options_.frames || signal != 0) && !options_.screenshot.empty())
            saveScreenshot(options_.screenshot);
        SDL_GL_SwapWindow(window_);
        // Headless frames are timed: OpenGL's queued work counts in this
        // frame's drawing, not in the next frame's stepping.
        if (headless_) glFinish();
        frameMs.push_back(secondsSince(frameStart) * 1e3);
        steppingMs.push_back(millisecondsBetween(stepStart, readStart));
        readingMs.push_back(millisecondsBetween(readStart, drawStart));
        drawingMs.push_back(secondsSince(drawStart) * 1e3);
        if (signal != 0) break;
    }
    if (!options_.outputState.empty()) io::writeState(options_.outputState, *world_);
    const std::string groups = sceneFileEdit_ ? " (the scene's groups: " + groupsText(*sceneFileEdit_) + ")" : "";
    if (headless_)
        std::printf(
            "carom view: %llu frames of %zu disks%s, %s collisions, %s over %.4g time "
            "units (kinetic %+.4g, potential %+.4g); median frame %.2f ms (stepping %.2f ms, reading back %.2f ms, "
            "drawing %.2f ms)\n",
            static_cast<unsigned long long>(rendered), world_->diskCount(), groups.c_str(),
            collisionSchemeName(collisions_), energyDriftText().c_str(), driftTime_,
            motion_.kinetic - motionAtDriftStart_.kinetic, motion_.potential - motionAtDriftStart_.potential,
            median(frameMs), median(steppingMs), median(readingMs), median(drawingMs));
    if (signal == 0) return 0;
    std::fprintf(stderr, "carom view: interrupted by %s", app::signalName(signal));
    if (headless_) {
        std::fprintf(stderr, " after %llu of %llu frames", static_cast<unsigned long long>(rendered),
                     static_cast<unsigned long long>(options_.frames));
        if (!options_.screenshot.empty())
            std::fprintf(stderr, "; %s shows frame %llu, the last rendered", options_.screenshot.c_str(),
                         static_cast<unsigned long long>(rendered));
        if (!options_.record.empty())
            std::fprintf(stderr, "; %s holds frame_00000.png to frame_%05llu.png", options_.record.c_str(),
                         static_cast<unsigned long long>(rendered - 1));
    }
    std::fputc('\n', stderr);
    return app::signalExitStatus(signal);
}

namespace {

// Whether `name` is one of the frames --record writes: frame_00000.png, ...
bool isRecordedFrame(const std::string& name) {
    const std::string prefix = "frame_", suffix = ".png";
    if (name.size() < prefix.size() + 5 + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return false;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    return std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Refuses, before the window opens, outputs that would be lost or replace
// an input (app/output_plan.h).
void checkFiles(const ViewOptions& o) {
    app::OutputPlan plan;
    for (const auto& [option, path] : {std::pair{"--scene", o.scene.sceneFile},
                                       std::pair{"--input-state", o.scene.inputState}, std::pair{"--events", o.events}})
        if (!path.empty()) plan.input(option, path);
    for (const auto& [option, path] :
         {std::pair{"--screenshot", o.screenshot}, std::pair{"--output-state", o.outputState}})
        if (!path.empty()) plan.output(option, path);
    if (!o.record.empty()) plan.outputFolder("--record", o.record, isRecordedFrame);
    plan.check();
}

}  // namespace

int runViewer(const ViewOptions& options) {
    // From the start: a signal while the window opens stops after frame 1.
    const app::StopSignals stopSignals(app::StopSignals::FirstSignal::Stops, "carom view");
    checkFiles(options);
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace carom::viewer
