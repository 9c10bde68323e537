#include "app/svg_plot.h"

#include <algorithm>
#include <sstream>

#include "app/format.h"

namespace carom::app {

namespace {

constexpr double kPlotWidth = 460, kPlotHeight = 340;
constexpr double kLeft = 80, kRight = 220, kTop = 44, kBottom = 56;  // the legend widens kRight for long labels
constexpr double kHeight = kTop + kPlotHeight + kBottom;
constexpr double kLabelGap = 16;              // [px] between tick labels
constexpr double kCharacterWidth = 7;         // [px] of a legend label's character, about
constexpr double kTitleCharacterWidth = 8.5;  // [px] of a title's character (font size 15), about
constexpr double kLegendSample = 40;          // [px] of the legend's line or marker and the gaps around it

// A coordinate [px] as the SVG holds it.
std::string pixels(double value) { return format("%.1f", value); }

std::string escaped(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else
            out += c;
    }
    return out;
}

// One axis mapped onto [0, 1] (0 = left or bottom), in log10 units when logarithmic.
struct Scale {
    bool logarithmic = false;
    double lo = 0, hi = 1;  // in axis units (log10 of the value when logarithmic)

    bool shows(double value) const { return std::isfinite(value) && (!logarithmic || value > 0); }
    double unit(double value) const { return logarithmic ? std::log10(value) : value; }
    double fraction(double value) const { return (unit(value) - lo) / (hi - lo); }
};

// The step of "nice" ticks (1, 2 or 5 times a power of ten) giving about `count` ticks over `span`.
double niceStep(double span, int count) {
    const double raw = span / count;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double factor : {1.0, 2.0, 5.0})
        if (raw <= factor * power) return factor * power;
    return 10.0 * power;
}

Scale scaleFor(const Axis& axis, const std::vector<double>& values) {
    Scale scale;
    scale.logarithmic = axis.logarithmic;
    double lo = INFINITY, hi = -INFINITY;
    for (double v : values)
        if (scale.shows(v)) {
            lo = std::min(lo, scale.unit(v));
            hi = std::max(hi, scale.unit(v));
        }
    if (!std::isfinite(lo)) lo = 0, hi = 1;
    if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;
    const double margin = 0.05 * (hi - lo);
    lo -= margin;
    hi += margin;
    if (std::isfinite(axis.min) && scale.shows(axis.min)) lo = scale.unit(axis.min);
    if (std::isfinite(axis.max) && scale.shows(axis.max)) hi = scale.unit(axis.max);
    scale.lo = lo;
    scale.hi = hi;
    return scale;
}

// Tick values (not units): on a log axis decades, with 2 and 5 when it spans
// at most three decades and every digit when it spans at most one; nice
// multiples on a linear one.
std::vector<double> ticksFor(const Scale& scale) {
    std::vector<double> ticks;
    if (scale.logarithmic) {
        const double span = scale.hi - scale.lo;
        const std::vector<double> factors = span <= 1.0   ? std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}
                                            : span <= 3.0 ? std::vector<double>{1, 2, 5}
                                                          : std::vector<double>{1};
        for (double e = std::floor(scale.lo); e <= std::ceil(scale.hi); ++e)
            for (double factor : factors) {
                const double value = factor * std::pow(10.0, e);
                const double u = std::log10(value);
                if (u >= scale.lo - 1e-9 && u <= scale.hi + 1e-9) ticks.push_back(value);
            }
        return ticks;
    }
    const double step = niceStep(scale.hi - scale.lo, 6);
    for (double v = std::ceil(scale.lo / step - 1e-9) * step; v <= scale.hi + 1e-9 * step; v += step)
        ticks.push_back(std::abs(v) < 1e-9 * step ? 0.0 : v);
    return ticks;
}

// The stroke-dasharray attribute of a line's style.
const char* dashes(SeriesStyle style) {
    switch (style) {
        case SeriesStyle::DashedLine: return " stroke-dasharray=\"6,4\"";
        case SeriesStyle::DottedLine: return " stroke-dasharray=\"2,3\"";
        default: return "";
    }
}

std::string tickLabel(double value) { return format("%g", value); }

// The ticks that get a label: 1, 2 and 5 times a power of ten first, then
// the others, each only where it keeps `kLabelGap` plus `pixelsPerCharacter`
// per character of its label clear of the labels already placed (along an
// axis whose pixel position is `position`).
template <class Position>
std::vector<double> labelledTicks(const std::vector<double>& ticks, Position position, double pixelsPerCharacter) {
    const auto major = [](double t) {
        if (t == 0.0) return true;
        const double digit = std::round(std::abs(t) / std::pow(10.0, std::floor(std::log10(std::abs(t)))));
        return digit == 1 || digit == 2 || digit == 5 || digit == 10;
    };
    std::vector<double> labelled;
    for (bool majorPass : {true, false})
        for (double t : ticks) {
            if (major(t) != majorPass) continue;
            const double clearance = kLabelGap + pixelsPerCharacter * double(tickLabel(t).size());
            const bool clear = std::all_of(labelled.begin(), labelled.end(), [&](double other) {
                return std::abs(position(t) - position(other)) >= clearance;
            });
            if (clear) labelled.push_back(t);
        }
    return labelled;
}

}  // namespace

std::string renderSvg(const Plot& plot) {
    std::vector<double> xs, ys;
    for (const Series& s : plot.series) {
        xs.insert(xs.end(), s.x.begin(), s.x.end());
        for (std::size_t i = 0; i < s.y.size(); ++i) {
            const double e = i < s.error.size() ? s.error[i] : 0.0;
            ys.push_back(s.y[i]);  // on a log axis y - e may not show
            ys.push_back(s.y[i] - e);
            ys.push_back(s.y[i] + e);
        }
    }
    const Scale sx = scaleFor(plot.x, xs), sy = scaleFor(plot.y, ys);
    const auto px = [&](double v) { return kLeft + sx.fraction(v) * kPlotWidth; };
    const auto py = [&](double v) { return kTop + (1.0 - sy.fraction(v)) * kPlotHeight; };

    std::size_t longestLabel = 0;
    for (const Series& s : plot.series) longestLabel = std::max(longestLabel, s.label.size());
    // Wide enough for the legend and the title.
    const double width =
        std::max(kLeft + kPlotWidth + std::max(kRight, kLegendSample + kCharacterWidth * double(longestLabel)),
                 kLeft + kTitleCharacterWidth * double(plot.title.size()));

    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << kHeight
        << "\" viewBox=\"0 0 " << width << ' ' << kHeight << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<text x=\"" << kLeft << "\" y=\"26\" font-size=\"15\">" << escaped(plot.title) << "</text>\n";
    for (double t : ticksFor(sx)) {
        const std::string x = pixels(px(t));
        svg << "<line x1=\"" << x << "\" y1=\"" << kTop << "\" x2=\"" << x << "\" y2=\"" << kTop + kPlotHeight
            << "\" stroke=\"#e6e6e6\"/><line x1=\"" << x << "\" y1=\"" << kTop + kPlotHeight << "\" x2=\"" << x
            << "\" y2=\"" << kTop + kPlotHeight + 5 << "\" stroke=\"black\"/>\n";
    }
    for (double t : labelledTicks(ticksFor(sx), px, 7.0)) {
        svg << "<text x=\"" << pixels(px(t)) << "\" y=\"" << kTop + kPlotHeight + 18 << "\" text-anchor=\"middle\">"
            << tickLabel(t) << "</text>\n";
    }
    for (double t : ticksFor(sy)) {
        const std::string y = pixels(py(t));
        svg << "<line x1=\"" << kLeft << "\" y1=\"" << y << "\" x2=\"" << kLeft + kPlotWidth << "\" y2=\"" << y
            << "\" stroke=\"#e6e6e6\"/><line x1=\"" << kLeft - 5 << "\" y1=\"" << y << "\" x2=\"" << kLeft << "\" y2=\""
            << y << "\" stroke=\"black\"/>\n";
    }
    for (double t : labelledTicks(ticksFor(sy), py, 0.0))
        svg << "<text x=\"" << kLeft - 8 << "\" y=\"" << pixels(py(t) + 4) << "\" text-anchor=\"end\">" << tickLabel(t)
            << "</text>\n";
    svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kPlotWidth << "\" height=\"" << kPlotHeight
        << "\" fill=\"none\" stroke=\"black\"/>\n"
        << "<text x=\"" << kLeft + kPlotWidth / 2 << "\" y=\"" << kHeight - 14 << "\" text-anchor=\"middle\">"
        << escaped(plot.x.label) << "</text>\n"
        << "<text transform=\"translate(20," << kTop + kPlotHeight / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
        << escaped(plot.y.label) << "</text>\n";

    // Everything drawn from data is clipped to the plot area.
    svg << "<clipPath id=\"area\"><rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kPlotWidth
        << "\" height=\"" << kPlotHeight << "\"/></clipPath>\n<g clip-path=\"url(#area)\">\n";
    for (const Series& s : plot.series) {
        if (s.style != SeriesStyle::Points) {
            std::string points;
            const auto add = [&](double x, double y) {
                if (sx.shows(x) && sy.shows(y)) points += pixels(px(x)) + ',' + pixels(py(y)) + ' ';
            };
            for (std::size_t i = 0; i < s.y.size() && i < s.x.size(); ++i) {
                if (s.style != SeriesStyle::Steps) {
                    add(s.x[i], s.y[i]);
                } else if (i + 1 < s.x.size()) {
                    add(s.x[i], s.y[i]);
                    add(s.x[i + 1], s.y[i]);
                }
            }
            svg << "<polyline fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"1.8\"" << dashes(s.style)
                << " points=\"" << points << "\"/>\n";
            continue;
        }
        for (std::size_t i = 0; i < s.y.size() && i < s.x.size(); ++i) {
            if (!sx.shows(s.x[i]) || !sy.shows(s.y[i])) continue;
            const std::string x = pixels(px(s.x[i]));
            if (i < s.error.size() && s.error[i] > 0) {
                const double low = s.y[i] - s.error[i], high = s.y[i] + s.error[i];
                const std::string y0 = pixels(sy.shows(low) ? py(low) : kTop + kPlotHeight), y1 = pixels(py(high));
                svg << "<line x1=\"" << x << "\" y1=\"" << y0 << "\" x2=\"" << x << "\" y2=\"" << y1 << "\" stroke=\""
                    << s.colour << "\"/><line x1=\"" << pixels(px(s.x[i]) - 4) << "\" y1=\"" << y0 << "\" x2=\""
                    << pixels(px(s.x[i]) + 4) << "\" y2=\"" << y0 << "\" stroke=\"" << s.colour << "\"/><line x1=\""
                    << pixels(px(s.x[i]) - 4) << "\" y1=\"" << y1 << "\" x2=\"" << pixels(px(s.x[i]) + 4) << "\" y2=\""
                    << y1 << "\" stroke=\"" << s.colour << "\"/>\n";
            }
            svg << "<circle cx=\"" << x << "\" cy=\"" << pixels(py(s.y[i])) << "\" r=\"3.5\" fill=\"" << s.colour
                << "\"/>\n";
        }
    }
    svg << "</g>\n";

    double legendY = kTop + 12;
    for (const Series& s : plot.series) {
        if (s.label.empty()) continue;
        const double x = kLeft + kPlotWidth + 14;
        if (s.style == SeriesStyle::Points)
            svg << "<circle cx=\"" << x + 10 << "\" cy=\"" << legendY - 4 << "\" r=\"3.5\" fill=\"" << s.colour
                << "\"/>\n";
        else
            svg << "<line x1=\"" << x << "\" y1=\"" << legendY - 4 << "\" x2=\"" << x + 20 << "\" y2=\"" << legendY - 4
                << "\" stroke=\"" << s.colour << "\" stroke-width=\"1.8\"" << dashes(s.style) << "/>\n";
        svg << "<text x=\"" << x + 26 << "\" y=\"" << legendY << "\">" << escaped(s.label) << "</text>\n";
        legendY += 18;
    }
    svg << "</svg>\n";
    return svg.str();
}

}  // namespace carom::app
