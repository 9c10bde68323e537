// Checks the viewer's headless output (see tests/CMakeLists.txt: the
// view.screenshot and view.record fixtures render it under Xvfb first).
//
// The scene is tests/data/view_disks.csv in a 100 x 50 box drawn in a
// 400 x 300 window. The camera fits the box with a 20-pixel margin on the
// tighter side: 3.6 pixels per unit, the box spans pixels x 20..380 and
// y 60..240 (y down), so world (x, y) is pixel (20 + 3.6 x, 240 - 3.6 y).
// These numbers are worked out by hand, not by the viewer's camera code.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <stb/stb_image.h>

#include "app/viewer/palette.h"
#include "app/viewer/renderer.h"

using namespace carom::viewer;

namespace {

std::string outputDir() {
    const char* dir = std::getenv("CAROM_VIEW_OUTPUT");
    REQUIRE_MESSAGE(dir, "set CAROM_VIEW_OUTPUT to the folder the view fixtures wrote");
    return dir;
}

struct Image {
    int width = 0, height = 0;
    unsigned char* pixels = nullptr;
    explicit Image(const std::string& path) {
        int channels = 0;
        pixels = stbi_load(path.c_str(), &width, &height, &channels, 3);
        REQUIRE_MESSAGE(pixels, "cannot read " << path);
    }
    ~Image() { stbi_image_free(pixels); }
    Rgb at(int x, int y) const {
        const unsigned char* p = pixels + 3 * (std::size_t(y) * width + x);
        return {p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f};
    }
};

bool near(Rgb a, Rgb b) {
    const float tolerance = 3.0f / 255.0f;
    return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance && std::abs(a.b - b.b) <= tolerance;
}

Rgb quantised(Rgb c) {
    const std::uint32_t packed = packColour(c.r, c.g, c.b);
    return {(packed & 0xFF) / 255.0f, (packed >> 8 & 0xFF) / 255.0f, (packed >> 16 & 0xFF) / 255.0f};
}

std::string describe(Rgb c) {
    return "(" + std::to_string(int(c.r * 255)) + ", " + std::to_string(int(c.g * 255)) + ", " +
           std::to_string(int(c.b * 255)) + ")";
}

#define CHECK_COLOUR(image, x, y, expected)                                                                 \
    CHECK_MESSAGE(near((image).at(x, y), quantised(expected)),                                              \
                  "pixel (" << (x) << ", " << (y) << ") is " << describe((image).at(x, y)) << ", expected " \
                            << describe(quantised(expected)))

}  // namespace

TEST_CASE("screenshot: disks, empty space and walls are where the camera maps them") {
    const Image image(outputDir() + "/screenshot/view.png");
    REQUIRE(image.width == 400);
    REQUIRE(image.height == 300);

    // Disk centres carry their id colours (--color id).
    CHECK_COLOUR(image, 200, 150, idColour(0));  // (50, 25)
    CHECK_COLOUR(image, 56, 204, idColour(1));   // (10, 10)
    CHECK_COLOUR(image, 344, 96, idColour(2));   // (90, 40)
    // Radius 5 is 18 pixels: 22 pixels from a centre is empty box.
    CHECK_COLOUR(image, 222, 150, kBoxInterior);
    CHECK_COLOUR(image, 128, 96, kBoxInterior);  // (30, 40): empty

    // Walls: 2 pixels just outside each box edge; inside is the box, beyond is background.
    CHECK_COLOUR(image, 18, 150, kWall);  // left edge at x = 20
    CHECK_COLOUR(image, 19, 150, kWall);
    CHECK_COLOUR(image, 22, 150, kBoxInterior);
    CHECK_COLOUR(image, 15, 150, kBackground);
    CHECK_COLOUR(image, 380, 150, kWall);  // right edge at x = 380
    CHECK_COLOUR(image, 377, 150, kBoxInterior);
    CHECK_COLOUR(image, 385, 150, kBackground);
    CHECK_COLOUR(image, 200, 59, kWall);  // top edge at y = 60
    CHECK_COLOUR(image, 200, 62, kBoxInterior);
    CHECK_COLOUR(image, 200, 55, kBackground);
    CHECK_COLOUR(image, 200, 240, kWall);  // bottom edge at y = 240
    CHECK_COLOUR(image, 200, 237, kBoxInterior);
    CHECK_COLOUR(image, 200, 245, kBackground);
    CHECK_COLOUR(image, 5, 5, kBackground);
}

TEST_CASE("record: K frames give K numbered PNG files of the window size") {
    const std::filesystem::path dir = outputDir() + "/record/frames";
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        ++files;
        CHECK(entry.path().extension() == ".png");
    }
    CHECK(files == 5);
    for (int k = 0; k < 5; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d.png", k);
        const Image frame((dir / name).string());
        CHECK(frame.width == 400);
        CHECK(frame.height == 300);
    }
}
