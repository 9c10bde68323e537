// Draws the box and all disks: one instanced draw call for the disks (a quad
// per disk, the circle cut out in the fragment shader), so drawing stays
// interactive far beyond 10^4 disks. Needs a current OpenGL 3.3 core context.
#pragma once

#include <cstdint>
#include <vector>

#include "app/viewer/camera.h"
#include "app/viewer/gl.h"

namespace carom::viewer {

struct DiskInstance {
    float x, y;          // centre [world]
    float radius;        // [world]
    std::uint32_t rgba;  // colour, bytes R, G, B, A in memory order
};

std::uint32_t packColour(float r, float g, float b);

class Renderer {
public:
    Renderer();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Clears the window, draws the box interior, the walls (kWallPixels wide,
    // just outside the box edge) and the disks.
    void draw(const Camera& camera, float boxWidth, float boxHeight, const std::vector<DiskInstance>& disks);

    static constexpr float kWallPixels = 2.0f;

private:
    void drawRectangles(const Camera& camera, const std::vector<float>& corners, std::uint32_t rgba);

    GLuint diskProgram_ = 0, flatProgram_ = 0;
    GLuint diskVao_ = 0, cornerBuffer_ = 0, instanceBuffer_ = 0;
    GLuint flatVao_ = 0, flatBuffer_ = 0;
};

}  // namespace carom::viewer
