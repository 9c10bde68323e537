#include "app/validate/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/validate/svg_plot.h"

namespace carom::validation {

namespace {

const char* const kMeasured = "#d62728";
const char* const kReference = "black";

std::string fixed(double value, int decimals) {
    if (!std::isfinite(value)) return "—";
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

std::string general(double value, int digits = 4) {
    if (!std::isfinite(value)) return "—";
    char text[64];
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    return text;
}

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

void checkTable(std::ostream& md, const SuiteResult& r, const std::string& section) {
    md << "| check | measured | expected | criterion | deviation | result |\n|---|---|---|---|---|---|\n";
    for (const Check& c : r.checks)
        if (section.empty() || c.section == section)
            md << "| " << cell((section.empty() ? c.section + ": " : "") + c.name) << " | " << general(c.measured, 6)
               << " | " << general(c.expected, 6) << " | " << cell(c.criterion) << " | " << general(c.deviation, 3)
               << " | " << verdict(c.passed) << " |\n";
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

std::string eosPlot(const EosResult& eos) {
    Plot plot;
    plot.title = "Equation of state: Z = PA/(NkT) of the hard-disk fluid";
    plot.x = {"packing fraction eta", false, 0.0, 0.65};
    plot.y = {"Z", false, 1.0, NAN};
    plot.series.push_back(curve("reference", kReference, SeriesStyle::Line, referenceZ, false));
    plot.series.push_back(curve("Henderson 1975", "#1f77b4", SeriesStyle::DashedLine, hendersonZ, false));
    plot.series.push_back(curve("Luding 2001", "#2ca02c", SeriesStyle::DashedLine, ludingZ, false));
    plot.series.push_back(curve("Santos et al. 1995", "#9467bd", SeriesStyle::DashedLine, santosZ, false));
    Series measured = line("carom, dt " + general(eos.dt), kMeasured, SeriesStyle::Points, {}, {});
    for (const EosPoint& p : eos.points) {
        measured.x.push_back(p.packing);
        measured.y.push_back(p.z.mean);
        measured.error.push_back(p.z.error);
    }
    plot.series.push_back(measured);
    return renderSvg(plot);
}

std::string eosDeviationPlot(const EosResult& eos) {
    Plot plot;
    plot.title = "Equation of state: deviation from the reference";
    plot.x = {"packing fraction eta", false, 0.0, 0.65};
    plot.y = {"(Z - Z_ref) / Z_ref [%]", false, NAN, NAN};
    plot.series.push_back(line("reference", kReference, SeriesStyle::Line, {0.0, 0.65}, {0.0, 0.0}));
    plot.series.push_back(curve("Henderson 1975", "#1f77b4", SeriesStyle::DashedLine, hendersonZ, true));
    plot.series.push_back(curve("Luding 2001", "#2ca02c", SeriesStyle::DashedLine, ludingZ, true));
    plot.series.push_back(curve("Santos et al. 1995", "#9467bd", SeriesStyle::DashedLine, santosZ, true));
    // One dashed pair per tolerance, over the packings held to it.
    std::vector<double> tolerances;
    for (const EosPoint& p : eos.points)
        if (std::find(tolerances.begin(), tolerances.end(), p.tolerance) == tolerances.end())
            tolerances.push_back(p.tolerance);
    for (double tolerance : tolerances) {
        double lo = 1, hi = 0;
        for (const EosPoint& p : eos.points)
            if (p.tolerance == tolerance) lo = std::min(lo, p.packing - 0.025), hi = std::max(hi, p.packing + 0.025);
        const std::string label = tolerance == tolerances.front() ? "tolerance" : "";
        for (double sign : {1.0, -1.0})
            plot.series.push_back(line(sign > 0 ? label : "", "#ff7f0e", SeriesStyle::DashedLine, {lo, hi},
                                       {sign * 100 * tolerance, sign * 100 * tolerance}));
    }
    Series measured = line("carom, dt " + general(eos.dt), kMeasured, SeriesStyle::Points, {}, {});
    for (const EosPoint& p : eos.points) {
        measured.x.push_back(p.packing);
        measured.y.push_back(100.0 * (p.z.mean / p.zReference - 1.0));
        measured.error.push_back(100.0 * p.z.error / p.zReference);
    }
    plot.series.push_back(measured);
    return renderSvg(plot);
}

Series fitLine(const PowerLaw& fit, const std::vector<ConvergencePoint>& points) {
    std::vector<double> x, y;
    for (const ConvergencePoint& p : points) {
        x.push_back(p.dt);
        y.push_back(fit.coefficient * std::pow(p.dt, fit.order));
    }
    return line("fit: order " + fixed(fit.order, 2), "#1f77b4", SeriesStyle::DashedLine, x, y);
}

std::string convergenceZPlot(const ConvergenceResult& c) {
    Plot plot;
    plot.title = "Convergence: |Z - Z_ref| against dt at eta = " + fixed(c.packing, 2);
    plot.x = {"dt", true, NAN, NAN};
    plot.y = {"|Z - Z_ref|", true, NAN, NAN};
    Series measured = line("carom (1 s.e. bars)", kMeasured, SeriesStyle::Points, {}, {});
    for (const ConvergencePoint& p : c.points) {
        measured.x.push_back(p.dt);
        measured.y.push_back(p.zError);
        measured.error.push_back(p.z.error);
    }
    plot.series.push_back(measured);
    plot.series.push_back(fitLine(c.zErrorFit, c.points));
    return renderSvg(plot);
}

std::string convergenceEnergyPlot(const ConvergenceResult& c) {
    Plot plot;
    plot.title = "Convergence: energy drift against dt at eta = " + fixed(c.packing, 2);
    plot.x = {"dt", true, NAN, NAN};
    plot.y = {"rms |dE|/E per block / block time", true, NAN, NAN};
    Series measured = line("carom", kMeasured, SeriesStyle::Points, {}, {});
    for (const ConvergencePoint& p : c.points) {
        measured.x.push_back(p.dt);
        measured.y.push_back(p.energyDriftRate);
    }
    plot.series.push_back(measured);
    plot.series.push_back(fitLine(c.driftFit, c.points));
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
    plot.series.push_back(line("H of the uniform start", "#1f77b4", SeriesStyle::DashedLine, {0, end},
                               {hUniform, hUniform}));
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
    plot.series.push_back(line("5 % critical value", kReference, SeriesStyle::DashedLine, {0, end},
                               {r.ksCritical, r.ksCritical}));
    return renderSvg(plot);
}

std::string speedPlot(const RelaxationResult& r) {
    Plot plot;
    plot.title = "Relaxation: final speed distribution";
    if (!relaxationRan(r)) return noData(plot.title);
    plot.x = {"speed |v|", false, 0.0, r.speedBinEdges.back()};
    plot.y = {"probability density", false, 0.0, NAN};
    plot.series.push_back(line("carom, t = " + general(r.samples.back().time), kMeasured, SeriesStyle::Steps,
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
       << r.checks.size() << " checks pass.\n\n"
       << "carom's time-stepped collisions against the published hard-disk results of the reference "
          "(`shared/physics/hard-disks.md`: Clisby & McCoy 2006, Luding 2001, Henderson 1975, Santos, "
          "López de Haro & Yuste 1995). Produced by `carom validate`; "
       << (r.options.quick ? "this is the **quick** suite (CI): fewer disks and shorter runs, with the same "
                             "tolerances (those that follow from the sample size say so); the full suite is "
                             "`carom validate` without `--quick`."
                           : "this is the full suite.")
       << "\n\n| | |\n|---|---|\n"
       << "| command | `" << c.command << "` |\n"
       << "| date | " << c.date << " |\n"
       << "| backend | " << r.device << " |\n"
       << "| host | " << c.host << ", " << c.hostThreads << " OpenMP threads, load " << general(c.hostLoad, 3)
       << " at the start |\n"
       << "| dt | " << general(r.options.dt) << " (equation of state, relaxation, conservation); convergence: ";
    for (std::size_t k = 0; k < r.convergence.points.size(); ++k)
        md << (k ? ", " : "") << general(r.convergence.points[k].dt);
    md << "; two-body cases 1e-4, wall bounce 1e-3 |\n"
       << "| seed | " << r.options.seed << " |\n"
       << "| wall time | " << fixed(r.wallSeconds, 1) << " s |\n\n"
       << "Units: disks of radius 1 (σ = 2) and mass 1 at kT = 1; a disk's mean speed is then √(π/2) ≈ 1.25 "
          "radii per unit time.\n\n## All checks\n\n";
    checkTable(md, r, "");
}

void markdownEos(std::ostream& md, const EosResult& e, const SuiteResult& r) {
    md << "## 1. Equation of state\n\n"
       << "N disks in a periodic box at packing fraction η, started from `makeInitialState`'s hexagonal lattice "
          "with Gaussian velocities (zero total momentum, kT = 1). The lattice melts, then Z is measured over "
       << e.blocks << " blocks at dt = " << general(e.dt)
       << " (times in the table: at least 20 and 2 collisions per disk). Each block starts from kT = 1: the "
          "scheme does not conserve energy in dense systems (section 2), "
          "and the bias of Z grows with the distance a disk moves per step, so the velocities are rescaled "
          "between blocks to keep that distance what dt says. Within a block, from the contacts the backend "
          "counts (`Backend::contacts()`, `thermodynamics()`):\n\n"
       << "- kT = (E_kin − P²/2M) / (N − 1), the mean of its values at the block's start and end\n"
       << "- P A = N kT + Σ r_ij · J_ij / (2 t), the collision virial with the centre distance r_ij at which "
          "each impulse J_ij = 2 μ_ij |v_n| is applied, and Z = P A / (N kT)\n"
       << "- collision rate = collisions / (N t), each pair once\n\n"
       << "Z is the mean of the block values; the error is the standard error of the block means. "
       << "Tolerance: 1 % for η ≤ 0.5, 2 % at η = 0.6"
       << (r.options.quick ? ", as in the full suite; the quick suite's runs are shorter (blocks of 5 instead "
                             "of 10 time units) with N = 2048 unless --particles says otherwise, so its "
                             "statistical error is about 1.4 times the full suite's at the same N."
                           : ".")
       << "\n\n| η | N | melt time | blocks × time | Z | Z_ref | deviation | tolerance | collisions per disk "
          "and unit time | kT | rms ΔE/E per block | result |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t k = 0; k < e.points.size(); ++k) {
        const EosPoint& p = e.points[k];
        const double deviation = 100.0 * (p.z.mean / p.zReference - 1.0);
        md << "| " << fixed(p.packing, 2) << " | " << p.particles << " | " << general(p.equilibrationTime, 3)
           << " | " << e.blocks << " × " << general(p.blockTime, 3) << " | " << fixed(p.z.mean, 4) << " ± "
           << fixed(p.z.error, 4) << " | " << general(p.zReference, 6) << " | " << fixed(deviation, 2) << " % | "
           << general(100 * p.tolerance) << " % | " << fixed(p.collisionRate, 3) << " | " << fixed(p.kT, 4)
           << " | " << general(p.energyChangeRms, 2) << " | "
           << verdict(std::abs(deviation) <= 100 * p.tolerance) << " |\n";
    }
    md << "\n![Z against packing fraction](eos.svg)\n\n![Deviation from the reference](eos-deviation.svg)\n\n";
}

void markdownConvergence(std::ostream& md, const ConvergenceResult& c, const SuiteResult& s) {
    md << "## 2. Convergence in dt\n\n"
       << "One melted state at η = " << fixed(c.packing, 2) << " (N = " << c.particles
       << ", periodic) continued at each dt: two blocks to settle, then " << c.blocks
       << " measured blocks of duration " << general(c.blockTime)
       << ", each started from kT = 1 as in section 1. The energy drift is the root "
          "mean square of the relative energy change over a block, divided by the block time. Simultaneous "
          "contacts are resolved together (Jacobi), which conserves momentum but not energy: a disk hit by "
          "two others in one step takes both impulses, computed from the velocities before the step. Such "
          "steps become rarer as dt shrinks, so the drift falls with dt; they are random in sign (a random "
          "walk of the energy, order about 1/2) until the density makes them systematic.\n\n"
       << "| dt | Z | \\|Z − Z_ref\\| | energy drift per unit time |\n|---|---|---|---|\n";
    for (const ConvergencePoint& p : c.points)
        md << "| " << general(p.dt) << " | " << fixed(p.z.mean, 4) << " ± " << fixed(p.z.error, 4) << " | "
           << fixed(p.zError, 4) << " | " << general(p.energyDriftRate, 3) << " |\n";
    double largestWithinOnePercent = 0.0;
    for (const ConvergencePoint& p : c.points)
        if (p.zError <= 0.01 * c.zReference) largestWithinOnePercent = std::max(largestWithinOnePercent, p.dt);
    md << "\nThe largest dt measured here with Z within 1 % of the reference: "
       << (largestWithinOnePercent > 0 ? general(largestWithinOnePercent) : std::string("none")) << ".\n";
    md << "\nObserved orders (log-log least squares over all dt): |Z − Z_ref| ∝ dt^" << fixed(c.zErrorFit.order, 2)
       << ", energy drift ∝ dt^" << fixed(c.driftFit.order, 2) << ". Z_ref = " << general(c.zReference, 6)
       << ". Where |Z − Z_ref| is within about two standard errors (the bars) of zero, the bias is below "
          "what the run resolves and flattens the fitted order.\n\n";
    checkTable(md, s, "convergence");
    md << "![|Z - Z_ref| against dt](convergence-z.svg)\n\n![Energy drift against dt](convergence-energy.svg)\n\n";
}

void markdownRelaxation(std::ostream& md, const RelaxationResult& r, const SuiteResult& s) {
    md << "## 3. Relaxation to Maxwell–Boltzmann\n\n";
    if (!relaxationRan(r)) {
        md << "The relaxation runs failed:\n\n";
        checkTable(md, s, "relaxation");
        return;
    }
    md << r.particles << " disks at η = " << fixed(r.packing, 2) << " in a periodic box, dt = " << general(r.dt)
       << ", start with velocities uniform on the square [−a, a]², a = √3 (kT = a²/3 = 1), minus their mean. "
          "Every " << general(r.samples[1].time - r.samples[0].time) << " time units: H = ∫ f ln f d²v from a "
       << r.histogram.binsPerAxis << " × " << r.histogram.binsPerAxis << " histogram over [−3a, 3a]² (bins of "
       << "a/4, so ±a are bin edges), and the Kolmogorov–Smirnov statistic D of the speeds against the "
          "Rayleigh distribution at the state's kT.\n\n"
       << "- H falls by H_eq(kT_end) − H_uniform = ln(6/π) − 1 − ln(kT_end/kT_start) (= −0.3529 with exact "
          "energy conservation). Measured: H_end − H_start = "
       << fixed(r.hFinal - r.hInitial, 4) << ", with H_end the mean of the last " << r.finalSnapshots
       << " samples. Tolerance " << fixed(r.hTolerance, 4) << ": the plug-in bias (occupied bins − 1)/(2n) = "
       << fixed(r.hPluginBias, 4) << " (upwards), plus the binning bias of a Gaussian, w²/(12 kT/m) = "
       << fixed(r.hBinningBias, 4) << " (downwards, bins of width w), plus three standard errors of one "
          "snapshot, 3/√n = "
       << fixed(3 / std::sqrt(double(r.particles)), 4) << ".\n- Final D = " << fixed(r.samples.back().ks, 4)
       << " against the 5 % critical value 1.358/√n = "
       << fixed(r.ksCritical, 4) << " (at the start D = " << fixed(r.samples.front().ks, 3) << ").\n\n";
    checkTable(md, s, "relaxation");
    md << "![H against time](relaxation-h.svg)\n\n![KS statistic against time](relaxation-ks.svg)\n\n"
       << "![Final speed histogram](relaxation-speeds.svg)\n\n";
}

void markdownExact(std::ostream& md, const SuiteResult& s) {
    md << "## 4. Exact cases\n\n"
       << "Two disks of radius 1 in a 100 × 100 box with walls, dt = 1e-4, stepped until they have collided "
          "once and moved apart, against the two-body formula of the reference (the outcomes it lists, and "
          "for the heavy projectile the formula at the exact contact point). The engine finds a contact up to "
          "|u| dt after it happens, which tilts the collision normal by at most |u| dt / σ = 5e-5 rad; the "
          "tolerances are 20 times that. Then one disk (r = 1, v = (3, 0.4)) between walls 10 apart, "
          "dt = 1e-3: the period of its x motion from the steps at which it leaves the left wall.\n\n";
    checkTable(md, s, "exact cases");
}

void markdownConservation(std::ostream& md, const SuiteResult& s) {
    md << "## 5. Conservation on every backend\n\n"
       << "Each backend this build has (OpenCL with both pipelines, on the device `--device` names) runs the "
          "same periodic box from the same state. Momentum is conserved to rounding: every impulse is applied "
          "to both disks of a pair. The kinetic energy is not conserved exactly (section 2 measures how it "
          "wanders with dt); here its change over 10 time units (about 12 collisions per disk) is held to 1 %, "
          "a bound against gross errors: a wrong impulse would change the energy by its whole size within a "
          "few collisions per disk.\n\n"
       << "| backend | device | N | η | dt | steps | \\|ΔP\\| / Σm\\|v\\| | ΔE/E |\n"
       << "|---|---|---|---|---|---|---|---|\n";
    for (const ConservationRun& run : s.conservation)
        md << "| " << run.backend << " | " << cell(run.device) << " | " << run.particles << " | "
           << fixed(run.packing, 2) << " | " << general(run.dt) << " | " << run.steps << " | "
           << general(run.momentumError, 3) << " | " << general(run.energyChange, 3) << " |\n";
    md << '\n';
    checkTable(md, s, "conservation");
}

}  // namespace

const std::vector<std::string>& reportFileNames() {
    static const std::vector<std::string> names = {
        "README.md",        "eos.svg",          "eos-deviation.svg", "convergence-z.svg", "convergence-energy.svg",
        "relaxation-h.svg", "relaxation-ks.svg", "relaxation-speeds.svg"};
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
    return {{"README.md", md.str()},
            {"eos.svg", eosPlot(r.eos)},
            {"eos-deviation.svg", eosDeviationPlot(r.eos)},
            {"convergence-z.svg", convergenceZPlot(r.convergence)},
            {"convergence-energy.svg", convergenceEnergyPlot(r.convergence)},
            {"relaxation-h.svg", hPlot(r.relaxation)},
            {"relaxation-ks.svg", ksPlot(r.relaxation)},
            {"relaxation-speeds.svg", speedPlot(r.relaxation)}};
}

namespace {

nlohmann::ordered_json number(double value) {
    return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json();
}

nlohmann::ordered_json meanAndError(const MeanAndError& m) { return {{"mean", m.mean}, {"error", m.error}}; }

nlohmann::ordered_json powerLaw(const PowerLaw& fit) {
    return {{"order", fit.order}, {"coefficient", fit.coefficient}};
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
                          {"passes_when", k.lowerBound ? "deviation > limit" : "deviation <= limit"},
                          {"criterion", k.criterion},
                          {"passed", k.passed}});
    json eos = json::array();
    for (const EosPoint& p : r.eos.points)
        eos.push_back({{"packing", p.packing},
                       {"particles", p.particles},
                       {"equilibration_time", p.equilibrationTime},
                       {"block_time", p.blockTime},
                       {"z", meanAndError(p.z)},
                       {"z_reference", p.zReference},
                       {"tolerance", p.tolerance},
                       {"collision_rate", p.collisionRate},
                       {"kT", p.kT},
                       {"energy_change_rms_per_block", p.energyChangeRms}});
    json convergence = json::array();
    for (const ConvergencePoint& p : r.convergence.points)
        convergence.push_back({{"dt", p.dt},
                               {"z", meanAndError(p.z)},
                               {"z_error", p.zError},
                               {"energy_drift_rate", p.energyDriftRate}});
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
                                {"energy_change", run.energyChange}});
    const RelaxationResult& rx = r.relaxation;
    return {{"suite", r.options.quick ? "quick" : "full"},
            {"passed", r.passed()},
            {"checks_failed", failures(r)},
            {"command", c.command},
            {"date", c.date},
            {"host", {{"cpu", c.host}, {"threads", c.hostThreads}, {"load", c.hostLoad}}},
            {"backend", {{"kind", r.options.backend.kind}, {"pipeline", r.options.backend.pipeline},
                         {"device", r.device}}},
            {"dt", r.options.dt},
            {"seed", r.options.seed},
            {"wall_seconds", r.wallSeconds},
            {"checks", checks},
            {"equation_of_state",
             {{"dt", r.eos.dt},
              {"blocks", r.eos.blocks},
              {"points", eos}}},
            {"convergence",
             {{"packing", r.convergence.packing},
              {"particles", r.convergence.particles},
              {"z_reference", r.convergence.zReference},
              {"block_time", r.convergence.blockTime},
              {"blocks", r.convergence.blocks},
              {"z_error_fit", powerLaw(r.convergence.zErrorFit)},
              {"energy_drift_fit", powerLaw(r.convergence.driftFit)},
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
            {"conservation", conservation}};
}

void printSummary(std::ostream& out, const SuiteResult& r) {
    for (const Check& c : r.checks)
        out << (c.passed ? "PASS  " : "FAIL  ") << c.section << ": " << c.name << ": " << general(c.measured, 6)
            << " (" << c.criterion << ")\n";
    const std::size_t failed = failures(r);
    out << "validate: " << (failed == 0 ? "PASS" : "FAIL") << ", " << r.checks.size() - failed << " of "
        << r.checks.size() << " checks pass (" << (r.options.quick ? "quick" : "full") << " suite, "
        << fixed(r.wallSeconds, 1) << " s)\n";
}

}  // namespace carom::validation
