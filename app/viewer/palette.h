// Colours. Disks are coloured in the renderer's vertex shader (renderer.cpp):
// viridis at 9 stops for continuous quantities, and idColour below for ids,
// which the screenshot tests check the shader's copy against.
#pragma once

#include <cmath>
#include <cstdint>

namespace carom::viewer {

struct Rgb {
    float r, g, b;
};

enum class Colouring { Speed, Mass, Radius, Id };
constexpr int kColouringCount = 4;
inline const char* colouringName(Colouring c) {
    constexpr const char* names[] = {"speed", "mass", "radius", "id"};
    return names[static_cast<int>(c)];
}

// A bright colour that is the same for an id in every frame and every run.
inline Rgb idColour(std::uint32_t id) {
    std::uint32_t h = id * 2654435761u;  // Knuth's multiplicative hash
    h ^= h >> 15;
    const float hue = (h % 360u) / 60.0f;
    const float x = 1.0f - std::fabs(std::fmod(hue, 2.0f) - 1.0f);
    const int sector = static_cast<int>(hue);
    const Rgb rgb[] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
    const Rgb c = rgb[sector % 6];
    return {0.25f + 0.75f * c.r, 0.25f + 0.75f * c.g, 0.25f + 0.75f * c.b};
}

// Background outside the box, the box interior and the walls.
constexpr Rgb kBackground{0.09f, 0.09f, 0.11f};
constexpr Rgb kBoxInterior{0.16f, 0.17f, 0.20f};
constexpr Rgb kWall{0.85f, 0.85f, 0.85f};

}  // namespace carom::viewer
