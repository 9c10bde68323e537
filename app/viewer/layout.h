// Where the panels go and what they leave for the box. Pure arithmetic, in
// window points (ImGui's units; drawable pixels are points times the HiDPI
// ratio), so the tests can check it.
//
// The panels are one column docked to the window's left edge, as tall as the
// window: kColumnShare of the window's width within [kMinColumnWidth,
// kMaxColumnWidth], and never more than half of it, so that from a
// kSmallestWindow upward the box keeps at least half the width. Collapsed,
// the column is its title bar, a strip along the top.
#pragma once

#include <algorithm>

#include "app/viewer/camera.h"

namespace carom::viewer {

enum class Panels { Shown, Collapsed, Hidden };

constexpr double kColumnShare = 0.3;
constexpr double kMinColumnWidth = 240;
constexpr double kMaxColumnWidth = 360;
// The smallest window the layout is made for: the user cannot shrink the
// window below it (or below what --window asked for, if that was smaller).
constexpr int kSmallestWindowWidth = 320, kSmallestWindowHeight = 240;

inline double panelColumnWidth(double windowWidth) {
    return std::min(windowWidth / 2, std::clamp(kColumnShare * windowWidth, kMinColumnWidth, kMaxColumnWidth));
}

// The rectangle of a window of windowWidth x windowHeight points that the
// panels leave free; titleBarHeight is the collapsed column's height.
inline Rect freeView(double windowWidth, double windowHeight, Panels panels, double titleBarHeight) {
    switch (panels) {
        case Panels::Shown: {
            const double column = panelColumnWidth(windowWidth);
            return {column, 0, windowWidth - column, windowHeight};
        }
        case Panels::Collapsed: return {0, titleBarHeight, windowWidth, windowHeight - titleBarHeight};
        case Panels::Hidden: break;
    }
    return {0, 0, windowWidth, windowHeight};
}

}  // namespace carom::viewer
