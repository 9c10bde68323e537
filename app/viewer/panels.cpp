// The Dear ImGui panels of the viewer, one column docked to the window's left
// edge (layout.h): scene, simulation, live readouts (the energies with the
// total's drift, momentum), the speed distribution against Maxwell-Boltzmann,
// and the controls.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "app/viewer/layout.h"
#include "app/viewer/viewer_app.h"

namespace carom::viewer {
namespace {

// A dark rectangle the width of the panel and `height` high at the cursor,
// for drawing into; returns its top-left corner. ImGui::Dummy(size) ends it.
ImVec2 canvas(ImVec2 size) {
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::GetWindowDrawList()->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y),
                                              IM_COL32(30, 30, 36, 255));
    return origin;
}

// The speed histogram as a probability density, with the 2D Maxwell-Boltzmann
// (Rayleigh) density for the current temperature drawn over it.
// `speeds`: views whose values are speeds; `sums`: the readouts' sums.
void speedHistogram(const std::vector<DiskView>& speeds, const ViewSums& sums) {
    constexpr int kBins = 40;
    const double n = double(std::max<std::size_t>(1, speeds.size()));
    const double meanMass = sums.mass / n;
    const double kT = sums.kineticEnergy / n;  // 2D: E_kin = N kT
    const double vmax = std::max(1e-12, 3.0 * std::sqrt(2.0 * kT / meanMass));
    const double binWidth = vmax / kBins;
    std::vector<double> density(kBins, 0.0);
    for (const DiskView& view : speeds) {
        const int bin = int(view.value / binWidth);
        if (bin >= 0 && bin < kBins) density[bin] += 1.0 / (n * binWidth);
    }
    auto rayleigh = [&](double v) { return meanMass * v / kT * std::exp(-meanMass * v * v / (2 * kT)); };
    const double peak = std::max(*std::max_element(density.begin(), density.end()), rayleigh(std::sqrt(kT / meanMass)));

    const ImVec2 size(ImGui::GetContentRegionAvail().x, 120);
    const ImVec2 origin = canvas(size);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    auto toScreen = [&](double v, double f) {
        return ImVec2(origin.x + float(v / vmax) * size.x, origin.y + size.y - float(f / (1.1 * peak)) * size.y);
    };
    for (int b = 0; b < kBins; ++b)
        draw->AddRectFilled(toScreen(b * binWidth, density[b]), toScreen((b + 1) * binWidth, 0),
                            IM_COL32(90, 150, 220, 255));
    std::vector<ImVec2> curve;
    for (int k = 0; k <= 100; ++k) curve.push_back(toScreen(vmax * k / 100, rayleigh(vmax * k / 100)));
    draw->AddPolyline(curve.data(), int(curve.size()), IM_COL32(250, 200, 60, 255), 0, 2.0f);
    ImGui::Dummy(size);
    ImGui::TextDisabled("bars: speeds; curve: Rayleigh for kT = %.4g, m = %.3g", kT, meanMass);
}

// The kinetic energy over the last frames, on a scale that includes 0. With
// gravity, the kinetic, potential and total (white) energies' changes since
// `driftStart` instead: the kinetic and potential lines mirror each other
// while the total stays flat, however large the potential energy is beside
// the kinetic.
void energyPlot(const std::deque<EnergySample>& history, bool gravity, const EnergySample& driftStart) {
    constexpr ImU32 kKinetic = IM_COL32(90, 150, 220, 255), kPotential = IM_COL32(120, 200, 120, 255),
                    kTotal = IM_COL32(240, 240, 240, 255);
    const EnergySample zero = gravity ? driftStart : EnergySample{};
    const auto kinetic = [&](const EnergySample& e) { return e.kinetic - zero.kinetic; };
    const auto potential = [&](const EnergySample& e) { return e.potential - zero.potential; };
    const auto total = [&](const EnergySample& e) { return kinetic(e) + potential(e); };
    double lo = 0, hi = 0;
    for (const EnergySample& e : history)
        for (const double value : {kinetic(e), gravity ? potential(e) : 0.0, gravity ? total(e) : 0.0}) {
            lo = std::min(lo, value);
            hi = std::max(hi, value);
        }
    const double margin = hi > lo ? 0.05 * (hi - lo) : 1.0;  // keeps the lines off the edges
    lo -= margin;
    hi += margin;
    const ImVec2 size(ImGui::GetContentRegionAvail().x, 70);
    const ImVec2 origin = canvas(size);
    const auto line = [&](ImU32 colour, auto&& value) {
        std::vector<ImVec2> points;
        for (std::size_t k = 0; k < history.size(); ++k)
            points.push_back(ImVec2(origin.x + size.x * float(k) / float(std::max<std::size_t>(1, history.size() - 1)),
                                    origin.y + size.y * float(1 - (value(history[k]) - lo) / (hi - lo))));
        ImGui::GetWindowDrawList()->AddPolyline(points.data(), int(points.size()), colour, 0, 1.5f);
    };
    // The flat total first, under the lines that move.
    if (gravity) line(kTotal, total);
    line(kKinetic, kinetic);
    if (gravity) line(kPotential, potential);
    ImGui::Dummy(size);
    const EnergySample last = history.empty() ? EnergySample{} : history.back();
    ImGui::TextColored(ImColor(kKinetic), "kinetic %.6g", last.kinetic);
    if (gravity) {
        ImGui::SameLine();
        ImGui::TextColored(ImColor(kPotential), "potential %.6g", last.potential);
        ImGui::SameLine();
        ImGui::TextColored(ImColor(kTotal), "total");
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("lines: changes since the drift's start");
        ImGui::PopTextWrapPos();
    }
}

// `text` wrapped to a readable width, while the last item is hovered (also
// when it is disabled).
void tooltip(const std::string& text) {
    if (!ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) return;
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30);
    ImGui::TextUnformatted(text.c_str());
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
}

void plot(const char* label, const std::deque<float>& history) {
    const std::vector<float> values(history.begin(), history.end());
    ImGui::PlotLines(label, values.data(), int(values.size()), 0, nullptr, FLT_MAX, FLT_MAX, ImVec2(0, 50));
}

// One group of disks: how many (at least one), their radii and masses; each
// InputFloat2 edits a min and the max declared right after it (SceneDef and
// GroupDef, carom/types.h). The count and the seed are edited at their own
// width, so no value is cut short.
void groupInputs(const char* countLabel, std::uint32_t& count, float& radiusMin, float& massMin) {
    const std::uint32_t step = 1;
    if (ImGui::InputScalar(countLabel, ImGuiDataType_U32, &count, &step)) count = std::max<std::uint32_t>(1, count);
    ImGui::InputFloat2("radius min/max", &radiusMin);
    ImGui::InputFloat2("mass min/max", &massMin);
}

void seedInput(std::uint64_t& seed) {
    const std::uint64_t step = 1;
    ImGui::InputScalar("seed", ImGuiDataType_U64, &seed, &step);
}

}  // namespace

void Viewer::drawScenePanel() {
    groupInputs("particles", sceneEdit_.particles, sceneEdit_.radiusMin, sceneEdit_.massMin);
    ImGui::SliderFloat("packing", &sceneEdit_.packing, 0.01f, 0.7f);
    ImGui::InputFloat("speed", &sceneEdit_.speed);
    seedInput(sceneEdit_.seed);
    if (ImGui::Button("Apply")) applyScene(sceneEdit_);
}

// The --scene file's groups, as the file (and the options given with it) set
// them; Apply places them anew.
void Viewer::drawSceneFilePanel() {
    SceneFileDef& scene = *sceneFileEdit_;
    ImGui::TextWrapped("%s", scene.path.c_str());
    if (scene.packing > 0)
        ImGui::Text("box sized for packing %.3g", scene.packing);
    else
        ImGui::Text("box %g x %g", scene.world.width, scene.world.height);
    for (std::size_t g = 0; g < scene.groups.size(); ++g) {
        GroupDef& group = scene.groups[g];
        ImGui::PushID(int(g));
        ImGui::Separator();
        ImGui::Text("%s%s", group.name.c_str(), group.region ? ", in its region" : "");
        groupInputs("count", group.count, group.radiusMin, group.massMin);
        // The file gives a group a speed or a temperature (Maxwell-Boltzmann
        // velocities); a temperature edited to 0 turns back to the speed.
        if (group.temperature > 0)
            ImGui::InputFloat("temperature", &group.temperature);
        else
            ImGui::InputFloat("speed", &group.speed);
        ImGui::PopID();
    }
    ImGui::Separator();
    if (!scene.disks.empty()) ImGui::Text("and %zu single [[disk]]s", scene.disks.size());
    seedInput(scene.seed);
    if (ImGui::Button("Apply")) applySceneFile(scene);
}

void Viewer::drawPanels() {
    // Placed and sized every frame; the title bar's arrow collapses it.
    const ImVec2 window = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(float(panelColumnWidth(window.x)), window.y), ImGuiCond_Always);
    ImGui::Begin("carom", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
    panelsCollapsed_ = ImGui::IsWindowCollapsed();

    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (sceneFileEdit_)
            drawSceneFilePanel();
        else
            drawScenePanel();
        ImGui::SameLine();
        if (ImGui::Button("Reset (R)")) reset();
    }

    if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::TextWrapped("%s on %s", computeEngineName(world_->def().engine), world_->deviceName().c_str());
        if (ImGui::BeginCombo("collisions", collisionSchemeName(collisions_))) {
            for (const CollisionScheme scheme :
                 {CollisionScheme::Simultaneous, CollisionScheme::Pairwise, CollisionScheme::Events}) {
                const bool refused = scheme == CollisionScheme::Events && !eventsRefusal_.empty();
                ImGui::BeginDisabled(refused);
                if (ImGui::Selectable(collisionSchemeName(scheme), scheme == collisions_) && scheme != collisions_)
                    setCollisions(scheme);
                ImGui::EndDisabled();
                if (refused) tooltip(eventsRefusal_);
            }
            ImGui::EndCombo();
        }
        tooltip(
            "--collisions. simultaneous: the seed's scheme, impulses from the state before the step, summed (its "
            "energy drifts, markedly under gravity); pairwise: binary collisions at their exact contact times (energy "
            "kept); "
            "events: exact event-driven dynamics in double, CPU only. A switch keeps the disks as they are and "
            "restarts the energy drift.");
        float dt = dt_;
        if (ImGui::InputFloat("dt", &dt, 0, 0, "%.5f") && dt > 0 && std::isfinite(dt)) setMotion(dt, gravityOn_);
        ImGui::SliderInt("steps per frame", &stepsPerFrame_, 0, 200);
        bool gravity = gravityOn_;
        if (ImGui::Checkbox("gravity (G)", &gravity)) setMotion(dt_, gravity);
        ImGui::SameLine();
        if (ImGui::InputFloat2("##gravity", &gravity_.x) && gravityOn_) setMotion(dt_, true);
        ImGui::Checkbox("paused (Space)", &paused_);
        ImGui::Text("colouring (C): %s", colouringName(colouring_));
    }

    if (ImGui::CollapsingHeader("Readouts", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::Text("%zu disks, %.0f frames/s, %.3f ms per step", views_.size(), ImGui::GetIO().Framerate,
                    simMsPerStep_);
        ImGui::Text("collisions per second: %.0f", collisionsPerSecond_);
        const bool events = world_->def().collisions == CollisionScheme::Events;
        if (events) {
            const EventCounts counts = world_->eventCounts();
            ImGui::Text("events: %llu wall bounces, %llu cell crossings",
                        static_cast<unsigned long long>(counts.wallBounces),
                        static_cast<unsigned long long>(counts.cellCrossings));
        }
        energyPlot(energyHistory_, gravityOn_, {motionAtDriftStart_.kinetic, motionAtDriftStart_.potential});
        ImGui::Text("total energy %.6g; %s", motion_.kinetic + motion_.potential, energyDriftText().c_str());
        tooltip(
            "(E - E0) / |E0|: the total energy's relative change since E0 was measured; n/a when E0 is 0 "
            "(then the change itself). Near 0 with the pairwise and events schemes; not with the simultaneous "
            "one, markedly under gravity.");
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled(
            "drift: the relative change%s over the last %.4g time units, since the scene, a reset, a grab, a "
            "burst, dt, gravity or the collision scheme last changed",
            events ? " of the engine's double state" : "", driftTime_);
        ImGui::PopTextWrapPos();
        ImGui::Text("momentum (%.4g, %.4g)", motion_.momentum[0], motion_.momentum[1]);
        plot("##momentum", momentumHistory_);
        speedHistogram(speedViews(), viewSums_);
    }
    if (ImGui::CollapsingHeader("Controls") && ImGui::BeginTable("controls", 2)) {
        for (const Control& control : kControls) {
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(control.keys);
            ImGui::TableNextColumn();
            ImGui::TextWrapped("%s", control.action);
        }
        ImGui::EndTable();
    }
    if (!message_.empty()) ImGui::TextColored(ImVec4(1, 0.7f, 0.3f, 1), "%s", message_.c_str());
    ImGui::End();
}

}  // namespace carom::viewer
