#include "app/validate/report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/format.h"
#include "app/svg_plot.h"

namespace carom::validation {

namespace {

using app::format;
using app::Plot;
using app::renderSvg;
using app::Series;
using app::SeriesStyle;

const char* const kMeasured = "#d62728";
const char* const kReference = "black";

// Markdown table cells must not contain a bare '|'.
std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '|') out += '\\';
        out += c;
    }
    return out;
}

std::string verdict(bool passed) { return passed ? "PASS" : "**FAIL**"; }

std::size_t failures(const SuiteResult& r) {
    return std::size_t(std::count_if(r.checks.begin(), r.checks.end(), [](const Check& c) { return !c.passed; }));
}

// The checks of `section` (all when empty) as a table; nothing when it has none.
void checkTable(std::ostream& md, const SuiteResult& r, const std::string& section) {
    if (std::none_of(r.checks.begin(), r.checks.end(),
                     [&](const Check& c) { return section.empty() || c.section == section; }))
        return;
    md << "| check | measured | expected | criterion | deviation | result |\n|---|---|---|---|---|---|\n";
    for (const Check& c : r.checks)
        if (section.empty() || c.section == section)
            md << "| " << cell((section.empty() ? c.section + ": " : "") + c.name) << " | "
               << format("%.6g", c.measured) << " | " << format("%.6g", c.expected) << " | " << cell(c.criterion)
               << " | " << format("%.3g", c.deviation) << " | " << verdict(c.passed) << " |\n";
    md << '\n';
}

Series line(const std::string& label, const std::string& colour, SeriesStyle style, std::vector<double> x,
            std::vector<double> y) {
    Series s;
    s.label = label;
    s.colour = colour;
    s.style = style;
    s.x = std::move(x);
    s.y = std::move(y);
    return s;
}

// A closed form of Z(eta) over the plotted range, as given or relative to the reference in %.
Series curve(const std::string& label, const std::string& colour, SeriesStyle style, double (*z)(double),
             bool relative) {
    std::vector<double> x, y;
    for (int k = 0; k <= 130; ++k) {
        const double eta = 0.005 * k;
        x.push_back(eta);
        y.push_back(relative ? 100.0 * (z(eta) / referenceZ(eta) - 1.0) : z(eta));
    }
    return line(label, colour, style, x, y);
}

const char* const kEvents = "#8c564b";

// The event-driven Z of section 9.1, as given or relative to the reference in %.
Series eventsSeries(const std::vector<EventsEosPoint>& points, bool relative) {
    Series s = line("carom, events (CPU)", kEvents, SeriesStyle::Points, {}, {});
    for (const EventsEosPoint& p : points) {
        const MeanAndError& z = p.run.measured.z;
        s.x.push_back(p.run.packing);
        s.y.push_back(relative ? 100.0 * (z.mean / p.zReference - 1.0) : z.mean);
        s.error.push_back(relative ? 100.0 * z.error / p.zReference : z.error);
    }
    return s;
}

std::string eosPlot(const EosResult& eos, const EventsResult& events) {
    Plot plot;
    plot.title = "Equation of state: Z = PA/(NkT) of the hard-disk fluid";
    plot.x = {"packing fraction eta", false, 0.0, 0.65};
    plot.y = {"Z", false, 1.0, NAN};
    plot.series.push_back(curve("reference", kReference, SeriesStyle::Line, referenceZ, false));
    plot.series.push_back(curve("Henderson 1975", "#1f77b4", SeriesStyle::DashedLine, hendersonZ, false));
    plot.series.push_back(curve("Luding 2001", "#2ca02c", SeriesStyle::DashedLine, ludingZ, false));
    plot.series.push_back(curve("Santos et al. 1995", "#9467bd", SeriesStyle::DashedLine, santosZ, false));
    Series measured = line("carom, pairwise, dt " + format("%.4g", eos.dt), kMeasured, SeriesStyle::Points, {}, {});
    for (const EosPoint& p : eos.points) {
        measured.x.push_back(p.packing);
        measured.y.push_back(p.measured.z.mean);
        measured.error.push_back(p.measured.z.error);
    }
    plot.series.push_back(measured);
    plot.series.push_back(eventsSeries(events.eos, false));
    return renderSvg(plot);
}

std::string eosDeviationPlot(const EosResult& eos, const EventsResult& events) {
    Plot plot;
    plot.title = "Equation of state: deviation from the reference";
    plot.x = {"packing fraction eta", false, 0.0, 0.65};
    plot.y = {"(Z - Z_ref) / Z_ref [%]", false, NAN, NAN};
    plot.series.push_back(line("reference", kReference, SeriesStyle::Line, {0.0, 0.65}, {0.0, 0.0}));
    plot.series.push_back(curve("Henderson 1975", "#1f77b4", SeriesStyle::DashedLine, hendersonZ, true));
    plot.series.push_back(curve("Luding 2001", "#2ca02c", SeriesStyle::DashedLine, ludingZ, true));
    plot.series.push_back(curve("Santos et al. 1995", "#9467bd", SeriesStyle::DashedLine, santosZ, true));
    for (double sign : {1.0, -1.0})
        plot.series.push_back(line(sign > 0 ? "target +-0.3 %" : "", "#ff7f0e", SeriesStyle::DashedLine, {0.075, 0.625},
                                   {sign * 100 * kZTarget, sign * 100 * kZTarget}));
    Series measured = line("carom, pairwise (1 s.e. bars)", kMeasured, SeriesStyle::Points, {}, {});
    for (const EosPoint& p : eos.points) {
        measured.x.push_back(p.packing);
        measured.y.push_back(100.0 * (p.measured.z.mean / p.zReference - 1.0));
        measured.error.push_back(100.0 * p.measured.z.error / p.zReference);
    }
    plot.series.push_back(measured);
    for (double sign : {1.0, -1.0})
        plot.series.push_back(line(sign > 0 ? "events target +-0.1 % (+ 2 s.e.)" : "", kEvents, SeriesStyle::DashedLine,
                                   {0.075, 0.625}, {sign * 100 * kEventsZTarget, sign * 100 * kEventsZTarget}));
    plot.series.push_back(eventsSeries(events.eos, true));
    return renderSvg(plot);
}

std::string convergenceZPlot(const ConvergenceResult& c) {
    Plot plot;
    plot.title = "Convergence: Z against dt at eta = " + format("%.2f", c.packing) + " (pairwise)";
    plot.x = {"dt", true, NAN, NAN};
    plot.y = {"Z", false, NAN, NAN};
    if (c.points.empty()) return renderSvg(plot);
    const double lo = c.points.back().dt / 1.5, hi = c.points.front().dt * 1.5;
    plot.series.push_back(line("Z_ref", kReference, SeriesStyle::Line, {lo, hi}, {c.zReference, c.zReference}));
    for (double sign : {1.0, -1.0}) {
        const double z = c.zReference * (1.0 + sign * kZTarget);
        plot.series.push_back(
            line(sign > 0 ? "Z_ref +-0.3 %" : "", "#ff7f0e", SeriesStyle::DashedLine, {lo, hi}, {z, z}));
    }
    Series measured = line("carom (1 s.e. bars)", kMeasured, SeriesStyle::Points, {}, {});
    for (const ConvergencePoint& p : c.points) {
        measured.x.push_back(p.dt);
        measured.y.push_back(p.measured.z.mean);
        measured.error.push_back(p.measured.z.error);
    }
    plot.series.push_back(measured);
    return renderSvg(plot);
}

// |dE|/E per unit time over a run of blocks.
double driftPerTime(const BlockStatistics& m) { return std::abs(m.energyChange) / (m.blocks * m.blockTime); }

std::string energyDtPlot(const ConvergenceResult& c, const SimultaneousResult& s) {
    Plot plot;
    plot.title = "Energy drift against dt at eta = 0.5";
    plot.x = {"dt", true, NAN, NAN};
    plot.y = {"|dE|/E per unit time", true, NAN, NAN};
    Series simultaneous = line("simultaneous", kMeasured, SeriesStyle::Points, {}, {});
    for (const SimultaneousRun& run : s.dtSweep) {
        simultaneous.x.push_back(run.dt);
        simultaneous.y.push_back(std::abs(run.driftRate));
    }
    Series pairwise = line("pairwise", "#1f77b4", SeriesStyle::Points, {}, {});
    for (const ConvergencePoint& p : c.points) {
        pairwise.x.push_back(p.dt);
        pairwise.y.push_back(driftPerTime(p.measured));
    }
    plot.series.push_back(simultaneous);
    plot.series.push_back(pairwise);
    return renderSvg(plot);
}

std::string energyDensityPlot(const EosResult& e, const SimultaneousResult& s) {
    Plot plot;
    plot.title = "Energy drift against packing fraction at dt = 0.01";
    plot.x = {"packing fraction eta", false, 0.0, 0.65};
    plot.y = {"|dE|/E per unit time", true, NAN, NAN};
    Series simultaneous = line("simultaneous", kMeasured, SeriesStyle::Points, {}, {});
    for (const SimultaneousRun& run : s.packingSweep) {
        simultaneous.x.push_back(run.packing);
        simultaneous.y.push_back(std::abs(run.driftRate));
    }
    Series pairwise =
        line("pairwise (section 1, dt " + format("%.4g", e.dt) + ")", "#1f77b4", SeriesStyle::Points, {}, {});
    for (const EosPoint& p : e.points) {
        pairwise.x.push_back(p.packing);
        pairwise.y.push_back(driftPerTime(p.measured));
    }
    plot.series.push_back(simultaneous);
    plot.series.push_back(pairwise);
    return renderSvg(plot);
}

// The relaxation's plots, when its runs completed.
bool relaxationRan(const RelaxationResult& r) { return r.samples.size() >= 2 && !r.speedBinEdges.empty(); }

std::string noData(const std::string& title) {
    Plot plot;
    plot.title = title + ": no data (the runs failed)";
    return renderSvg(plot);
}

std::string hPlot(const RelaxationResult& r) {
    Plot plot;
    plot.title = "Relaxation: Boltzmann H-function (histogram estimate)";
    if (!relaxationRan(r)) return noData(plot.title);
    plot.x = {"time", false, 0.0, NAN};
    plot.y = {"H", false, NAN, NAN};
    Series measured = line("carom", kMeasured, SeriesStyle::Line, {}, {});
    for (const RelaxationSample& s : r.samples) {
        measured.x.push_back(s.time);
        measured.y.push_back(s.h);
    }
    const double end = r.samples.back().time;
    const double hUniform = -std::log(4.0 * r.halfWidth * r.halfWidth);
    plot.series.push_back(measured);
    plot.series.push_back(
        line("H of the uniform start", "#1f77b4", SeriesStyle::DashedLine, {0, end}, {hUniform, hUniform}));
    plot.series.push_back(line("H_eq = ln(m/2pi kT) - 1", kReference, SeriesStyle::DashedLine, {0, end},
                               {hEquilibrium(r.kTFinal), hEquilibrium(r.kTFinal)}));
    const double expectedEstimate = hEquilibrium(r.kTFinal) + r.hPluginBias - r.hBinningBias;
    plot.series.push_back(line("H_eq + estimator bias", "#7f7f7f", SeriesStyle::DashedLine, {0, end},
                               {expectedEstimate, expectedEstimate}));
    return renderSvg(plot);
}

std::string ksPlot(const RelaxationResult& r) {
    Plot plot;
    plot.title = "Relaxation: Kolmogorov-Smirnov statistic of the speeds against Rayleigh";
    if (!relaxationRan(r)) return noData(plot.title);
    plot.x = {"time", false, 0.0, NAN};
    plot.y = {"KS statistic D", true, NAN, NAN};
    Series measured = line("carom", kMeasured, SeriesStyle::Line, {}, {});
    for (const RelaxationSample& s : r.samples) {
        measured.x.push_back(s.time);
        measured.y.push_back(s.ks);
    }
    const double end = r.samples.back().time;
    plot.series.push_back(measured);
    plot.series.push_back(
        line("5 % critical value", kReference, SeriesStyle::DashedLine, {0, end}, {r.ksCritical, r.ksCritical}));
    return renderSvg(plot);
}

std::string speedPlot(const RelaxationResult& r) {
    Plot plot;
    plot.title = "Relaxation: final speed distribution";
    if (!relaxationRan(r)) return noData(plot.title);
    plot.x = {"speed |v|", false, 0.0, r.speedBinEdges.back()};
    plot.y = {"probability density", false, 0.0, NAN};
    plot.series.push_back(line("carom, t = " + format("%.4g", r.samples.back().time), kMeasured, SeriesStyle::Steps,
                               r.speedBinEdges, r.speedDensity));
    std::vector<double> x, y;
    for (int k = 0; k <= 200; ++k) {
        x.push_back(r.speedBinEdges.back() * k / 200);
        y.push_back(rayleighPdf(x.back(), r.kTFinal));
    }
    plot.series.push_back(line("Rayleigh at the final kT", kReference, SeriesStyle::Line, x, y));
    return renderSvg(plot);
}

void markdownHeader(std::ostream& md, const SuiteResult& r, const RunContext& c) {
    const std::size_t failed = failures(r);
    md << "# carom physics validation\n\n"
       << "**Result: " << (failed == 0 ? "PASS" : "FAIL") << "** — " << r.checks.size() - failed << " of "
       << r.checks.size() << " checks pass.\n\n";
    md << "carom's collisions against the published hard-disk results of the reference "
          "(`shared/physics/hard-disks.md`: Clisby & McCoy 2006, Luding 2001, Henderson 1975, Santos, "
          "López de Haro & Yuste 1995). Sections 1–7 run the **pairwise** collision scheme (binary elastic "
          "collisions at exact contact times) and never touch the velocities: kT is what the conserved energy "
          "gives, measured per block. Section 8 runs the seed's **simultaneous** scheme for comparison. "
          "Section 9 runs the exact **event-driven** scheme (`--collisions events`), always on the CPU "
          "(its only backend), against the reference and as the yardstick of the stepped schemes. "
          "Produced by `carom validate`; "
       << (r.options.quick ? "this is the **quick** suite (CI): fewer disks and shorter runs; where its size "
                             "cannot resolve a target, the tolerance is three standard errors and the table says "
                             "so. The full suite is `carom validate` without `--quick`."
                           : "this is the full suite.")
       << "\n\n| | |\n|---|---|\n"
       << "| command | `" << c.command << "` |\n"
       << "| date | " << c.date << " |\n"
       << "| backend | " << r.device << " |\n"
       << "| host | " << c.host << ", " << c.hostThreads << " OpenMP threads, load " << format("%.3g", c.hostLoad)
       << " at the start |\n"
       << "| collisions | pairwise (sections 1–7), simultaneous (section 8), events (section 9; " << r.events.device
       << ") |\n"
       << "| dt | " << format("%.4g", r.options.dt)
       << " (equation of state, relaxation, conservation, dense gas, gravity); convergence: ";
    for (std::size_t k = 0; k < r.convergence.points.size(); ++k)
        md << (k ? ", " : "") << format("%.4g", r.convergence.points[k].dt);
    md << "; simultaneous scheme: ";
    for (std::size_t k = 0; k < r.simultaneous.dtSweep.size(); ++k)
        md << (k ? ", " : "") << format("%.4g", r.simultaneous.dtSweep[k].dt);
    md << "; two-body cases 0.01, wall bounce 1e-3 |\n"
       << "| seed | " << r.options.seed << " |\n"
       << "| wall time | " << format("%.1f", r.wallSeconds) << " s |\n\n"
       << "Units: disks of radius 1 (σ = 2) and mass 1 at kT = 1; a disk's mean speed is then √(π/2) ≈ 1.25 "
          "radii per unit time.\n\n## All checks\n\n";
    checkTable(md, r, "");
}

// "0.3 %", or "0.45 % (3 s.e.)" where the run cannot resolve the target.
std::string toleranceCell(double tolerance, double target) {
    return format("%.2g", 100 * tolerance) + " %" + (tolerance > target ? " (3 s.e.)" : "");
}

void markdownEos(std::ostream& md, const EosResult& e, const SuiteResult& r) {
    const int blocks = e.points.empty() ? 0 : e.points.front().measured.blocks;
    md << "## 1. Equation of state and collision frequency\n\n"
       << "N disks in a periodic box at packing fraction η, started from `makeInitialState`'s hexagonal lattice "
          "with Gaussian velocities (zero total momentum, kT = 1), pairwise scheme at dt = "
       << format("%.4g", e.dt) << ". The lattice melts (at least 20 collisions per disk), then Z is measured over "
       << blocks
       << " blocks (at least 2 collisions per disk each). Nothing rescales the velocities: the scheme "
          "conserves energy, and the table shows by how much it changed. Within a block, from the contacts the "
          "backend counts (`Backend::contacts()`, `thermodynamics()`):\n\n"
       << "- kT = (E_kin − P²/2M) / (N − 1), the mean of its values at the block's start and end\n"
       << "- P A = E_kin + Σ r_ij · J_ij / (2 t) with E_kin = (N - 1) kT in the periodic box, the collision virial "
          "with the centre distance r_ij at which "
          "each impulse J_ij = 2 μ_ij |v_n| is applied (σ at an exact contact), and Z = P A / (N kT)\n"
       << "- ω, a disk's collision frequency: carom's collision rate counts each colliding pair once per "
          "collision, and every collision involves two disks, so ω = 2 × collisions / (N t). Against "
          "ω(Z, kT) = 4 Z_c/σ · √(kT/(π m)) with the block's own kT and collisions' share of Z, "
          "Z_c = Σ r_ij · J_ij / (2 N kT t): the virial gives Z_c = σ ⟨|v_n|⟩ ω / (4 kT), and for exact dynamics "
          "the colliding pairs' normal speed averages √(π kT/m), so the ratio is 1 at any density. Z_c is "
          "Z − (N − 1)/N in the periodic box (Z − 1 only as N → ∞: at N = 4 096 and η = 0.1 the difference "
          "is 0.1 % of ω). The block's own Z keeps the statistical error of Z "
          "out of the ratio (Z is checked against the reference separately); the ratio against the reference's "
          "Z is shown too.\n\n"
       << "Z and the ratio are the means of the block values. Their standard errors allow for correlation "
          "between consecutive blocks (in 2D the pressure's time correlation decays slowly, as 1/t): the blocks "
          "are merged in adjacent pairs, level by level, down to at least 8, and the largest of the levels' "
          "standard errors is taken (Flyvbjerg & Petersen 1989). "
          "Targets: Z within 0.3 % of the reference, the ratio within 1 % of 1. Where three standard errors "
          "(for Z, the run's and the reference's own uncertainty combined) exceed the target, the run cannot "
          "resolve it and the tolerance is the three standard errors, marked (3 s.e.)"
       << (r.options.quick ? "; the quick suite's runs are shorter (fewer and shorter blocks, N = " +
                                 std::to_string(kEosParticles(true)) + " unless --particles says otherwise)."
                           : ".")
       << "\n\n| η | N | melt time | blocks × time | Z | Z_ref | deviation | tolerance | ω | ω / ω(Z, kT) | "
          "tolerance | ω / ω(Z_ref, kT) | kT | ΔE/E over the blocks | late contacts | max rounds |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const EosPoint& p : e.points) {
        const BlockStatistics& m = p.measured;
        const double omega = 2.0 * m.collisionRate;
        md << "| " << format("%.2f", p.packing) << " | " << p.particles << " | " << format("%.3g", p.equilibrationTime)
           << " | " << m.blocks << " × " << format("%.3g", m.blockTime) << " | " << format("%.4f", m.z.mean) << " ± "
           << format("%.4f", m.z.error) << " | " << format("%.6g", p.zReference)
           << (p.zReferenceError > 0 ? " ± " + format("%.4g", p.zReferenceError) : std::string()) << " | "
           << format("%.3f", 100.0 * (m.z.mean / p.zReference - 1.0)) << " % | "
           << toleranceCell(p.zTolerance, kZTarget) << " | " << format("%.4f", omega) << " | "
           << format("%.4f", m.rateRatio.mean) << " ± " << format("%.4f", m.rateRatio.error) << " | "
           << toleranceCell(p.rateTolerance, kRateTarget) << " | "
           << format("%.4f", omega / collisionFrequency(p.zReference, m.kT, 2.0, 1.0)) << " | " << format("%.4f", m.kT)
           << " | " << format("%.2g", m.energyChange) << " | " << m.lateContacts << " | " << m.maxRounds << " |\n";
    }
    md << "\n![Z against packing fraction](eos.svg)\n\n![Deviation from the reference](eos-deviation.svg)\n\n";
}

void markdownConvergence(std::ostream& md, const ConvergenceResult& c, const SuiteResult& s) {
    const int blocks = c.points.empty() ? 0 : c.points.front().measured.blocks;
    const double blockTime = c.points.empty() ? 0.0 : c.points.front().measured.blockTime;
    const double finest = c.points.empty() ? NAN : c.points.back().dt;
    md << "## 2. Dependence on dt\n\n"
       << "One state at η = " << format("%.2f", c.packing) << " (N = " << c.particles
       << ", periodic, pairwise), melted "
       << "for " << format("%.4g", c.equilibrationTime) << " time units at dt = " << format("%.4g", kDefaultDt)
       << ", continued at each dt: one block to settle, then " << blocks << " blocks of " << format("%.4g", blockTime)
       << " time units, measured as in section 1 (no rescaling). The pairwise scheme applies every impulse at "
          "the exact contact time and normal, so Z should not depend on dt; where a step's fastest disks would "
          "outrun the grid's allowance the step is split into substeps (at the largest dts). Each Z is held "
          "against Z at dt = "
       << format("%.4g", finest)
       << " within three standard errors of the difference (the runs share their start, so this is "
          "conservative). Late contacts are pairs found overlapping beyond rounding (the rounds could not "
          "order them in time); they are what could make Z depend on dt.\n\n"
       << "| dt | Z | Z − Z(dt = " << format("%.4g", finest)
       << ") | (Z − Z_ref) / Z_ref | ΔE/E over the blocks | "
          "late contacts | max rounds |\n|---|---|---|---|---|---|---|\n";
    for (const ConvergencePoint& p : c.points)
        md << "| " << format("%.4g", p.dt) << " | " << format("%.4f", p.measured.z.mean) << " ± "
           << format("%.4f", p.measured.z.error) << " | " << format("%.4f", p.zDifference) << " ± "
           << format("%.4f", p.differenceError) << " | "
           << format("%.3f", 100.0 * (p.measured.z.mean / c.zReference - 1.0)) << " % | "
           << format("%.2g", p.measured.energyChange) << " | " << p.measured.lateContacts << " | "
           << p.measured.maxRounds << " |\n";
    double resolution = 0.0;  // the largest tolerance of the comparisons
    for (const ConvergencePoint& p : c.points)
        resolution = std::max(resolution, statisticalTolerance(0.0, p.differenceError));
    md << "\nZ_ref = " << format("%.6g", c.zReference) << ". At this size the comparisons resolve differences of "
       << format("%.3f", resolution) << " (" << format("%.2f", 100.0 * resolution / c.zReference) << " % of Z).\n\n";
    checkTable(md, s, "convergence");
    md << "![Z against dt](convergence-z.svg)\n\n"
       << "The energy plots show, per unit time, the pairwise runs' |ΔE/E| over their blocks and the "
          "simultaneous runs' least-squares drift (section 8).\n\n"
       << "![Energy drift against dt, both schemes](convergence-energy.svg)\n\n";
}

void markdownRelaxation(std::ostream& md, const RelaxationResult& r, const SuiteResult& s) {
    md << "## 3. Relaxation to Maxwell–Boltzmann\n\n";
    if (!relaxationRan(r)) {
        md << "The relaxation runs failed:\n\n";
        checkTable(md, s, "relaxation");
        return;
    }
    md << r.particles << " disks at η = " << format("%.2f", r.packing)
       << " in a periodic box, pairwise scheme at dt = " << format("%.4g", r.dt)
       << ", start with velocities uniform on the square [−a, a]², a = √3 (kT = a²/3 = 1), minus their mean. "
          "Every "
       << format("%.4g", r.samples[1].time - r.samples[0].time) << " time units: H = ∫ f ln f d²v from a "
       << r.histogram.binsPerAxis << " × " << r.histogram.binsPerAxis << " histogram over [−3a, 3a]² (bins of "
       << "a/4, so ±a are bin edges), and the Kolmogorov–Smirnov statistic D of the speeds against the "
          "Rayleigh distribution at the state's kT.\n\n"
       << "- H falls by H_eq(kT_end) − H_uniform = ln(6/π) − 1 − ln(kT_end/kT_start) (= −0.3529 with exact "
          "energy conservation, which the pairwise scheme has but for rounding). Measured: H_end − H_start = "
       << format("%.4f", r.hFinal - r.hInitial) << ", with H_end the mean of the last " << r.finalSnapshots
       << " samples. Tolerance " << format("%.4f", r.hTolerance)
       << ": the plug-in bias (occupied bins − 1)/(2n) = " << format("%.4f", r.hPluginBias)
       << " (upwards), plus the binning bias of a Gaussian, w²/(12 kT/m) = " << format("%.4f", r.hBinningBias)
       << " (downwards, bins of width w), plus three standard errors of one "
          "snapshot, 3/√n = "
       << format("%.4f", 3 / std::sqrt(double(r.particles))) << ".\n- Final D = " << format("%.4f", r.samples.back().ks)
       << " against the 5 % critical value 1.358/√n = " << format("%.4f", r.ksCritical)
       << " (at the start D = " << format("%.3f", r.samples.front().ks) << ").\n\n";
    checkTable(md, s, "relaxation");
    md << "![H against time](relaxation-h.svg)\n\n![KS statistic against time](relaxation-ks.svg)\n\n"
       << "![Final speed histogram](relaxation-speeds.svg)\n\n";
}

void markdownExact(std::ostream& md, const SuiteResult& s) {
    md << "## 4. Exact cases\n\n"
       << "Two disks of radius 1 in a 100 × 100 box with walls, pairwise scheme, dt = 1e-4, stepped until they "
          "have collided once and moved apart, against the two-body formula of the reference (the outcomes it "
          "lists, and for the heavy projectile the formula at the exact contact point). The scheme collides them "
          "at the exact contact time and normal, so only the rounding of float positions near 50 "
          "(2^-18 ≈ 3.8e-6) separates the result from the formula: it tilts the normal by up to about "
          "2 × 3.8e-6 / σ ≈ 4e-6 rad (2e-4°, 4e-6 of the speed), and the tolerances are five times that, 2e-5 "
          "of the incoming speed and 1e-3°. Then one disk (r = 1, v = (3, 0.4)) between walls 10 apart, "
          "dt = 1e-3: the period of "
          "its x motion from the steps at which it leaves the left wall: the wall reflects it at the exact contact "
          "time, and each bounce time is known to a step, so the mean period is within dt.\n\n";
    checkTable(md, s, "exact cases");
}

void markdownConservation(std::ostream& md, const SuiteResult& s) {
    md << "## 5. Conservation on every backend\n\n"
       << "Each backend this build has (OpenCL with both pipelines, on the device `--device` names) runs the "
          "same periodic box from the same state with the pairwise scheme. Momentum is conserved to rounding: "
          "every impulse is applied to both disks of a pair. Each collision conserves kinetic energy exactly "
          "but for the rounding of the new float velocities, about the unit roundoff 2^-24 of the pair's "
          "energy: the tolerance is that, all of one sign, for every collision of every disk over the run "
          "(random signs would give far less).\n\n"
       << "| backend | device | N | η | dt | steps | collisions per disk | \\|ΔP\\| / Σm\\|v\\| | ΔE/E | late "
          "contacts |\n"
       << "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const ConservationRun& run : s.conservation) {
        md << "| " << run.backend << " | ";
        md << cell(run.device) << " | " << run.particles << " | " << format("%.2f", run.packing) << " | "
           << format("%.4g", run.dt) << " | " << run.steps << " | " << format("%.1f", run.collisionsPerDisk) << " | "
           << format("%.3g", run.momentumError) << " | " << format("%.3g", run.energyChange) << " | "
           << run.lateContacts << " |\n";
    }
    md << '\n';
    checkTable(md, s, "conservation");
}

void markdownDense(std::ostream& md, const SuiteResult& s) {
    const DenseResult& d = s.dense;
    const BlockStatistics& m = d.measured;
    md << "## 6. Dense gas\n\n"
       << d.particles << " disks at η = " << format("%.2f", d.packing)
       << " in a periodic box (near the liquid–hexatic transition, where the reference's closed forms are "
          "1–4 % too high, so Z is shown, not checked), pairwise scheme at dt = "
       << format("%.4g", d.dt) << ", from the hexagonal lattice: " << format("%.4g", d.equilibrationTime)
       << " time units to melt, then " << m.blocks << " blocks of " << format("%.4g", m.blockTime)
       << " time units, measured as in section 1. Held: the energy over the whole run within 1e-4; no blow-up "
          "(every disk "
          "finite and in the box, and no overlap beyond 1e-3 σ at the end: exact contacts leave none, and a "
          "late contact is pushed back to touching); the collision frequency against ω(Z, kT) as in section "
          "1, which holds at any density for exact dynamics.\n\n"
       << "| ΔE/E | \\|ΔP\\| / Σm\\|v\\| | Z | ω / ω(Z, kT) | kT | largest overlap | late contacts | "
          "max rounds |\n"
       << "|---|---|---|---|---|---|---|---|\n"
       << "| " << format("%.3g", d.energyChange) << " | " << format("%.3g", d.momentumError) << " | "
       << format("%.4f", m.z.mean) << " ± " << format("%.4f", m.z.error) << " | " << format("%.4f", m.rateRatio.mean)
       << " ± " << format("%.4f", m.rateRatio.error) << " | " << format("%.4f", m.kT) << " | "
       << format("%.3g", d.maxOverlap) << " | " << m.lateContacts << " | " << m.maxRounds << " |\n\n";
    checkTable(md, s, "dense gas");
}

void markdownGravity(std::ostream& md, const SuiteResult& s) {
    const GravityResult& g = s.gravity;
    md << "## 7. Gravity\n\n"
       << "`scenes/gravity_settle.toml` at dt = " << format("%.4g", g.dt)
       << " with the pairwise scheme: " << g.particles
       << " disks (radius 0.5–1, mass 0.5–2) released in the upper part of a walled " << format("%.4g", g.width)
       << " × " << format("%.4g", g.height) << " box fall under g = " << format("%.4g", g.gravity)
       << " and pile up on the floor; " << format("%.4g", g.duration)
       << " time units. Between events every disk flies on its exact parabola, and disks falling alike keep "
          "their relative motion linear, so K + U is conserved but for rounding. U = Σ m g y is measured from "
          "the floor, so K + U is the energy the disks can turn into motion. Held within 1e-3.\n\n"
       << "| K start | K end | U start | U end | Δ(K+U)/(K+U) | late contacts | max rounds |\n"
       << "|---|---|---|---|---|---|---|\n"
       << "| " << format("%.6g", g.kineticStart) << " | " << format("%.6g", g.kineticEnd) << " | "
       << format("%.6g", g.potentialStart) << " | " << format("%.6g", g.potentialEnd) << " | "
       << format("%.3g", g.energyChange) << " | " << g.lateContacts << " | " << g.maxRounds << " |\n\n";
    checkTable(md, s, "gravity");
}

void simultaneousTable(std::ostream& md, const std::vector<SimultaneousRun>& runs) {
    md << "| η | dt | ΔE/E over the run | drift per unit time | wander | Z, second half | Z_ref |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const SimultaneousRun& run : runs)
        md << "| " << format("%.2f", run.packing) << " | " << format("%.4g", run.dt) << " | "
           << format("%.3g", run.energyChange) << " | " << format("%.3g", run.driftRate) << " | "
           << format("%.2g", run.wander) << " | " << format("%.4f", run.z) << " | "
           << format("%.6g", referenceZ(run.packing)) << " |\n";
    md << '\n';
}

void markdownSimultaneous(std::ostream& md, const SuiteResult& s) {
    const SimultaneousResult& r = s.simultaneous;
    md << "## 8. The simultaneous scheme, for comparison\n\n"
       << "The seed's scheme resolves all of a step's contacts at once from the velocities before the step, "
          "with a positional correction. Each pair's impulse is elastic, but a disk in two contacts takes two "
          "impulses computed from the same velocities, and their cross terms change the energy: systematically "
          "upwards in dense gases (`shared/physics/hard-disks.md`). Measured here, not checked: "
       << r.particles << " disks in a periodic box from the hexagonal lattice at kT = 1, " << format("%.4g", r.duration)
       << " time units without rescaling. The energy E(t)/E(0) is sampled every " << format("%.4g", r.sampleInterval)
       << " time unit; the table gives its change over the run, the slope of its least-squares line (the "
          "drift) and the rms about that line (the wander: the energy also goes up and down within a run, so a "
          "single run resolves the drift only roughly where the wander is comparable). Z is the collision "
          "virial over the second half at the mean of its start and end kT (this scheme applies impulses "
          "inside the overlap, r_ij < σ).\n\n"
       << "Against dt at η = 0.5:\n\n";
    simultaneousTable(md, r.dtSweep);
    md << "Against the packing fraction at dt = 0.01:\n\n";
    simultaneousTable(md, r.packingSweep);
    md << "The pairwise scheme's energy changes at the same dts and packings are in sections 1 and 2; both "
          "plots show the two schemes side by side.\n\n"
       << "![Energy drift against packing fraction, both schemes](energy-density.svg)\n\n";
    checkTable(md, s, "simultaneous scheme");
}

// The observed order of convergence between two runs whose dt differ by a
// factor of 2: log2 of the ratio of their distances.
double observedOrder(double coarse, double fine) { return std::log2(coarse / fine); }

std::string trajectoryPlot(const TrajectoryResult& t) {
    Plot plot;
    plot.title = "Stepped schemes against events: rms distance of the final positions";
    plot.x = {"dt", true, NAN, NAN};
    plot.y = {"rms |x - x_events|", true, NAN, NAN};
    Series pairwise = line("pairwise", "#1f77b4", SeriesStyle::Points, {}, {});
    Series simultaneous = line("simultaneous", kMeasured, SeriesStyle::Points, {}, {});
    for (const TrajectoryPoint& p : t.points) {
        pairwise.x.push_back(p.dt);
        pairwise.y.push_back(p.pairwiseRms);
        simultaneous.x.push_back(p.dt);
        simultaneous.y.push_back(p.simultaneousRms);
    }
    plot.series.push_back(pairwise);
    plot.series.push_back(simultaneous);
    if (!t.points.empty()) {  // a line of slope 1 through the simultaneous scheme's largest dt
        const TrajectoryPoint& first = t.points.front();
        const double last = t.points.back().dt;
        plot.series.push_back(line("order 1", "#7f7f7f", SeriesStyle::DashedLine, {first.dt, last},
                                   {first.simultaneousRms, first.simultaneousRms * last / first.dt}));
    }
    return renderSvg(plot);
}

std::string schemesPlot(const std::vector<SchemeComparison>& schemes) {
    Plot plot;
    plot.title = "Z of the stepped schemes minus Z of events (same N, eta, seed)";
    plot.x = {"dt", true, NAN, NAN};
    plot.y = {"Z - Z_events", false, NAN, NAN};
    const char* const colours[] = {"#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};
    std::size_t k = 0;
    for (const SchemeComparison& c : schemes) {
        const std::string colour = colours[k++ % 4];
        const std::string at = "eta " + format("%.1f", c.packing);
        Series pairwise = line("pairwise, " + at, colour, SeriesStyle::Points, {}, {});
        Series simultaneous = line("simultaneous, " + at, colour, SeriesStyle::Line, {}, {});
        for (const SchemeZ& run : c.runs) {
            pairwise.x.push_back(run.dt);
            pairwise.y.push_back(run.pairwise.z.mean - c.events.mean);
            pairwise.error.push_back(std::hypot(run.pairwise.z.error, c.events.error));
            simultaneous.x.push_back(run.dt);
            simultaneous.y.push_back(run.simultaneous.z.mean - c.events.mean);
        }
        plot.series.push_back(pairwise);
        plot.series.push_back(simultaneous);
    }
    if (!schemes.empty() && !schemes.front().runs.empty())
        plot.series.push_back(line("", kReference, SeriesStyle::Line,
                                   {schemes.front().runs.back().dt, schemes.front().runs.front().dt}, {0.0, 0.0}));
    return renderSvg(plot);
}

void markdownEventsEos(std::ostream& md, const SuiteResult& s) {
    const std::vector<EventsEosPoint>& points = s.events.eos;
    md << "### 9.1 Equation of state and the collision-rate identity\n\n";
    if (points.empty()) {
        md << "The runs failed:\n\n";
        checkTable(md, s, "events: equation of state");
        return;
    }
    const EventsRun& first = points.front().run;
    md << first.particles << " disks in a periodic box at each η, from the same hexagonal lattice and Gaussian "
       << "velocities (kT = 1, seed " << s.options.seed << ") as section 1: a warm-up of "
       << format("%.4g", first.warmupCollisions) << " collisions per disk, then " << first.measured.blocks
       << " blocks of " << format("%.4g", first.measured.blockTime / (first.warmupTime / first.warmupCollisions))
       << " collisions per disk (times from the reference Z), measured as in section 1 from the contacts the "
          "backend counts. The collision virial uses r_ij = σ exactly (`ContactTotals::virial` sums σ_ij J_ij); "
          "kT = (E_kin − P²/2M)/(N − 1). Held: Z within 0.1 % of the reference plus two standard errors "
          "(the run's, from blocking, and the reference's own, combined); the collision-rate identity "
          "ω = 4 Z_c/σ · √(kT/(π m)) within three standard errors (it is exact for exact dynamics at any "
          "density, up to statistics; Z_c = Z − (N − 1)/N, see section 1); the energy, in double, within "
          "10⁻¹² per 10⁶ collisions.\n\n"
       << "| η | N | Z | Z_ref | Z − Z_ref | deviation | tolerance | ω / ω(Z_c, kT) | ΔE/E | collisions | "
          "overlapping | wall time | collisions/s |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const EventsEosPoint& p : points) {
        const EventsRun& run = p.run;
        const BlockStatistics& m = run.measured;
        md << "| " << format("%.2f", run.packing) << " | " << run.particles << " | " << format("%.4f", m.z.mean)
           << " ± " << format("%.4f", m.z.error) << " | " << format("%.6g", p.zReference)
           << (p.zReferenceError > 0 ? " ± " + format("%.4g", p.zReferenceError) : std::string()) << " | "
           << format("%.4f", m.z.mean - p.zReference) << " | "
           << format("%.3f", 100.0 * (m.z.mean / p.zReference - 1.0)) << " % | " << format("%.4f", p.zTolerance)
           << " | " << format("%.4f", m.rateRatio.mean) << " ± " << format("%.4f", m.rateRatio.error) << " | "
           << format("%.2g", run.energyChange) << " | " << run.collisions << " | " << run.overlapping << " | "
           << format("%.1f", run.seconds) << " s | " << format("%.3g", double(run.collisions) / run.seconds) << " |\n";
    }
    md << "\nThe event-driven points are in the equation-of-state plots of section 1. Wall time and "
          "collisions per second are of this run on this host, for scale (they include the warm-up).\n\n";
    checkTable(md, s, "events: equation of state");
}

void markdownEventsDense(std::ostream& md, const SuiteResult& s) {
    const EventsDense& d = s.events.dense;
    const EventsRun& run = d.run;
    md << "### 9.2 η = 0.70, the liquid–hexatic region (reported)\n\n";
    if (run.particles == 0) {
        md << "The run failed:\n\n";
        checkTable(md, s, "events: dense");
        return;
    }
    const BlockStatistics& m = run.measured;
    md << run.particles << " disks, periodic, from the lattice: a warm-up of " << format("%.4g", run.warmupCollisions)
       << " collisions per disk, then " << m.blocks
       << " blocks as in 9.1. Here the fluid meets the "
          "first-order liquid–hexatic transition (coexistence from η ≈ 0.700 to 0.716 for large N) and the "
          "pressure depends strongly on N (a Mayer–Wood loop at small N), so Z is reported beside published "
          "values, not checked; the collision-rate identity, exact at any density, is checked. Published "
          "values are βPσ² (σ the diameter), converted with Z = π βPσ² / (4 η); they are the authors' data as "
          "collected in github.com/jellyfysh/HistoricDisks (`DigitizedData`), periodic boxes.\n\n"
       << "| source | method | N | βPσ² | Z |\n|---|---|---|---|---|\n"
       << "| carom, this run | event-driven MD | " << run.particles << " | "
       << format("%.4f", 4.0 * run.packing * m.z.mean / kPi) << " ± "
       << format("%.4f", 4.0 * run.packing * m.z.error / kPi) << " | " << format("%.4f", m.z.mean) << " ± "
       << format("%.4f", m.z.error) << " |\n";
    for (const PublishedPressure& p : d.published)
        md << "| " << p.source << " | " << p.method << " | " << p.particles << " | " << format("%.6g", p.betaPSigma2)
           << " ± " << format("%.2g", p.error) << " | " << format("%.4f", compressibility(p, run.packing)) << " |\n";
    md << "\nω / ω(Z_c, kT) = " << format("%.4f", m.rateRatio.mean) << " ± " << format("%.4f", m.rateRatio.error)
       << ", ΔE/E = " << format("%.2g", run.energyChange) << ", " << run.collisions << " collisions in "
       << format("%.1f", run.seconds) << " s.\n\n";
    checkTable(md, s, "events: dense");
}

void markdownTrajectories(std::ostream& md, const SuiteResult& s) {
    const TrajectoryResult& t = s.events.trajectories;
    md << "### 9.3 Trajectories of the stepped schemes against events\n\n";
    if (t.points.empty()) {
        md << "The runs failed:\n\n";
        checkTable(md, s, "events: trajectories");
        return;
    }
    md << t.starts << " independent starts of " << t.particles << " disks of radius 1 (one per cell of a 4 × 4 grid, "
       << "jittered; thermal velocities; seeds from " << s.options.seed << ") between walls in a "
       << format("%.4g", t.width) << " × " << format("%.4g", t.height) << " box, each run for "
       << format("%.4g", t.duration) << " time units from the same start by `events` (" << t.eventCollisions
       << " collisions and " << t.eventWallBounces
       << " wall bounces in all: short enough that the stepped runs collide in the same "
          "sequence, before chaos separates the trajectories) and by the stepped schemes at halving dt, on the CPU. "
          "The distance is between each stepped scheme's final positions (float32) and the event-driven ones "
          "(double), over the disks of all starts; the observed order is log2 of the ratio of successive "
          "distances.\n\n"
          "What it shows: the simultaneous scheme, which resolves a contact only after the step has made it "
          "overlap, converges to the exact dynamics at first order in dt, until its distance meets a floor. The "
          "pairwise scheme collides at the exact contact times, so it has no error of order dt at all: its "
          "distance is the floor, the float32 rounding of the positions, which grows as dt shrinks (each step "
          "rounds x + v dt, and while v is constant it rounds the same way, so the error grows with the number "
          "of steps, as 1/dt) and is amplified by each collision. At small dt both schemes sit on the same "
          "floor. Checked: the simultaneous scheme's mean order over the halvings where its own error dominates "
          "is at least 0.5, and the pairwise scheme is within 10⁻³ of the exact positions at the largest "
          "dt.\n\n"
       << "| dt | pairwise rms | order | pairwise max | collisions | simultaneous rms | order | simultaneous max | "
          "collisions |\n|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t k = 0; k < t.points.size(); ++k) {
        const TrajectoryPoint& p = t.points[k];
        const bool first = k == 0;
        md << "| " << format("%.4g", p.dt) << " | " << format("%.3g", p.pairwiseRms) << " | "
           << (first ? "" : format("%.2f", observedOrder(t.points[k - 1].pairwiseRms, p.pairwiseRms))) << " | "
           << format("%.3g", p.pairwiseMax) << " | " << p.pairwiseCollisions << " | "
           << format("%.3g", p.simultaneousRms) << " | "
           << (first ? "" : format("%.2f", observedOrder(t.points[k - 1].simultaneousRms, p.simultaneousRms))) << " | "
           << format("%.3g", p.simultaneousMax) << " | " << p.simultaneousCollisions << " |\n";
    }
    md << "\n![Distance to events against dt](trajectories.svg)\n\n";
    checkTable(md, s, "events: trajectories");
}

void markdownSchemes(std::ostream& md, const SuiteResult& s) {
    const std::vector<SchemeComparison>& schemes = s.events.schemes;
    md << "### 9.4 Z of the stepped schemes against events\n\n";
    if (schemes.empty()) {
        md << "The runs failed.\n\n";
        checkTable(md, s, "events: schemes");
        return;
    }
    const SchemeComparison& first = schemes.front();
    const BlockStatistics& m = first.runs.front().pairwise;
    md << "The pairwise and simultaneous schemes on the suite's backend (" << s.device << ") from the same "
       << "lattice, N = " << first.particles
       << " and seed as the event-driven runs of 9.1, at each dt: " << format("%.4g", first.warmupTime)
       << " time units of warm-up, then " << m.blocks << " blocks of " << format("%.4g", m.blockTime)
       << " time units, measured as in section 1 (kT per block from the state, no "
          "rescaling). Z_events is 9.1's. The pairwise scheme applies impulses at exact contact times, so its "
          "difference should vanish within the errors at every dt; the simultaneous scheme resolves overlaps "
          "after the step (r_ij < σ) and heats the gas, a dt-dependent bias; in a dense gas at a large dt it can heat "
          "until its state is no longer finite, which the table reports. Reported, not checked.\n\n"
       << "| η | dt | Z_events | Z pairwise | pairwise − events | Z simultaneous | simultaneous − events | "
          "ΔE/E simultaneous, over the blocks |\n|---|---|---|---|---|---|---|---|\n";
    std::vector<std::string> failures;
    // "Z ± error | Z - Z_events ± error", or the run's failure, listed below the table.
    const auto schemeCells = [&](const MeanAndError& z, const MeanAndError& events, const std::string& failure,
                                 const std::string& what) {
        if (!failure.empty()) {
            failures.push_back(what + ": " + failure);
            return "did not complete (" + std::to_string(failures.size()) + ") | —";
        }
        return format("%.4f", z.mean) + " ± " + format("%.4f", z.error) + " | " + format("%.4f", z.mean - events.mean) +
               " ± " + format("%.4f", std::hypot(z.error, events.error));
    };
    for (const SchemeComparison& c : schemes)
        for (const SchemeZ& run : c.runs) {
            const std::string where = "η = " + format("%.2f", c.packing) + ", dt = " + format("%.4g", run.dt);
            md << "| " << format("%.2f", c.packing) << " | " << format("%.4g", run.dt) << " | "
               << format("%.4f", c.events.mean) << " ± " << format("%.4f", c.events.error) << " | "
               << schemeCells(run.pairwise.z, c.events, run.pairwiseFailure, where + ", pairwise") << " | "
               << schemeCells(run.simultaneous.z, c.events, run.simultaneousFailure, where + ", simultaneous") << " | "
               << (run.simultaneousFailure.empty() ? format("%.3g", run.simultaneous.energyChange) : "—") << " |\n";
        }
    md << '\n';
    for (std::size_t k = 0; k < failures.size(); ++k) md << "(" << k + 1 << ") " << cell(failures[k]) << "\n\n";
    md << "![Z of the stepped schemes minus Z of events](schemes-z.svg)\n\n";
}

void markdownEvents(std::ostream& md, const SuiteResult& s) {
    md << "## 9. Exact event-driven dynamics (`--collisions events`)\n\n"
       << "The event-driven scheme moves every disk on its exact free flight between instantaneous binary "
          "collisions, wall bounces and cell crossings taken one at a time in time order: "
       << s.events.device
       << ". It runs on the CPU whatever `--backend` says, since it has no other backend; "
          "only the stepped runs of 9.4 use `--backend`. dt only sets when its state is sampled.\n\n";
    markdownEventsEos(md, s);
    markdownEventsDense(md, s);
    markdownTrajectories(md, s);
    markdownSchemes(md, s);
}

}  // namespace

const std::vector<std::string>& reportFileNames() {
    static const std::vector<std::string> names = {"README.md",
                                                   "eos.svg",
                                                   "eos-deviation.svg",
                                                   "convergence-z.svg",
                                                   "convergence-energy.svg",
                                                   "relaxation-h.svg",
                                                   "relaxation-ks.svg",
                                                   "relaxation-speeds.svg",
                                                   "energy-density.svg",
                                                   "trajectories.svg",
                                                   "schemes-z.svg"};
    return names;
}

std::map<std::string, std::string> reportFiles(const SuiteResult& r, const RunContext& c) {
    std::ostringstream md;
    markdownHeader(md, r, c);
    markdownEos(md, r.eos, r);
    markdownConvergence(md, r.convergence, r);
    markdownRelaxation(md, r.relaxation, r);
    markdownExact(md, r);
    markdownConservation(md, r);
    markdownDense(md, r);
    markdownGravity(md, r);
    markdownSimultaneous(md, r);
    markdownEvents(md, r);
    return {{"README.md", md.str()},
            {"eos.svg", eosPlot(r.eos, r.events)},
            {"eos-deviation.svg", eosDeviationPlot(r.eos, r.events)},
            {"convergence-z.svg", convergenceZPlot(r.convergence)},
            {"convergence-energy.svg", energyDtPlot(r.convergence, r.simultaneous)},
            {"relaxation-h.svg", hPlot(r.relaxation)},
            {"relaxation-ks.svg", ksPlot(r.relaxation)},
            {"relaxation-speeds.svg", speedPlot(r.relaxation)},
            {"energy-density.svg", energyDensityPlot(r.eos, r.simultaneous)},
            {"trajectories.svg", trajectoryPlot(r.events.trajectories)},
            {"schemes-z.svg", schemesPlot(r.events.schemes)}};
}

namespace {

nlohmann::ordered_json number(double value) {
    return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json();
}

nlohmann::ordered_json meanAndError(const MeanAndError& m) { return {{"mean", m.mean}, {"error", m.error}}; }

nlohmann::ordered_json blockStatistics(const BlockStatistics& m) {
    return {{"blocks", m.blocks},
            {"block_time", m.blockTime},
            {"z", meanAndError(m.z)},
            {"z_blocks", m.zBlocks},
            {"collision_rate", m.collisionRate},
            {"collision_frequency", 2.0 * m.collisionRate},
            {"frequency_ratio", meanAndError(m.rateRatio)},
            {"kT", m.kT},
            {"energy_change", m.energyChange},
            {"late_contacts", m.lateContacts},
            {"max_rounds", m.maxRounds}};
}

nlohmann::ordered_json simultaneousRuns(const std::vector<SimultaneousRun>& runs) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const SimultaneousRun& run : runs)
        out.push_back({{"packing", run.packing},
                       {"dt", run.dt},
                       {"energy_change", run.energyChange},
                       {"drift_rate", run.driftRate},
                       {"wander", run.wander},
                       {"z_second_half", run.z}});
    return out;
}

nlohmann::ordered_json eventsRun(const EventsRun& run) {
    return {{"packing", run.packing},
            {"particles", run.particles},
            {"warmup_collisions_per_disk", run.warmupCollisions},
            {"warmup_time", run.warmupTime},
            {"measured", blockStatistics(run.measured)},
            {"collisions", run.collisions},
            {"cell_crossings", run.cellCrossings},
            {"overlapping", run.overlapping},
            {"energy_change", run.energyChange},
            {"energy_tolerance", run.energyTolerance},
            {"wall_seconds", run.seconds}};
}

nlohmann::ordered_json eventsJson(const EventsResult& e) {
    using json = nlohmann::ordered_json;
    json eos = json::array();
    for (const EventsEosPoint& p : e.eos)
        eos.push_back({{"run", eventsRun(p.run)},
                       {"z_reference", p.zReference},
                       {"z_reference_error", p.zReferenceError},
                       {"z_tolerance", p.zTolerance},
                       {"frequency_tolerance", p.rateTolerance}});
    json published = json::array();
    for (const PublishedPressure& p : e.dense.published)
        published.push_back({{"source", p.source},
                             {"method", p.method},
                             {"particles", p.particles},
                             {"beta_p_sigma2", p.betaPSigma2},
                             {"error", p.error},
                             {"z", compressibility(p, e.dense.run.packing)}});
    json trajectories = json::array();
    for (const TrajectoryPoint& p : e.trajectories.points)
        trajectories.push_back(
            {{"dt", p.dt},
             {"pairwise", {{"rms", p.pairwiseRms}, {"max", p.pairwiseMax}, {"collisions", p.pairwiseCollisions}}},
             {"simultaneous",
              {{"rms", p.simultaneousRms}, {"max", p.simultaneousMax}, {"collisions", p.simultaneousCollisions}}}});
    json schemes = json::array();
    for (const SchemeComparison& c : e.schemes) {
        json runs = json::array();
        for (const SchemeZ& run : c.runs)
            runs.push_back({{"dt", run.dt},
                            {"pairwise", blockStatistics(run.pairwise)},
                            {"pairwise_failure", run.pairwiseFailure},
                            {"simultaneous", blockStatistics(run.simultaneous)},
                            {"simultaneous_failure", run.simultaneousFailure}});
        schemes.push_back({{"packing", c.packing},
                           {"particles", c.particles},
                           {"warmup_time", c.warmupTime},
                           {"z_events", meanAndError(c.events)},
                           {"runs", runs}});
    }
    const TrajectoryResult& t = e.trajectories;
    return {
        {"device", e.device},
        {"equation_of_state", eos},
        {"dense",
         {{"run", eventsRun(e.dense.run)}, {"frequency_tolerance", e.dense.rateTolerance}, {"published", published}}},
        {"trajectories",
         {{"particles", t.particles},
          {"box", {t.width, t.height}},
          {"duration", t.duration},
          {"event_collisions", t.eventCollisions},
          {"event_wall_bounces", t.eventWallBounces},
          {"points", trajectories}}},
        {"schemes", schemes}};
}

}  // namespace

nlohmann::ordered_json toJson(const SuiteResult& r, const RunContext& c) {
    using json = nlohmann::ordered_json;
    json checks = json::array();
    for (const Check& k : r.checks)
        checks.push_back({{"section", k.section},
                          {"name", k.name},
                          {"measured", number(k.measured)},
                          {"expected", number(k.expected)},
                          {"deviation", number(k.deviation)},
                          {"limit", k.limit},
                          {"criterion", k.criterion},
                          {"passed", k.passed}});
    json eos = json::array();
    for (const EosPoint& p : r.eos.points)
        eos.push_back({{"packing", p.packing},
                       {"particles", p.particles},
                       {"equilibration_time", p.equilibrationTime},
                       {"measured", blockStatistics(p.measured)},
                       {"z_reference", p.zReference},
                       {"z_reference_error", p.zReferenceError},
                       {"z_tolerance", p.zTolerance},
                       {"frequency_tolerance", p.rateTolerance}});
    json convergence = json::array();
    for (const ConvergencePoint& p : r.convergence.points)
        convergence.push_back({{"dt", p.dt},
                               {"measured", blockStatistics(p.measured)},
                               {"z_difference", p.zDifference},
                               {"difference_error", p.differenceError}});
    json samples = json::array();
    for (const RelaxationSample& s : r.relaxation.samples)
        samples.push_back({{"time", s.time}, {"h", s.h}, {"ks", s.ks}, {"kT", s.kT}});
    json conservation = json::array();
    for (const ConservationRun& run : r.conservation)
        conservation.push_back({{"backend", run.backend},
                                {"device", run.device},
                                {"particles", run.particles},
                                {"packing", run.packing},
                                {"dt", run.dt},
                                {"steps", run.steps},
                                {"momentum_error", run.momentumError},
                                {"energy_change", run.energyChange},
                                {"collisions_per_disk", run.collisionsPerDisk},
                                {"late_contacts", run.lateContacts}});
    const RelaxationResult& rx = r.relaxation;
    const DenseResult& d = r.dense;
    const GravityResult& g = r.gravity;
    const SimultaneousResult& sim = r.simultaneous;
    return {
        {"suite", r.options.quick ? "quick" : "full"},
        {"passed", r.passed()},
        {"checks_failed", failures(r)},
        {"command", c.command},
        {"date", c.date},
        {"host", {{"cpu", c.host}, {"threads", c.hostThreads}, {"load", c.hostLoad}}},
        {"backend",
         {{"kind", r.options.backend.engine == ComputeEngine::Cpu ? "cpu" : "opencl"},
          {"pipeline", r.options.backend.engine == ComputeEngine::Cpu ? json(nullptr)
                                                                      : json(pipelineName(r.options.backend.engine))},
          {"device", r.device}}},
        {"collisions", {{"sections_1_to_7", "pairwise"}, {"section_8", "simultaneous"}, {"section_9", "events"}}},
        {"dt", r.options.dt},
        {"seed", r.options.seed},
        {"wall_seconds", r.wallSeconds},
        {"checks", checks},
        {"equation_of_state", {{"dt", r.eos.dt}, {"points", eos}}},
        {"convergence",
         {{"packing", r.convergence.packing},
          {"particles", r.convergence.particles},
          {"z_reference", r.convergence.zReference},
          {"equilibration_time", r.convergence.equilibrationTime},
          {"points", convergence}}},
        {"relaxation",
         {{"packing", rx.packing},
          {"particles", rx.particles},
          {"dt", rx.dt},
          {"half_width", rx.halfWidth},
          {"histogram", {{"range", rx.histogram.range}, {"bins_per_axis", rx.histogram.binsPerAxis}}},
          {"h_initial", rx.hInitial},
          {"h_final", rx.hFinal},
          {"h_plugin_bias", rx.hPluginBias},
          {"h_binning_bias", rx.hBinningBias},
          {"h_tolerance", rx.hTolerance},
          {"ks_critical", rx.ksCritical},
          {"kT_final", rx.kTFinal},
          {"samples", samples},
          {"speed_histogram", {{"edges", rx.speedBinEdges}, {"density", rx.speedDensity}}}}},
        {"conservation", conservation},
        {"dense_gas",
         {{"packing", d.packing},
          {"particles", d.particles},
          {"dt", d.dt},
          {"equilibration_time", d.equilibrationTime},
          {"measured", blockStatistics(d.measured)},
          {"energy_change", d.energyChange},
          {"momentum_error", d.momentumError},
          {"max_overlap", d.maxOverlap},
          {"escaped", d.escaped},
          {"frequency_tolerance", d.rateTolerance}}},
        {"gravity",
         {{"particles", g.particles},
          {"box", {g.width, g.height}},
          {"gravity", g.gravity},
          {"dt", g.dt},
          {"duration", g.duration},
          {"kinetic", {{"start", g.kineticStart}, {"end", g.kineticEnd}}},
          {"potential", {{"start", g.potentialStart}, {"end", g.potentialEnd}}},
          {"energy_change", g.energyChange},
          {"late_contacts", g.lateContacts},
          {"max_rounds", g.maxRounds},
          {"escaped", g.escaped}}},
        {"simultaneous_scheme",
         {{"particles", sim.particles},
          {"duration", sim.duration},
          {"sample_interval", sim.sampleInterval},
          {"dt_sweep", simultaneousRuns(sim.dtSweep)},
          {"packing_sweep", simultaneousRuns(sim.packingSweep)}}},
        {"events", eventsJson(r.events)}};
}

void printSummary(std::ostream& out, const SuiteResult& r) {
    for (const Check& c : r.checks)
        out << (c.passed ? "PASS  " : "FAIL  ") << c.section << ": " << c.name << ": " << format("%.6g", c.measured)
            << " (" << c.criterion << ")\n";
    const std::size_t failed = failures(r);
    out << "validate: " << (failed == 0 ? "PASS" : "FAIL") << ", " << r.checks.size() - failed << " of "
        << r.checks.size() << " checks pass";
    out << " (" << (r.options.quick ? "quick" : "full") << " suite, " << format("%.1f", r.wallSeconds) << " s)\n";
}

}  // namespace carom::validation
