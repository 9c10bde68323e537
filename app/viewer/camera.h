// World <-> window pixel mapping for the viewer. Pure arithmetic, no GL, so
// the tests can check it.
//
// The view is the rectangle of the window the panels leave free (layout.h;
// the whole window when they are hidden). The fitted view shows the whole box
// in it with kMarginPixels on the tighter side, keeping the aspect ratio,
// centred. World y points up, pixel y down. Zoom and pan are applied on top
// of the fitted view. When the window or the view changes (resize, H,
// collapsing the panels) a fitted view is fitted again; a zoomed or panned
// one keeps its zoom and the world point at the view's centre, until refit
// (F) or a new scene.
#pragma once

#include <algorithm>

namespace carom::viewer {

struct Vec2 {
    double x = 0;
    double y = 0;
};

// A rectangle of the window, y down.
struct Rect {
    double x = 0, y = 0, width = 1, height = 1;
    Vec2 centre() const { return {x + width / 2, y + height / 2}; }
};

class Camera {
public:
    static constexpr double kMarginPixels = 20.0;

    // The window is window.x by window.y pixels; the box is shown in `view`.
    void setLayout(Vec2 window, Rect view) {
        window_ = window;
        view_ = view;
        if (fitted_) refit();
    }

    // Fits the box [0,boxWidth] x [0,boxHeight] into the view.
    void fit(double boxWidth, double boxHeight) {
        box_ = {boxWidth, boxHeight};
        refit();
    }

    // Back to the fitted view of the box, undoing zoom and pan.
    void refit() {
        const double usableX = std::max(1.0, view_.width - 2 * kMarginPixels);
        const double usableY = std::max(1.0, view_.height - 2 * kMarginPixels);
        pixelsPerUnit_ = std::min(usableX / box_.x, usableY / box_.y);
        centre_ = {box_.x / 2, box_.y / 2};
        fitted_ = true;
    }

    Vec2 toPixel(Vec2 world) const {
        const Vec2 anchor = view_.centre();
        return {anchor.x + (world.x - centre_.x) * pixelsPerUnit_, anchor.y - (world.y - centre_.y) * pixelsPerUnit_};
    }

    Vec2 toWorld(Vec2 pixel) const {
        const Vec2 anchor = view_.centre();
        return {centre_.x + (pixel.x - anchor.x) / pixelsPerUnit_, centre_.y - (pixel.y - anchor.y) / pixelsPerUnit_};
    }

    // Zooms by `factor` keeping the world point under `pixel` fixed.
    void zoomAbout(Vec2 pixel, double factor) {
        const Vec2 anchor = toWorld(pixel);
        pixelsPerUnit_ *= factor;
        const Vec2 moved = toWorld(pixel);
        centre_.x += anchor.x - moved.x;
        centre_.y += anchor.y - moved.y;
        fitted_ = false;
    }

    // Moves the view by a drag of (dx, dy) pixels.
    void pan(double dxPixels, double dyPixels) {
        centre_.x -= dxPixels / pixelsPerUnit_;
        centre_.y += dyPixels / pixelsPerUnit_;
        fitted_ = false;
    }

    double pixelsPerUnit() const { return pixelsPerUnit_; }
    // The world point at the view's centre.
    Vec2 centre() const { return centre_; }
    Vec2 window() const { return window_; }
    Rect view() const { return view_; }
    bool fitted() const { return fitted_; }

private:
    Vec2 box_{1, 1};
    Vec2 window_{1, 1};
    Rect view_;
    Vec2 centre_{0.5, 0.5};
    double pixelsPerUnit_ = 1;
    bool fitted_ = true;
};

}  // namespace carom::viewer
