// Disk colours. A perceptually ordered colour map (viridis, sampled at 9
// stops) for continuous quantities, and a fixed hash colour for ids.
#pragma once

#include <algorithm>
#include <array>
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

// t in [0, 1] (clamped) to viridis.
inline Rgb viridis(float t) {
    static constexpr std::array<Rgb, 9> stops = {{{0.267f, 0.005f, 0.329f},
                                                  {0.283f, 0.141f, 0.458f},
                                                  {0.254f, 0.265f, 0.530f},
                                                  {0.207f, 0.372f, 0.553f},
                                                  {0.164f, 0.471f, 0.558f},
                                                  {0.128f, 0.567f, 0.551f},
                                                  {0.135f, 0.659f, 0.518f},
                                                  {0.478f, 0.821f, 0.318f},
                                                  {0.993f, 0.906f, 0.144f}}};
    t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) : 0.0f;
    const float position = t * (stops.size() - 1);
    const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(position), stops.size() - 2);
    const float f = position - i;
    const Rgb a = stops[i], b = stops[i + 1];
    return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
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
