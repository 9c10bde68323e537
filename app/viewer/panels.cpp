// The Dear ImGui panels of the viewer: scene, simulation, live readouts and
// the speed distribution against Maxwell-Boltzmann.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "app/viewer/viewer_app.h"

namespace carom::viewer {
namespace {

// The speed histogram as a probability density, with the 2D Maxwell-Boltzmann
// (Rayleigh) density for the current temperature drawn over it.
void speedHistogram(const std::vector<Particle>& particles, double kineticEnergy) {
    constexpr int kBins = 40;
    const double n = double(std::max<std::size_t>(1, particles.size()));
    double meanMass = 0;
    for (const Particle& p : particles) meanMass += p.mass;
    meanMass /= n;
    const double kT = kineticEnergy / n;  // 2D: E_kin = N kT
    const double vmax = std::max(1e-12, 3.0 * std::sqrt(2.0 * kT / meanMass));
    const double binWidth = vmax / kBins;
    std::vector<double> density(kBins, 0.0);
    for (const Particle& p : particles) {
        const int bin = int(std::hypot(p.velocity.x, p.velocity.y) / binWidth);
        if (bin >= 0 && bin < kBins) density[bin] += 1.0 / (n * binWidth);
    }
    auto rayleigh = [&](double v) { return meanMass * v / kT * std::exp(-meanMass * v * v / (2 * kT)); };
    const double peak = std::max(*std::max_element(density.begin(), density.end()),
                                 rayleigh(std::sqrt(kT / meanMass)));

    const ImVec2 size(ImGui::GetContentRegionAvail().x, 120);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y), IM_COL32(30, 30, 36, 255));
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

void plot(const char* label, const std::deque<float>& history) {
    const std::vector<float> values(history.begin(), history.end());
    ImGui::PlotLines(label, values.data(), int(values.size()), 0, nullptr, FLT_MAX, FLT_MAX, ImVec2(0, 50));
}

}  // namespace

void Viewer::drawPanels() {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("carom");

    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
        int particles = int(sceneEdit_.particles);
        if (ImGui::InputInt("particles", &particles)) sceneEdit_.particles = std::uint32_t(std::max(1, particles));
        ImGui::SliderFloat("packing", &sceneEdit_.packing, 0.01f, 0.7f);
        ImGui::InputFloat2("radius min/max", &sceneEdit_.radiusMin);
        ImGui::InputFloat2("mass min/max", &sceneEdit_.massMin);
        ImGui::InputFloat("speed", &sceneEdit_.speed);
        int seed = int(sceneEdit_.seed);
        if (ImGui::InputInt("seed", &seed)) sceneEdit_.seed = std::uint64_t(std::max(0, seed));
        if (ImGui::Button("Apply")) applyScene(sceneEdit_);
        ImGui::SameLine();
        if (ImGui::Button("Reset (R)")) reset();
    }

    if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::TextWrapped("%s on %s", backend_->name().c_str(), backend_->device().c_str());
        float dt = dt_;
        if (ImGui::InputFloat("dt", &dt, 0, 0, "%.5f") && dt > 0 && std::isfinite(dt)) {
            dt_ = dt;
            backend_->setMotion(dt_, gravityOn_ ? gravity_ : float2{0, 0});
        }
        ImGui::SliderInt("steps per frame", &stepsPerFrame_, 0, 200);
        bool gravity = gravityOn_;
        if (ImGui::Checkbox("gravity (G)", &gravity)) setGravity(gravity);
        ImGui::SameLine();
        if (ImGui::InputFloat2("##gravity", &gravity_.x) && gravityOn_) setGravity(true);
        ImGui::Checkbox("paused (Space)", &paused_);
        ImGui::Text("colouring (C): %s", colouringName(colouring_));
    }

    if (ImGui::CollapsingHeader("Readouts", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::Text("%zu disks, %.0f frames/s, %.3f ms per step", particles_.size(), ImGui::GetIO().Framerate,
                    simMsPerStep_);
        ImGui::Text("collisions per second: %.0f", collisionsPerSecond_);
        ImGui::Text("kinetic energy %.6g", kineticEnergy_);
        plot("##energy", energyHistory_);
        ImGui::Text("momentum (%.4g, %.4g)", momentum_[0], momentum_[1]);
        plot("##momentum", momentumHistory_);
        speedHistogram(particles_, kineticEnergy_);
    }
    if (!message_.empty()) ImGui::TextColored(ImVec4(1, 0.7f, 0.3f, 1), "%s", message_.c_str());
    ImGui::End();

    ImGui::SetNextWindowPos(ImVec2(float(drawableWidth_ / pixelRatio_) - 10, 10), ImGuiCond_Always, ImVec2(1, 0));
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("Controls", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
    ImGui::TextUnformatted(kControls);
    ImGui::End();
}

}  // namespace carom::viewer
