// Checks the viewer's headless output (see tests/viewer_tests.cmake: the
// view.screenshot, view.record, view.layout_* and interaction fixtures render
// it under Xvfb first) and the camera's arithmetic (view.camera, no display).
//
// view.screenshot is tests/data/view_disks.csv in a 100 x 50 box drawn in a
// 400 x 300 window with the panels hidden, so the view is the whole window.
// The camera fits the box with a 20-pixel margin on the tighter side: 3.6
// pixels per unit, the box spans pixels x 20..380 and y 60..240 (y down), so
// world (x, y) is pixel (20 + 3.6 x, 240 - 3.6 y). These numbers, and those
// of kLayouts below, are worked out by hand, not by the viewer's camera code.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <stb/stb_image.h>

#include "app/viewer/layout.h"
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

// view.layout_*: tests/data/view_corners.csv, disks of radius 5 at the centre
// (id 0) and the four corners (ids 1-4) of a 100 x 100 box, with the panels
// shown in a column on the left.
constexpr double kCornersBox = 100, kCornersRadius = 5;
constexpr Vec2 kCornersDisks[] = {{50, 50}, {5, 5}, {95, 5}, {5, 95}, {95, 95}};

struct Layout {
    int width, height;       // the window
    double column;           // the panel column's width
    double pixelsPerUnit;    // the free view's tighter side less two margins, over 100
    double boxLeft, boxTop;  // the box's top-left corner
};

constexpr Layout kLayouts[] = {
    // 0.3 x 320 = 96 is below the least column, 240, which is more than half
    // the window: 160. The view x 160..320 leaves 120 x 200 within the
    // margins: 1.2 pixels per unit, a box of 120 pixels centred at (240, 120).
    {320, 240, 160, 1.2, 180, 60},
    // 0.3 x 400 = 120 -> 240 -> half the window, 200. The view x 200..400
    // leaves 160 x 360: 1.6, a box of 160 centred at (300, 200).
    {400, 400, 200, 1.6, 220, 120},
    // 0.3 x 1280 = 384 -> the widest column, 360. The view x 360..1280 leaves
    // 880 x 760: 7.6, a box of 760 centred at (820, 400).
    {1280, 800, 360, 7.6, 440, 20},
};

// The camera as the viewer sets it up for `layout` with the panels shown.
Camera layoutCamera(const Layout& layout) {
    Camera camera;
    camera.setLayout({double(layout.width), double(layout.height)},
                     freeView(layout.width, layout.height, Panels::Shown, 0));
    camera.fit(kCornersBox, kCornersBox);
    return camera;
}

// A row of the viewer's --output-state CSV (carom run's format).
struct StateDisk {
    double x = 0, y = 0, vx = 0, vy = 0, mass = 0, radius = 0;
};

std::vector<StateDisk> readState(const std::string& path) {
    std::ifstream in(path);
    REQUIRE_MESSAGE(in, "cannot read " << path);
    std::string line;
    std::getline(in, line);
    REQUIRE(line == "id,x,y,vx,vy,mass,radius");
    std::vector<StateDisk> disks;
    while (std::getline(in, line)) {
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream row(line);
        std::size_t id = 0;
        StateDisk disk;
        row >> id >> disk.x >> disk.y >> disk.vx >> disk.vy >> disk.mass >> disk.radius;
        REQUIRE_MESSAGE(row, "cannot read the row '" << line << "' of " << path);
        REQUIRE(id == disks.size());
        disks.push_back(disk);
    }
    return disks;
}

// tests/data/view_disks.csv: disks of radius 5, at rest.
constexpr Vec2 kViewDisks[] = {{50, 25}, {10, 10}, {90, 40}};

// view.screenshot's camera: view_disks.csv's 100 x 50 box in a 400 x 300
// window with the panels hidden.
Camera viewDisksCamera() {
    Camera camera;
    camera.setLayout({400, 300}, freeView(400, 300, Panels::Hidden, 0));
    camera.fit(100, 50);
    return camera;
}

#define CHECK_COLOUR(image, x, y, expected)                                                                 \
    CHECK_MESSAGE(near((image).at(x, y), quantised(expected)),                                              \
                  "pixel (" << (x) << ", " << (y) << ") is " << describe((image).at(x, y)) << ", expected " \
                            << describe(quantised(expected)))

}  // namespace

// CAROM_VIEW_SCREENSHOT names the fixture's folder: screenshot (the CPU
// engine, views in id order) by default, or screenshot_resident (views in the
// device's cell order, with the ids the device keeps).
TEST_CASE("screenshot: disks, empty space and walls are where the camera maps them") {
    const char* folder = std::getenv("CAROM_VIEW_SCREENSHOT");
    const Image image(outputDir() + "/" + (folder ? folder : "screenshot") + "/view.png");
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

TEST_CASE("screenshot_mass: disks of equal mass take viridis' middle stop") {
    const Image image(outputDir() + "/screenshot_mass/view.png");
    const Rgb middle{0.164f, 0.471f, 0.558f};  // viridis(0.5), the 5th of its 9 stops (renderer.cpp)
    CHECK_COLOUR(image, 200, 150, middle);
    CHECK_COLOUR(image, 56, 204, middle);
    CHECK_COLOUR(image, 344, 96, middle);
    CHECK_COLOUR(image, 222, 150, kBoxInterior);
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

TEST_CASE("camera: with the panels shown the box fits the view they leave free") {
    for (const Layout& layout : kLayouts) {
        CAPTURE(layout.width);
        CAPTURE(layout.height);
        CHECK(panelColumnWidth(layout.width) == doctest::Approx(layout.column));
        const Camera camera = layoutCamera(layout);
        CHECK(camera.pixelsPerUnit() == doctest::Approx(layout.pixelsPerUnit));
        const Vec2 topLeft = camera.toPixel({0, kCornersBox});
        CHECK(topLeft.x == doctest::Approx(layout.boxLeft));
        CHECK(topLeft.y == doctest::Approx(layout.boxTop));
        const Vec2 bottomRight = camera.toPixel({kCornersBox, 0});
        CHECK(bottomRight.x == doctest::Approx(layout.boxLeft + kCornersBox * layout.pixelsPerUnit));
        CHECK(bottomRight.y == doctest::Approx(layout.boxTop + kCornersBox * layout.pixelsPerUnit));
        const Vec2 back = camera.toWorld(topLeft);
        CHECK(back.x == doctest::Approx(0));
        CHECK(back.y == doctest::Approx(kCornersBox));
    }
}

TEST_CASE("camera: collapsed panels leave all but their title bar, hidden ones the whole window") {
    const Rect collapsed = freeView(400, 400, Panels::Collapsed, 19);
    CHECK(collapsed.x == 0);
    CHECK(collapsed.y == 19);
    CHECK(collapsed.width == 400);
    CHECK(collapsed.height == 381);
    Camera camera;
    camera.setLayout({400, 400}, collapsed);
    camera.fit(kCornersBox, kCornersBox);
    // 381 - 40 = 341 pixels for 100 units, centred at (200, 209.5).
    CHECK(camera.pixelsPerUnit() == doctest::Approx(3.41));
    CHECK(camera.toPixel({0, kCornersBox}).y == doctest::Approx(39));
    CHECK(camera.toPixel({0, kCornersBox}).x == doctest::Approx(29.5));

    // view.screenshot's numbers: a 100 x 50 box in 400 x 300, panels hidden.
    camera.setLayout({400, 300}, freeView(400, 300, Panels::Hidden, 19));
    camera.fit(100, 50);
    CHECK(camera.pixelsPerUnit() == doctest::Approx(3.6));
    CHECK(camera.toPixel({0, 50}).x == doctest::Approx(20));
    CHECK(camera.toPixel({0, 50}).y == doctest::Approx(60));
}

TEST_CASE("camera: a layout change refits a fitted view and keeps a zoomed one's zoom and centre") {
    Camera camera = layoutCamera(kLayouts[1]);  // 400 x 400, panels shown
    camera.setLayout({400, 400}, freeView(400, 400, Panels::Hidden, 19));
    CHECK(camera.fitted());
    CHECK(camera.pixelsPerUnit() == doctest::Approx(3.6));  // 360 pixels for 100 units
    CHECK(camera.toPixel({50, 50}).x == doctest::Approx(200));

    camera = layoutCamera(kLayouts[1]);
    const Vec2 cursor{250, 150};
    const Vec2 underCursor = camera.toWorld(cursor);
    camera.zoomAbout(cursor, 2);
    CHECK_FALSE(camera.fitted());
    CHECK(camera.pixelsPerUnit() == doctest::Approx(3.2));
    CHECK(camera.toPixel(underCursor).x == doctest::Approx(cursor.x));
    CHECK(camera.toPixel(underCursor).y == doctest::Approx(cursor.y));
    camera.pan(10, -20);
    const Vec2 centre = camera.centre();
    // Hiding the panels moves the view's centre from (300, 200) to (200, 200).
    camera.setLayout({400, 400}, freeView(400, 400, Panels::Hidden, 19));
    CHECK(camera.pixelsPerUnit() == doctest::Approx(3.2));
    CHECK(camera.toPixel(centre).x == doctest::Approx(200));
    CHECK(camera.toPixel(centre).y == doctest::Approx(200));
    camera.refit();
    CHECK(camera.fitted());
    CHECK(camera.pixelsPerUnit() == doctest::Approx(3.6));
}

namespace {

// The disks and the walls show where layoutCamera puts them, inside the view
// the panels leave free, and the panels cover their column.
void checkLayout(const Layout& layout) {
    const std::string size = std::to_string(layout.width) + "x" + std::to_string(layout.height);
    const Image image(outputDir() + "/layout_" + size + "/view.png");
    REQUIRE(image.width == layout.width);
    REQUIRE(image.height == layout.height);
    const Camera camera = layoutCamera(layout);
    const Rect view = camera.view();
    const double radius = kCornersRadius * camera.pixelsPerUnit();
    for (std::size_t id = 0; id < std::size(kCornersDisks); ++id) {
        const Vec2 centre = camera.toPixel(kCornersDisks[id]);
        CAPTURE(id);
        CHECK(centre.x - radius >= view.x);
        CHECK(centre.x + radius <= view.x + view.width);
        CHECK(centre.y - radius >= view.y);
        CHECK(centre.y + radius <= view.y + view.height);
        CHECK_COLOUR(image, int(centre.x), int(centre.y), idColour(std::uint32_t(id)));
    }
    // Walls: the 2 pixels just outside each box edge.
    const Vec2 topLeft = camera.toPixel({0, kCornersBox}), bottomRight = camera.toPixel({kCornersBox, 0});
    const int middleX = int((topLeft.x + bottomRight.x) / 2), middleY = int((topLeft.y + bottomRight.y) / 2);
    CHECK_COLOUR(image, int(topLeft.x) - 1, middleY, kWall);
    CHECK_COLOUR(image, int(bottomRight.x), middleY, kWall);
    CHECK_COLOUR(image, middleX, int(topLeft.y) - 1, kWall);
    CHECK_COLOUR(image, middleX, int(bottomRight.y), kWall);
    // The scene leaves background in the column; the panels are drawn over it,
    // and end where the column does.
    for (const int y : {layout.height / 4, layout.height / 2, 3 * layout.height / 4}) {
        const int x = int(layout.column / 2);
        CHECK_MESSAGE(!near(image.at(x, y), quantised(kBackground)),
                      "pixel (" << x << ", " << y << ") is the background: no panel there");
        CHECK_COLOUR(image, int(layout.column) + 2, y, kBackground);
    }
}

}  // namespace

TEST_CASE("layout 320x240: the smallest window shows the whole box beside the panels") { checkLayout(kLayouts[0]); }
TEST_CASE("layout 400x400: a square window shows the whole box beside the panels") { checkLayout(kLayouts[1]); }
TEST_CASE("layout 1280x800: the default window shows the whole box beside the panels") { checkLayout(kLayouts[2]); }

// The interactions (tests/data/view_*.events) on view_disks.csv, through the
// viewer's event handler; pixels below are window pixels, 3.6 to a unit.

TEST_CASE("throw: a disk grabbed and dragged along +x flies along +x when released; the others stay at rest") {
    const std::vector<StateDisk> disks = readState(outputDir() + "/throw/view.csv");
    REQUIRE(disks.size() == std::size(kViewDisks));
    // Grabbed at its pixel (200, 150), dragged 20 pixels right over two frames.
    CHECK(disks[0].vx > 0);
    CHECK(disks[0].vy == 0);
    CHECK(disks[0].x > kViewDisks[0].x + 20 / 3.6);  // past where it was let go
    CHECK(disks[0].y == kViewDisks[0].y);
    for (std::size_t id = 1; id < disks.size(); ++id) {
        CAPTURE(id);
        CHECK(disks[id].x == kViewDisks[id].x);
        CHECK(disks[id].y == kViewDisks[id].y);
        CHECK(disks[id].vx == 0);
        CHECK(disks[id].vy == 0);
    }
}

TEST_CASE("burst: a right click in empty space adds 12 disks about the cursor, none overlapping") {
    const std::vector<StateDisk> disks = readState(outputDir() + "/burst/view.csv");
    REQUIRE(disks.size() == std::size(kViewDisks) + 12);
    // The ring flies outwards symmetrically: its centre stays at the clicked
    // pixel (128, 96), world (30, 40).
    double sumX = 0, sumY = 0;
    for (std::size_t id = std::size(kViewDisks); id < disks.size(); ++id) {
        sumX += disks[id].x;
        sumY += disks[id].y;
    }
    CHECK(sumX / 12 == doctest::Approx(30).epsilon(1e-4));
    CHECK(sumY / 12 == doctest::Approx(40).epsilon(1e-4));
    for (std::size_t i = 0; i < disks.size(); ++i)
        for (std::size_t j = i + 1; j < disks.size(); ++j) {
            CAPTURE(i);
            CAPTURE(j);
            CHECK(std::hypot(disks[i].x - disks[j].x, disks[i].y - disks[j].y) >= disks[i].radius + disks[j].radius);
        }
}

TEST_CASE("burst_scene: with --scene a burst's disks are the scene's first group's") {
    const std::vector<StateDisk> disks = readState(outputDir() + "/burst_scene/view.csv");
    REQUIRE(disks.size() == 3 + 12);
    for (std::size_t id = 3; id < disks.size(); ++id) {
        CAPTURE(id);
        CHECK(disks[id].radius == 2.0);
        CHECK(disks[id].mass == 5.0);
    }
}

TEST_CASE("zoom_pan: after two wheel steps out and a middle drag the disks are where the camera puts them") {
    const Image image(outputDir() + "/zoom_pan/view.png");
    REQUIRE(image.width == 400);
    REQUIRE(image.height == 300);
    const Camera fitted = viewDisksCamera();
    Camera camera = fitted;
    camera.zoomAbout({120, 100}, std::pow(1.15, -2));  // the wheel at (120, 100)
    camera.pan(40, 30);                                // dragged from (300, 200) to (340, 230)
    for (std::uint32_t id = 0; id < std::size(kViewDisks); ++id) {
        CAPTURE(id);
        const Vec2 moved = camera.toPixel(kViewDisks[id]);
        CHECK_COLOUR(image, int(std::lround(moved.x)), int(std::lround(moved.y)), idColour(id));
    }
    // Disk 0 left its fitted pixel (200, 150) by more than its radius of 5 x 3.6 / 1.15^2 = 13.6 pixels.
    const Vec2 before = fitted.toPixel(kViewDisks[0]);
    CHECK_COLOUR(image, int(before.x), int(before.y), kBoxInterior);
}
