// `carom bench`: the performance comparison of the methods (app/bench/methods.h),
// each under the collision schemes it runs, over a sweep of N on one scene,
// against the measured memory bandwidths.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include <carom/files.h>
#include <carom/io.h>
#include <carom/world.h>

#include "app/commands.h"
#include "app/host_info.h"
#include "app/number_options.h"
#include "app/output_plan.h"
#include "app/processes.h"
#include "app/renamed_value.h"
#include "app/stop_signals.h"
#include "app/bench/report.h"

namespace carom::app {

using namespace carom::bench;

namespace {

// The largest N of the default sweep for the events method.
constexpr std::uint32_t kEventsLargestDefault = 1'000'000;
const std::vector<std::uint32_t> kDefaultSizes = {1000,   2000,   5000,    10000,   20000,   50000,   100000,
                                                  200000, 500000, 1000000, 2000000, 4000000, 8000000, 16000000};
const std::vector<std::uint32_t> kQuickSizes = {1000, 4000};
const std::vector<CollisionScheme> kSchemes = {CollisionScheme::Simultaneous, CollisionScheme::Pairwise,
                                               CollisionScheme::Events};
// Bandwidth buffers: well beyond the caches, and about the size of the
// largest state swept; small for --quick.
constexpr std::size_t kMinBandwidthBytes = std::size_t(64) << 20;
constexpr std::size_t kMaxBandwidthBytes = std::size_t(512) << 20;
constexpr std::size_t kQuickBandwidthBytes = std::size_t(16) << 20;

// Refused above what `availableBytes` of memory hold.
std::uint32_t parseSize(const std::string& text, std::uint64_t availableBytes) {
    std::uint64_t count = 0;
    try {
        count = parseParticleCount(text, 1, kMaxParticles);
    } catch (const Error& e) {
        throw Error(std::string("--sizes: ") + e.what());
    }
    requireRoomFor(count, "--sizes " + text, availableBytes);
    return static_cast<std::uint32_t>(count);
}

std::vector<std::uint32_t> chosenSizes(const BenchOptions& o) {
    std::vector<std::uint32_t> sizes;
    const std::uint64_t availableBytes = availableMemoryBytes();
    for (const std::string& text : o.sizes) sizes.push_back(parseSize(text, availableBytes));
    if (sizes.empty()) sizes = o.quick ? kQuickSizes : kDefaultSizes;
    std::sort(sizes.begin(), sizes.end());
    sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
    return sizes;
}

// Under mpirun, the methods that step a World: the others run in one process.
bool splits(const Method& method) { return !method.allPairs && !method.eventDriven; }

std::vector<Method> chosenMethods(const BenchOptions& o) {
    const bool split = processCount() > 1;
    std::vector<Method> methods;
    if (o.methods.empty()) {
        for (const Method& m : availableMethods())
            if (!split || splits(m)) methods.push_back(m);
        return methods;
    }
    for (const std::string& name : o.methods)
        if (const Method method = findMethod(name); split && !splits(method))  // findMethod refuses unknown names
            throw Error("--methods " + name +
                        ": runs in one process; allowed under mpirun: the methods that step a world (cpu, "
                        "opencl-host-grid, opencl-resident)");
    for (const Method& m : availableMethods())  // table order, whatever the order given
        if (std::find(o.methods.begin(), o.methods.end(), m.name) != o.methods.end()) methods.push_back(m);
    return methods;
}

std::vector<CollisionScheme> chosenSchemes(const BenchOptions& o) {
    if (o.collisions.empty())
        return processCount() > 1 ? std::vector<CollisionScheme>{kSchemes[0], kSchemes[1]} : kSchemes;
    std::vector<CollisionScheme> given;
    for (const std::string& name : o.collisions) {
        try {
            given.push_back(parseCollisionScheme(name));
        } catch (const Error& e) {
            throw Error(std::string("--collisions: ") + e.what());
        }
    }
    std::vector<CollisionScheme> schemes;
    for (CollisionScheme scheme : kSchemes)  // table order
        if (std::find(given.begin(), given.end(), scheme) != given.end()) schemes.push_back(scheme);
    return schemes;
}

// Each method under each scheme it runs, a method's schemes next to each
// other; refuses a choice that leaves nothing to measure.
std::vector<Variant> chosenVariants(const BenchOptions& o) {
    const std::vector<Method> methods = chosenMethods(o);
    const std::vector<CollisionScheme> schemes = chosenSchemes(o);
    std::vector<Variant> variants;
    for (const Method& method : methods)
        for (CollisionScheme scheme : schemes)
            if (runsScheme(method, scheme)) variants.push_back({method, scheme});
    if (variants.empty()) {
        std::string names;
        for (CollisionScheme scheme : schemes)
            names += (names.empty() ? "" : ",") + std::string(collisionSchemeName(scheme));
        throw Error("--collisions " + names + ": none of the methods chosen runs " +
                    (schemes.size() == 1 ? "the " + names + " scheme" : "any of these schemes") +
                    " (the naive methods run the simultaneous scheme only, the events method the events scheme "
                    "only); add a method that does, such as cpu or events");
    }
    // Its timing waits for the gas to leave the lattice, which a gas at rest never does.
    const bool events =
        std::any_of(variants.begin(), variants.end(), [](const Variant& v) { return v.method.eventDriven; });
    if (events && !(o.speed > 0)) {
        throw Error("--speed " + io::shortestText(o.speed) +
                    ": the events method times collisions, and disks at rest never collide; give --speed > 0 "
                    "(or leave events out of --methods)");
    }
    return variants;
}

TimingPlan timingPlan(const BenchOptions& o) {
    TimingPlan plan;
    if (o.quick) {
        plan.samples = 3;
        plan.sampleSeconds = 0.01;
        plan.warmupSeconds = 0.02;
    }
    if (o.samples > 0) plan.samples = o.samples;
    plan.budgetSeconds = o.budgetMs / 1e3;
    return plan;
}

SceneDef sceneFor(const BenchOptions& o, std::uint32_t particles) {
    SceneDef scene;
    scene.particles = particles;
    scene.packing = o.packing;
    scene.radiusMin = scene.radiusMax = o.radius;
    scene.speed = o.speed;
    scene.seed = o.seed;
    return scene;
}

// Measures every method under each of its schemes at one N; adds the rows,
// and drops the variants whose step went over the budget.
void benchOneSize(const BenchOptions& o, std::uint32_t particles, bool largerFollow, std::vector<Variant>& variants,
                  Report& report, const std::shared_ptr<const Decomposition>& decomposition) {
    const Scene scene = makeScene(sceneFor(o, particles));
    std::vector<Variant> kept;
    for (const Variant& variant : variants) {
        WorldDef world;
        world.width = scene.width;
        world.height = scene.height;
        world.dt = o.dt;
        world.collisions = variant.scheme;
        world.device = o.device;
        world.decomposition = decomposition;
        // The event-driven benchmarks' box (the literature's and issue 12's targets).
        if (variant.method.eventDriven) world.boundary = Boundary::Periodic;
        const double cells = cellsPerParticle(world, o.radius, particles);
        std::unique_ptr<Stepper> stepper = makeStepper(variant.method, world, scene.disks);
        Row row{variant, particles, cells, timeSteps(*stepper, report.plan), {}};
        stepper.reset();  // free its memory before the next method allocates
        if (o.profile) {
            const std::uint64_t stepsTimed =
                row.timing.warmupSteps + row.timing.stepsPerSample * row.timing.sampleSecondsPerStep.size();
            row.profile = profileMethod(variant.method, world, scene.disks, row.timing.stepsPerSample,
                                        row.timing.substepsPerStep, stepsTimed);
        }
        std::cerr << "  " << variantLabel(variant) << ", N = " << particles << ": ";
        if (row.timing.events)
            std::cerr << row.timing.events->collisionsPerSecond << " collisions/s\n";
        else
            std::cerr << row.timing.secondsPerStep * 1e3 << " ms/step\n";
        report.rows.push_back(row);
        // The default sweep stops the event-driven method at 10^6 disks: its
        // warm-up (3 collisions per disk) takes minutes beyond that.
        const bool eventsDone = variant.method.eventDriven && o.sizes.empty() && particles >= kEventsLargestDefault;
        if (eventsDone) continue;
        if (row.timing.secondsPerStep <= report.plan.budgetSeconds) {
            kept.push_back(variant);
        } else if (largerFollow) {
            report.dropped.push_back({variant, particles, row.timing.secondsPerStep});
        }
    }
    variants = kept;
}

int listMethods() {
    std::cout << "methods (carom bench --methods NAME,...):\n";
    for (const Method& m : availableMethods())
        std::cout << "  " << m.name << std::string(18 - m.name.size(), ' ') << m.description << '\n';
    std::cout << "collision schemes (--collisions NAME,...; default: all): simultaneous, pairwise, events; the "
                 "naive methods run simultaneous only, the events method events only (in a periodic box)\n";
    std::cout << "default sizes (--sizes N,...):";
    for (std::uint32_t n : kDefaultSizes) std::cout << ' ' << n;
    std::cout << "\nquick sizes (--quick):";
    for (std::uint32_t n : kQuickSizes) std::cout << ' ' << n;
    std::cout << '\n';
    return 0;
}

// A comma-separated list: CLI11's delimiter would skip empty entries
// ("1000,,2000", "cpu,"), so the entries are split here and an empty one is
// refused; `each` (a CLI11 transform) may rewrite each entry.
void addListOption(CLI::App& command, const std::string& name, std::vector<std::string>& entries,
                   const std::string& description, const CLI::Validator& each = CLI::Validator()) {
    command.add_option_function<std::vector<std::string>>(
        name,
        [&entries, name, each](const std::vector<std::string>& given) {
            for (const std::string& list : given) {
                std::string entry;
                for (std::istringstream split(list + ','); std::getline(split, entry, ',');) {
                    if (entry.empty())
                        throw CLI::ValidationError(name, "'" + io::printable(list) +
                                                             "' has an empty entry; allowed: entries separated by "
                                                             "single commas");
                    const std::string refusal = each(entry);
                    if (!refusal.empty()) throw CLI::ValidationError(name, refusal);
                    entries.push_back(entry);
                }
            }
        },
        description);
}

}  // namespace

void addBenchOptions(CLI::App& command, BenchOptions& o) {
    addListOption(command, "--methods", o.methods, "Methods to compare, comma-separated (see --list; default: all)",
                  renamedValue("--methods", "opencl-seed", "opencl-host-grid"));
    addListOption(command, "--collisions", o.collisions,
                  "Collision schemes to measure each method under, comma-separated: simultaneous, pairwise, "
                  "events (default: all; the naive methods run simultaneous only, the events method events "
                  "only). The table gives pw/sim, a pairwise step's time over a simultaneous one's, and the "
                  "events method's collisions, events and particle-time per second");
    addListOption(command, "--sizes", o.sizes,
                  "Particle counts N, comma-separated, e.g. 1e3,1e6,1.6e7 (default: 1e3 to 1.6e7)");
    command.add_option("--packing", o.packing, "Area fraction of the disks")
        ->transform(realNumber())
        ->capture_default_str();
    command.add_option("--radius", o.radius, "Radius of every disk")->transform(realNumber())->capture_default_str();
    command.add_option("--speed", o.speed, "Initial speed of every disk")
        ->transform(realNumber())
        ->capture_default_str();
    command.add_option("--dt", o.dt, "Time step")->transform(realNumber())->capture_default_str();
    command.add_option("--seed", o.seed, "Random seed of the scene")->transform(wholeNumber(0))->capture_default_str();
    command.add_option("--device", o.device, "OpenCL device: index from `carom devices` or part of its name");
    command.add_option("--samples", o.samples, "Timed samples per method and N (default 7, 3 with --quick)")
        ->transform(wholeNumber(1, 1000));
    command.add_option("--budget-ms", o.budgetMs, "Drop a method for larger N once one step takes longer than this")
        ->transform(realNumber())
        ->capture_default_str();
    fileOption(
        command.add_option("--json", o.json,
                           "Write the results as JSON to this file: a result per method, scheme and N (its fields "
                           "method, scheme, particles, ms_per_step, pairwise_over_simultaneous, ...; the events "
                           "method's collisions_per_second, particle_time_per_second, events_per_second, ...)"));
    fileOption(
        command.add_option("--csv", o.csv, "Write the results as CSV to this file: a row per method, scheme and N"));
    fileOption(command.add_option(
        "--plot", o.plot, "Write an SVG plot of throughput against N to this file: a line per method and scheme"));
    command.add_flag(
        "--profile", o.profile,
        "Also show where a step's time goes, under each scheme: device time per kernel and "
        "transfer (OpenCL; the pairwise kernels too), the grid build (cpu, on its threads); from separate runs");
    command.add_flag("--quick", o.quick, "A short run for CI: N = 1000 and 4000, 3 short samples");
    command.add_flag("--list", o.list, "List the methods, the collision schemes and the default sizes, then exit");
}

int benchCommand(const BenchOptions& o) {
    if (o.list) return listMethods();
    // Under mpirun every process steps its domain of each world; process 0 reports.
    const std::shared_ptr<const Decomposition> decomposition = runDecomposition(0, 0);
    if (decomposition && o.profile) throw Error("--profile: profiles one process; allowed under mpirun: leave it out");
    // The results are written at the end: a signal before then ends the
    // bench at once, with no file written (the rows measured so far are on stderr).
    StopSignals stopSignals(StopSignals::FirstSignal::Ends, "carom bench");
    std::vector<Variant> variants = chosenVariants(o);
    const std::vector<std::uint32_t> sizes = chosenSizes(o);
    validate(sceneFor(o, sizes.front()));
    WorldDef unitBox;
    unitBox.width = unitBox.height = 1.0f;
    unitBox.dt = o.dt;
    validate(unitBox);
    if (!(std::isfinite(o.budgetMs) && o.budgetMs > 0)) {
        std::ostringstream message;
        message << "--budget-ms must be a finite number > 0, got " << o.budgetMs;
        throw Error(message.str());
    }
    // Refuse unwritable outputs before the sweep, not after it.
    // Process 0 writes them.
    const bool writes = processRank() == 0;
    OutputPlan plan;
    for (const auto& [option, path] :
         {std::pair{"--json", o.json}, std::pair{"--csv", o.csv}, std::pair{"--plot", o.plot}})
        if (!path.empty() && writes) plan.output(option, path);
    plan.check();
    std::optional<io::AtomicFile> json, csv, plot;
    if (!o.json.empty() && writes) json.emplace(o.json);
    if (!o.csv.empty() && writes) csv.emplace(o.csv);
    if (!o.plot.empty() && writes) plot.emplace(o.plot);

    Report report;
    report.date = utcNow();
    report.host = hostCpu();
    report.hostThreads = hostThreads();
    report.hostLoad = hostLoad();
    report.scene = sceneFor(o, 0);
    report.dt = o.dt;
    report.plan = timingPlan(o);
    report.processes = processCount();
    if (decomposition) report.plan.agreed = slowestProcess;
    const std::size_t bandwidthBytes =
        o.quick ? kQuickBandwidthBytes
                : std::clamp(std::size_t(sizes.back()) * 2 * kDiskStateBytes, kMinBandwidthBytes, kMaxBandwidthBytes);
    report.bandwidth.hostCopy = measureHostCopy(bandwidthBytes, 5);
    if (std::any_of(variants.begin(), variants.end(), [](const Variant& v) { return v.method.opencl; }))
        report.device = measureDeviceBandwidth(o.device, bandwidthBytes, 5, report.bandwidth);

    for (std::size_t k = 0; k < sizes.size() && !variants.empty(); ++k)
        benchOneSize(o, sizes[k], k + 1 < sizes.size(), variants, report, decomposition);

    stopSignals.setFirstSignal(StopSignals::FirstSignal::Stops);  // each file is written whole
    printTable(std::cout, report);
    if (json) {
        writeJson(json->stream(), report);
        json->commit();
    }
    if (csv) {
        writeCsv(csv->stream(), report);
        csv->commit();
    }
    if (plot) {
        writeSvgPlot(plot->stream(), report);
        plot->commit();
    }
    return StopSignals::received() ? signalExitStatus(StopSignals::received()) : 0;
}

}  // namespace carom::app
