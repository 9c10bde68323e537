#include "app/bench/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>

#include <nlohmann/json.hpp>

#include "app/format.h"
#include "app/svg_plot.h"

namespace carom::bench {
namespace {

using app::format;

std::string optionalRatio(std::optional<double> ratio) { return ratio ? format("%.2fx", *ratio) : "-"; }

nlohmann::json optionalJson(std::optional<double> value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

double fractionOfFloor(const Report& report, const Row& row) {
    return floorSecondsPerStep(report, row) / row.timing.secondsPerStep;
}

const Row* findRow(const Report& report, const std::string& method, CollisionScheme scheme, std::uint32_t particles) {
    for (const Row& row : report.rows)
        if (row.variant.method.name == method && row.variant.scheme == scheme && row.particles == particles)
            return &row;
    return nullptr;
}

// The parts of a profile, the slowest first.
std::vector<std::pair<std::string, double>> slowestFirst(const std::map<std::string, double>& profile) {
    std::vector<std::pair<std::string, double>> parts(profile.begin(), profile.end());
    std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    return parts;
}

// The event-driven rows: rates per wall-clock second, not step times (a
// step of dt only sets when the state is sampled); after the stepped table
// when there was one.
void printEventRates(std::ostream& out, const Report& report, bool afterTable) {
    bool first = true;
    char line[200];
    for (const Row& row : report.rows) {
        if (!row.timing.events) continue;
        const EventRates& e = *row.timing.events;
        if (first) {
            out << (afterTable ? "\n" : "")
                << "event-driven, periodic box: per wall-clock second, median of the samples, timed after at "
                   "least "
                << report.plan.warmupCollisionsPerDisk << " collisions per disk\n";
            std::snprintf(line, sizeof line, "%-16s %10s %14s %16s %12s %11s %8s %12s\n", "method", "N", "collisions/s",
                          "particle-time/s", "events/s", "events/coll", "stale", "warm-up c/N");
            out << line;
            first = false;
        }
        const EventCounts& c = e.sampled;
        const double collisions = double(c.collisions);
        std::snprintf(line, sizeof line, "%-16s %10u %14.4g %16.4g %12.4g %11.3g %7.1f%% %12.3g\n",
                      row.variant.method.name.c_str(), row.particles, e.collisionsPerSecond, e.particleTimePerSecond,
                      e.eventsPerSecond, collisions > 0 ? double(eventsOf(c)) / collisions : 0.0,
                      eventsOf(c) > 0 ? 100.0 * double(c.stale) / double(eventsOf(c)) : 0.0, e.warmupCollisionsPerDisk);
        out << line;
    }
    if (!first)
        out << "  events: collisions, wall bounces, cell crossings and stale events recomputed; stale: their share; "
               "warm-up c/N: collisions per disk before the samples\n";
}

// An event-driven row: its rates instead of step times.
nlohmann::json eventRowJson(const Row& row) {
    const EventRates& e = *row.timing.events;
    const EventCounts& c = e.sampled;
    return {
        {"method", row.variant.method.name},
        {"scheme", collisionSchemeName(row.variant.scheme)},
        {"boundary", "periodic"},
        {"particles", row.particles},
        {"collisions_per_second", e.collisionsPerSecond},
        {"particle_time_per_second", e.particleTimePerSecond},
        {"events_per_second", e.eventsPerSecond},
        {"sample_collisions_per_second", e.sampleCollisionsPerSecond},
        {"steps_per_sample", row.timing.stepsPerSample},
        {"warmup_steps", row.timing.warmupSteps},
        {"warmup_collisions_per_disk", e.warmupCollisionsPerDisk},
        {"sampled_events",
         {{"collisions", c.collisions},
          {"wall_bounces", c.wallBounces},
          {"cell_crossings", c.cellCrossings},
          {"stale", c.stale},
          {"overlapping", c.overlapping}}},
    };
}

}  // namespace

std::string variantLabel(const Variant& variant) {
    return variant.scheme == CollisionScheme::Simultaneous || variant.method.eventDriven
               ? variant.method.name
               : variant.method.name + ' ' + collisionSchemeName(variant.scheme);
}

double particleStepsPerSecond(const Row& row) { return row.particles / row.timing.secondsPerStep; }

std::optional<double> speedupOver(const Report& report, const Row& row, const std::string& method) {
    if (const Row* other = findRow(report, method, row.variant.scheme, row.particles))
        return other->timing.secondsPerStep / row.timing.secondsPerStep;
    return std::nullopt;
}

std::optional<double> pairwiseOverSimultaneous(const Report& report, const Row& row) {
    if (row.variant.scheme != CollisionScheme::Pairwise) return std::nullopt;
    if (const Row* other = findRow(report, row.variant.method.name, CollisionScheme::Simultaneous, row.particles))
        return row.timing.secondsPerStep / other->timing.secondsPerStep;
    return std::nullopt;
}

std::string naiveCounterpart(const Method& method) { return method.opencl ? "naive-opencl" : "naive-cpu"; }

double floorSecondsPerStep(const Report& report, const Row& row) {
    const Traffic traffic = trafficPerParticleStep(row.variant, row.cellsPerParticle);
    return row.particles * floorSecondsPerParticleStep(traffic, report.bandwidth);
}

void printTable(std::ostream& out, const Report& report) {
    out << "carom bench, " << report.date << "\n  host   " << report.host << ", " << report.hostThreads
        << " threads, load average " << format("%.2f", report.hostLoad) << " at the start, copy "
        << format("%.1f", report.bandwidth.hostCopy / 1e9) << " GB/s\n";
    if (report.processes > 1)
        out << "  split  among " << report.processes
            << " processes (mpirun), each step timed on the slowest; host and device are process 0's\n";
    if (report.device)
        out << "  device " << report.device->name << " (" << report.device->platform << ", driver "
            << report.device->driver << "), copy " << format("%.1f", report.bandwidth.deviceCopy / 1e9)
            << " GB/s, upload " << format("%.1f", report.bandwidth.upload / 1e9) << " GB/s, download "
            << format("%.1f", report.bandwidth.download / 1e9) << " GB/s\n";
    out << "  scene  packing " << report.scene.packing << ", radius " << report.scene.radiusMin << ", speed "
        << report.scene.speed << ", dt " << report.dt << "; median of " << report.plan.samples
        << " samples after warm-up\n\n";
    char line[200];
    const auto stepped = [](const Row& row) { return !row.timing.events; };
    const bool anyStepped = std::any_of(report.rows.begin(), report.rows.end(), stepped);
    if (anyStepped) {
        std::snprintf(line, sizeof line, "%-16s %-12s %10s %11s %16s %7s %12s %9s %10s %9s\n", "method", "scheme", "N",
                      "ms/step", "particle-steps/s", "pw/sim", "vs host-grid", "vs naive", "floor ms", "of floor");
        out << line;
        for (const Row& row : report.rows) {
            if (!stepped(row)) continue;
            const Method& method = row.variant.method;
            const double floorMs = floorSecondsPerStep(report, row) * 1e3;
            std::snprintf(line, sizeof line, "%-16s %-12s %10u %11.4g %16.3g %7s %12s %9s %10.3g %8.1f%%\n",
                          method.name.c_str(), collisionSchemeName(row.variant.scheme), row.particles,
                          row.timing.secondsPerStep * 1e3, particleStepsPerSecond(row),
                          optionalRatio(pairwiseOverSimultaneous(report, row)).c_str(),
                          optionalRatio(speedupOver(report, row, "opencl-host-grid")).c_str(),
                          optionalRatio(speedupOver(report, row, naiveCounterpart(method))).c_str(), floorMs,
                          100.0 * fractionOfFloor(report, row));
            out << line;
        }
        out << "  pw/sim: a pairwise step's time over a simultaneous step's (same method and N); vs host-grid and vs "
               "naive compare within a scheme\n";
    }
    printEventRates(out, report, anyStepped);
    bool profiled = false;
    for (const Row& row : report.rows) {
        if (row.profile.empty()) continue;
        if (!profiled) out << "\nprofile: time per step of each part, the slowest first, from a separate run\n";
        profiled = true;
        double sum = 0;
        for (const auto& part : row.profile) sum += part.second;
        out << "  " << row.variant.method.name << ", " << collisionSchemeName(row.variant.scheme)
            << ", N = " << row.particles << ": parts sum to " << format("%.4g", sum * 1e6) << " us of "
            << format("%.4g", row.timing.secondsPerStep * 1e6) << " us measured\n";
        for (const auto& [name, seconds] : slowestFirst(row.profile)) {
            std::snprintf(line, sizeof line, "    %11.4g us %5.1f%%  %s\n", seconds * 1e6,
                          sum > 0 ? 100.0 * seconds / sum : 0.0, name.c_str());
            out << line;
        }
    }
    for (const Dropped& d : report.dropped)
        out << "  " << variantLabel(d.variant) << ": dropped after N = " << d.particles << " (a step took "
            << format("%.3g", d.secondsPerStep * 1e3) << " ms, over the budget of "
            << format("%.3g", report.plan.budgetSeconds * 1e3) << " ms)\n";
}

void writeJson(std::ostream& out, const Report& report) {
    using nlohmann::json;
    const Bandwidth& b = report.bandwidth;
    json rows = json::array();
    for (const Row& row : report.rows) {
        if (row.timing.events) {
            rows.push_back(eventRowJson(row));
            continue;
        }
        const Traffic t = trafficPerParticleStep(row.variant, row.cellsPerParticle);
        rows.push_back({
            {"method", row.variant.method.name},
            {"scheme", collisionSchemeName(row.variant.scheme)},
            {"particles", row.particles},
            {"ms_per_step", row.timing.secondsPerStep * 1e3},
            {"sample_ms_per_step",
             [&] {
                 json samples = json::array();
                 for (double s : row.timing.sampleSecondsPerStep) samples.push_back(s * 1e3);
                 return samples;
             }()},
            {"steps_per_sample", row.timing.stepsPerSample},
            {"warmup_steps", row.timing.warmupSteps},
            {"substeps_per_step", row.timing.substepsPerStep},
            {"particle_steps_per_second", particleStepsPerSecond(row)},
            {"pairwise_over_simultaneous", optionalJson(pairwiseOverSimultaneous(report, row))},
            {"speedup_vs_host_grid", optionalJson(speedupOver(report, row, "opencl-host-grid"))},
            {"speedup_vs_naive", optionalJson(speedupOver(report, row, naiveCounterpart(row.variant.method)))},
            {"cells_per_particle", row.cellsPerParticle},
            {"bytes_per_particle_step",
             {{"device", t.device}, {"host", t.host}, {"upload", t.upload}, {"download", t.download}}},
            {"floor_ms_per_step", floorSecondsPerStep(report, row) * 1e3},
            {"fraction_of_floor", fractionOfFloor(report, row)},
            {"device_bytes_per_particle", double(row.timing.devicePeakBytes) / double(row.particles)},
        });
        if (!row.profile.empty()) {
            json profile = json::object();
            for (const auto& [name, seconds] : row.profile) profile[name] = seconds * 1e3;
            rows.back()["profile_ms_per_step"] = profile;
        }
    }
    json dropped = json::array();
    for (const Dropped& d : report.dropped)
        dropped.push_back({{"method", d.variant.method.name},
                           {"scheme", collisionSchemeName(d.variant.scheme)},
                           {"after_particles", d.particles},
                           {"ms_per_step", d.secondsPerStep * 1e3}});
    json device = nullptr;
    if (report.device)
        device = {{"name", report.device->name},
                  {"platform", report.device->platform},
                  {"version", report.device->version},
                  {"driver", report.device->driver}};
    const SceneDef& s = report.scene;
    const json document = {
        {"date", report.date},
        {"host", {{"cpu", report.host}, {"threads", report.hostThreads}, {"load_average_1min", report.hostLoad}}},
        {"processes", report.processes},
        {"opencl_device", device},
        {"scene",
         {{"packing", s.packing},
          {"radius", s.radiusMin},
          {"mass", s.massMin},
          {"speed", s.speed},
          {"seed", s.seed},
          {"dt", report.dt}}},
        {"timing",
         {{"samples", report.plan.samples},
          {"sample_seconds", report.plan.sampleSeconds},
          {"warmup_seconds", report.plan.warmupSeconds},
          {"budget_ms_per_step", report.plan.budgetSeconds * 1e3},
          {"warmup_collisions_per_disk", report.plan.warmupCollisionsPerDisk},
          {"statistic", "median of the samples' mean ms/step; for the events method, of the samples' rates"}}},
        {"bandwidth_bytes_per_second",
         {{"host_copy", b.hostCopy},
          {"device_copy", b.deviceCopy},
          {"upload", b.upload},
          {"download", b.download},
          {"note", "copies count bytes read plus bytes written; best of several runs"}}},
        {"traffic_model",
         "bytes per particle-step: state read and written once (2 x 32), sortedIndices written and read once "
         "(2 x 4), cells written and read once (2 x 8 per cell); neighbour reads hit in cache. Host grid: the host "
         "reads its state copy and writes the grid, uploads the grid, downloads the state. All pairs: the state only. "
         "Pairwise adds its forward search: state (32), sorted index and cell (2 x 4) read, event (8) written; the "
         "host-grid pipeline also writes and uploads the cells (4); the rounds' lists are small and not counted."},
        {"results", rows},
        {"dropped", dropped},
    };
    out << document.dump(2) << '\n';
}

void writeCsv(std::ostream& out, const Report& report) {
    // Later columns come last, so the earlier columns keep their places: the
    // scheme's, then the events method's rates (its step columns are empty,
    // as the rates are the stepped rows').
    out << "method,particles,ms_per_step,particle_steps_per_second,speedup_vs_host_grid,speedup_vs_naive,"
           "floor_ms_per_step,fraction_of_floor,samples,steps_per_sample,scheme,pairwise_over_simultaneous,"
           "collisions_per_second,particle_time_per_second,events_per_second\n";
    const auto optional = [](std::optional<double> v) { return v ? format("%.6g", *v) : std::string(); };
    for (const Row& row : report.rows) {
        const std::optional<EventRates>& events = row.timing.events;
        out << row.variant.method.name << ',' << row.particles << ',';
        if (events)
            out << ",,,,,,";
        else
            out << format("%.6g", row.timing.secondsPerStep * 1e3) << ',' << format("%.6g", particleStepsPerSecond(row))
                << ',' << optional(speedupOver(report, row, "opencl-host-grid")) << ','
                << optional(speedupOver(report, row, naiveCounterpart(row.variant.method))) << ','
                << format("%.6g", floorSecondsPerStep(report, row) * 1e3) << ','
                << format("%.6g", fractionOfFloor(report, row)) << ',';
        out << row.timing.sampleSecondsPerStep.size() << ',' << row.timing.stepsPerSample << ','
            << collisionSchemeName(row.variant.scheme) << ',' << optional(pairwiseOverSimultaneous(report, row));
        if (events)
            out << ',' << format("%.6g", events->collisionsPerSecond) << ','
                << format("%.6g", events->particleTimePerSecond) << ',' << format("%.6g", events->eventsPerSecond);
        else
            out << ",,,";
        out << '\n';
    }
}

// Log-log axes: N across, particle-steps/s up, one line per method and
// scheme (pairwise dotted), and the bandwidth floor of the grid methods under
// the simultaneous scheme as dashed lines (the table and JSON have the
// pairwise floors). The events method's rows are left out: it has no step
// time (the table, JSON and CSV have its rates).
void writeSvgPlot(std::ostream& out, const Report& report) {
    app::Plot plot;
    plot.title = "carom bench: throughput against N, packing " + format("%g", report.scene.packing) +
                 (report.device ? ", " + report.device->name : std::string());
    plot.x = {"N (disks)", true};
    plot.y = {"particle-steps per second", true};
    std::vector<Row> rows;  // the stepped ones: the events method has no step time to plot
    std::copy_if(report.rows.begin(), report.rows.end(), std::back_inserter(rows),
                 [](const Row& row) { return !row.timing.events; });
    if (rows.empty()) {
        plot.title = "carom bench: no stepped method measured, no throughput to plot";
        out << app::renderSvg(plot);
        return;
    }
    const std::map<std::string, std::string> colours = {{"naive-cpu", "#9e9e9e"},
                                                        {"naive-opencl", "#616161"},
                                                        {"cpu", "#1f77b4"},
                                                        {"opencl-host-grid", "#ff7f0e"},
                                                        {"opencl-resident", "#2ca02c"}};
    // Floors (in particle-steps/s) of the grid methods, at the largest N's cells per particle.
    std::map<std::string, double> floors;
    for (const Row& row : rows) {
        const double seconds = floorSecondsPerStep(report, row);
        if (!row.variant.method.allPairs && row.variant.scheme == CollisionScheme::Simultaneous && seconds > 0)
            floors[row.variant.method.name] = row.particles / seconds;
    }
    // Whole decades on both axes.
    double minN = INFINITY, maxN = 0, minY = INFINITY, maxY = 0;
    for (const Row& row : rows) {
        minN = std::min(minN, double(row.particles));
        maxN = std::max(maxN, double(row.particles));
        minY = std::min(minY, particleStepsPerSecond(row));
        maxY = std::max(maxY, particleStepsPerSecond(row));
    }
    for (const auto& [name, rate] : floors) maxY = std::max(maxY, rate);
    const auto decades = [](app::Axis& axis, double min, double max) {
        const double low = std::floor(std::log10(min));
        axis.min = std::pow(10.0, low);
        axis.max = std::pow(10.0, std::max(low + 1, std::ceil(std::log10(max))));
    };
    decades(plot.x, minN, maxN);
    decades(plot.y, minY, maxY);

    for (const Method& method : allMethods()) {
        for (const CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Pairwise}) {
            app::Series line;
            line.style = scheme == CollisionScheme::Pairwise ? app::SeriesStyle::DottedLine : app::SeriesStyle::Line;
            for (const Row& row : rows)
                if (row.variant.method.name == method.name && row.variant.scheme == scheme) {
                    line.x.push_back(row.particles);
                    line.y.push_back(particleStepsPerSecond(row));
                }
            if (line.x.empty()) continue;
            line.label = variantLabel({method, scheme});
            line.colour = colours.at(method.name);
            plot.series.push_back(std::move(line));
        }
        const auto floor = floors.find(method.name);
        if (floor == floors.end() || method.name == "opencl-host-grid") continue;
        plot.series.push_back({method.name + " floor (model)",
                               colours.at(method.name),
                               app::SeriesStyle::DashedLine,
                               {plot.x.min, plot.x.max},
                               {floor->second, floor->second},
                               {}});
    }
    out << app::renderSvg(plot);
}

}  // namespace carom::bench
