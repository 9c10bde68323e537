// World <-> window pixel mapping for the viewer. Pure arithmetic, no GL, so
// the tests can check it.
//
// The default view fits the box to the window with kMarginPixels on the
// tighter side, keeping the aspect ratio, centred. World y points up, pixel y
// down. Zoom and pan are applied on top of the fitted view.
#pragma once

#include <algorithm>

namespace carom::viewer {

struct Vec2 {
    double x = 0;
    double y = 0;
};

class Camera {
public:
    static constexpr double kMarginPixels = 20.0;

    // Fits the box [0,boxWidth] x [0,boxHeight] to a window of the given size.
    void fit(double boxWidth, double boxHeight, int windowWidth, int windowHeight) {
        box_ = {boxWidth, boxHeight};
        window_ = {double(windowWidth), double(windowHeight)};
        const double usableX = std::max(1.0, window_.x - 2 * kMarginPixels);
        const double usableY = std::max(1.0, window_.y - 2 * kMarginPixels);
        pixelsPerUnit_ = std::min(usableX / boxWidth, usableY / boxHeight);
        // The world point at the window centre: the box centre.
        centre_ = {boxWidth / 2, boxHeight / 2};
    }

    // Keeps the current zoom and centre when the window changes size.
    void resize(int windowWidth, int windowHeight) { window_ = {double(windowWidth), double(windowHeight)}; }

    Vec2 toPixel(Vec2 world) const {
        return {window_.x / 2 + (world.x - centre_.x) * pixelsPerUnit_,
                window_.y / 2 - (world.y - centre_.y) * pixelsPerUnit_};
    }

    Vec2 toWorld(Vec2 pixel) const {
        return {centre_.x + (pixel.x - window_.x / 2) / pixelsPerUnit_,
                centre_.y - (pixel.y - window_.y / 2) / pixelsPerUnit_};
    }

    // Zooms by `factor` keeping the world point under `pixel` fixed.
    void zoomAbout(Vec2 pixel, double factor) {
        const Vec2 anchor = toWorld(pixel);
        pixelsPerUnit_ *= factor;
        const Vec2 moved = toWorld(pixel);
        centre_.x += anchor.x - moved.x;
        centre_.y += anchor.y - moved.y;
    }

    // Moves the view by a drag of (dx, dy) pixels.
    void pan(double dxPixels, double dyPixels) {
        centre_.x -= dxPixels / pixelsPerUnit_;
        centre_.y += dyPixels / pixelsPerUnit_;
    }

    double pixelsPerUnit() const { return pixelsPerUnit_; }
    Vec2 centre() const { return centre_; }
    Vec2 window() const { return window_; }

private:
    Vec2 box_{1, 1};
    Vec2 window_{1, 1};
    Vec2 centre_{0.5, 0.5};
    double pixelsPerUnit_ = 1;
};

}  // namespace carom::viewer
