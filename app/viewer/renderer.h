// Draws the box and all disks: one instanced draw call for the disks (a quad
// per disk, the circle cut out in the fragment shader, the colour computed in
// the vertex shader from the disk's 16-byte view), so drawing stays
// interactive far beyond 10^4 disks. Needs a current OpenGL 3.3 core context.
#pragma once

#include <cstdint>
#include <vector>

#include "app/viewer/camera.h"
#include "app/viewer/gl.h"
#include <carom/types.h>

namespace carom::viewer {

// How a disk's DiskView::value becomes its colour, in the vertex shader:
// viridis((value - low) / (high - low)) (0.5 where high <= low), or with
// byId the id's colour (palette.h's idColour).
struct DiskColours {
    bool byId = false;
    float low = 0.0f, high = 1.0f;
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
    void draw(const Camera& camera, float boxWidth, float boxHeight, const std::vector<DiskView>& disks,
              const DiskColours& colours);

    static constexpr float kWallPixels = 2.0f;

private:
    void drawRectangles(const Camera& camera, const std::vector<float>& corners, std::uint32_t rgba);

    GLuint diskProgram_ = 0, flatProgram_ = 0;
    GLuint diskVao_ = 0, cornerBuffer_ = 0, instanceBuffer_ = 0;
    GLuint flatVao_ = 0, flatBuffer_ = 0;
};

}  // namespace carom::viewer
