#include "app/viewer/renderer.h"

#include <cstddef>
#include <string>

#include "app/viewer/palette.h"
#include <carom/types.h>

namespace carom::viewer {
namespace {

// The disks' colour maps: viridis at 9 stops, and a port of palette.h's
// idColour (tests/view_check.cpp checks screenshots against both).
const char* const kDiskVertex = R"(#version 330 core
layout(location = 0) in vec2 corner;   // unit quad, -1..1
layout(location = 1) in vec3 disk;     // centre x, y and radius, world units
layout(location = 2) in float value;   // DiskView::value
uniform vec2 scale;                    // world -> normalized device coordinates
uniform vec2 offset;
uniform bool byId;
uniform float low, high;
out vec2 local;
out vec3 diskColour;
const vec3 stops[9] = vec3[9](vec3(0.267, 0.005, 0.329), vec3(0.283, 0.141, 0.458), vec3(0.254, 0.265, 0.530),
                              vec3(0.207, 0.372, 0.553), vec3(0.164, 0.471, 0.558), vec3(0.128, 0.567, 0.551),
                              vec3(0.135, 0.659, 0.518), vec3(0.478, 0.821, 0.318), vec3(0.993, 0.906, 0.144));
vec3 viridis(float t) {
    t = isnan(t) || isinf(t) ? 0.0 : clamp(t, 0.0, 1.0);
    float position = t * 8.0;
    int i = min(int(position), 7);
    return mix(stops[i], stops[i + 1], position - float(i));
}
vec3 idColour(uint id) {
    uint h = id * 2654435761u;
    h ^= h >> 15;
    float hue = float(h % 360u) / 60.0;
    float x = 1.0 - abs(mod(hue, 2.0) - 1.0);
    vec3 sectors[6] = vec3[6](vec3(1, x, 0), vec3(x, 1, 0), vec3(0, 1, x), vec3(0, x, 1), vec3(x, 0, 1), vec3(1, 0, x));
    return 0.25 + 0.75 * sectors[int(hue) % 6];
}
void main() {
    local = corner;
    diskColour = byId ? idColour(uint(value)) : viridis(high > low ? (value - low) / (high - low) : 0.5);
    gl_Position = vec4((disk.xy + corner * disk.z) * scale + offset, 0.0, 1.0);
}
)";

const char* const kDiskFragment = R"(#version 330 core
in vec2 local;
in vec3 diskColour;
out vec4 fragment;
void main() {
    float r = length(local);
    float edge = fwidth(r);
    if (r > 1.0 + edge) discard;
    // A darker rim so touching disks stay distinguishable, and an
    // antialiased edge.
    vec3 rgb = mix(diskColour, diskColour * 0.55, smoothstep(0.8, 1.0, r));
    fragment = vec4(rgb, 1.0 - smoothstep(1.0 - edge, 1.0 + edge, r));
}
)";

const char* const kFlatVertex = R"(#version 330 core
layout(location = 0) in vec2 position; // world units
uniform vec2 scale;
uniform vec2 offset;
void main() { gl_Position = vec4(position * scale + offset, 0.0, 1.0); }
)";

const char* const kFlatFragment = R"(#version 330 core
uniform vec4 colour;
out vec4 fragment;
void main() { fragment = colour; }
)";

GLuint compile(GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        throw Error(std::string("viewer: shader compilation failed: ") + log);
    }
    return shader;
}

GLuint link(const char* vertex, const char* fragment) {
    const GLuint program = glCreateProgram();
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex), fs = compile(GL_FRAGMENT_SHADER, fragment);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        throw Error(std::string("viewer: shader link failed: ") + log);
    }
    return program;
}

// World -> normalized device coordinates for the camera, as scale and offset:
// the offset is where toPixel puts the world origin, so drawing and picking agree.
void setCameraUniforms(GLuint program, const Camera& camera) {
    const Vec2 window = camera.window();
    const Vec2 origin = camera.toPixel({0, 0});
    const float sx = float(2 * camera.pixelsPerUnit() / window.x);
    const float sy = float(2 * camera.pixelsPerUnit() / window.y);
    glUniform2f(glGetUniformLocation(program, "scale"), sx, sy);
    glUniform2f(glGetUniformLocation(program, "offset"), float(2 * origin.x / window.x - 1),
                float(1 - 2 * origin.y / window.y));
}

void appendRectangle(std::vector<float>& corners, float x0, float y0, float x1, float y1) {
    corners.insert(corners.end(), {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1});
}

}  // namespace

std::uint32_t packColour(float r, float g, float b) {
    auto byte = [](float v) { return std::uint32_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
    return byte(r) | byte(g) << 8 | byte(b) << 16 | 0xFFu << 24;
}

Renderer::Renderer() {
    diskProgram_ = link(kDiskVertex, kDiskFragment);
    flatProgram_ = link(kFlatVertex, kFlatFragment);

    glGenVertexArrays(1, &diskVao_);
    glBindVertexArray(diskVao_);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};  // a triangle strip: 4 vertex shader runs a disk
    glGenBuffers(1, &cornerBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, cornerBuffer_);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glGenBuffers(1, &instanceBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, instanceBuffer_);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(DiskView), nullptr);  // position, radius
    glVertexAttribDivisor(1, 1);
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(DiskView),
                          reinterpret_cast<const void*>(offsetof(DiskView, value)));
    glVertexAttribDivisor(2, 1);

    glGenVertexArrays(1, &flatVao_);
    glBindVertexArray(flatVao_);
    glGenBuffers(1, &flatBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, flatBuffer_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
}

Renderer::~Renderer() {
    glDeleteBuffers(1, &cornerBuffer_);
    glDeleteBuffers(1, &instanceBuffer_);
    glDeleteBuffers(1, &flatBuffer_);
    glDeleteVertexArrays(1, &diskVao_);
    glDeleteVertexArrays(1, &flatVao_);
    glDeleteProgram(diskProgram_);
    glDeleteProgram(flatProgram_);
}

void Renderer::drawRectangles(const Camera& camera, const std::vector<float>& corners, std::uint32_t rgba) {
    glUseProgram(flatProgram_);
    setCameraUniforms(flatProgram_, camera);
    glUniform4f(glGetUniformLocation(flatProgram_, "colour"), (rgba & 0xFF) / 255.0f, (rgba >> 8 & 0xFF) / 255.0f,
                (rgba >> 16 & 0xFF) / 255.0f, 1.0f);
    glBindVertexArray(flatVao_);
    glBindBuffer(GL_ARRAY_BUFFER, flatBuffer_);
    glBufferData(GL_ARRAY_BUFFER, corners.size() * sizeof(float), corners.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(corners.size() / 2));
}

void Renderer::draw(const Camera& camera, float boxWidth, float boxHeight, const std::vector<DiskView>& disks,
                    const DiskColours& colours) {
    const Vec2 window = camera.window();
    glViewport(0, 0, GLsizei(window.x), GLsizei(window.y));
    glClearColor(kBackground.r, kBackground.g, kBackground.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);

    std::vector<float> corners;
    appendRectangle(corners, 0, 0, boxWidth, boxHeight);
    drawRectangles(camera, corners, packColour(kBoxInterior.r, kBoxInterior.g, kBoxInterior.b));

    const float w = float(kWallPixels / camera.pixelsPerUnit());
    corners.clear();
    appendRectangle(corners, -w, -w, boxWidth + w, 0);                     // bottom
    appendRectangle(corners, -w, boxHeight, boxWidth + w, boxHeight + w);  // top
    appendRectangle(corners, -w, 0, 0, boxHeight);                         // left
    appendRectangle(corners, boxWidth, 0, boxWidth + w, boxHeight);        // right
    drawRectangles(camera, corners, packColour(kWall.r, kWall.g, kWall.b));

    glUseProgram(diskProgram_);
    setCameraUniforms(diskProgram_, camera);
    glUniform1i(glGetUniformLocation(diskProgram_, "byId"), colours.byId);
    glUniform1f(glGetUniformLocation(diskProgram_, "low"), colours.low);
    glUniform1f(glGetUniformLocation(diskProgram_, "high"), colours.high);
    glBindVertexArray(diskVao_);
    glBindBuffer(GL_ARRAY_BUFFER, instanceBuffer_);
    glBufferData(GL_ARRAY_BUFFER, disks.size() * sizeof(DiskView), disks.data(), GL_STREAM_DRAW);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(disks.size()));
    glBindVertexArray(0);
}

}  // namespace carom::viewer
