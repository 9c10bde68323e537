// Small self-contained SVG charts for the reports of `carom validate` and
// `carom bench`: linear or logarithmic axes with ticks and labels, lines
// (reference curves, throughputs), points with error bars (measurements) and
// step outlines (histograms), and a legend.
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace carom::app {

struct Axis {
    std::string label;
    bool logarithmic = false;
    // The range shown; NaN = fitted to the data, with a margin.
    double min = NAN;
    double max = NAN;
};

enum class SeriesStyle {
    Line,        // a polyline through (x, y)
    DashedLine,  // the same, dashed
    DottedLine,  // the same, dotted
    Points,      // markers, with vertical error bars of +-error[i] when `error` is given
    Steps,       // a histogram outline: y[i] over [x[i], x[i+1]], so x has one more value than y
};

struct Series {
    std::string label;   // in the legend; empty = not listed
    std::string colour;  // any SVG colour
    SeriesStyle style = SeriesStyle::Line;
    std::vector<double> x, y;
    std::vector<double> error;  // Points only: empty, or one half-width per point
};

struct Plot {
    std::string title;
    Axis x, y;
    std::vector<Series> series;
};

// The plot as a complete SVG document. Points outside a logarithmic axis
// (<= 0) and non-finite points are left out.
std::string renderSvg(const Plot& plot);

}  // namespace carom::app
