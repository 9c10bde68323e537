#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <tuple>
#include <utility>

#ifdef _WIN32
#include <io.h>
#else
#include <unistd.h>
#endif

#include <carom/carom.h>
#include <carom/files.h>
#include <carom/io.h>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/number_options.h"
#include "app/output_plan.h"
#include "app/processes.h"
#include "app/stop_signals.h"

namespace carom::app {

void addRunOptions(CLI::App& command, RunOptions& o) {
    addSceneOptions(command, o.scene);
    tracked(command.add_option("--steps", o.steps, "Number of steps (default: the scene file's, else 1000)")
                ->transform(wholeNumber(0)),
            o.scene.given);
    fileOption(command.add_option("--output-state", o.outputState, "Write the final state to this CSV"));
    command.add_flag("--json", o.json, "Print a JSON summary on stdout instead of the text summary");
    fileOption(
        command.add_option("--trajectory", o.trajectory, "Write extended XYZ frames (OVITO, ASE) every --every steps"));
    fileOption(command.add_option("--stats", o.stats, "Write a CSV row of statistics every --every steps"));
    fileOption(
        command.add_option("--checkpoint", o.checkpoint, "Write a checkpoint every --every steps and at the end"));
    tracked(command.add_option("--every", o.every, "Steps between trajectory frames, statistics and checkpoints")
                ->transform(wholeNumber(1))
                ->capture_default_str(),
            o.scene.given);
    auto* resume = fileOption(
        command.add_option("--resume", o.resume, "Continue from this checkpoint for --steps more steps, bit for bit"));
    for (const char* scene :
         {"--scene", "--input-state", "--particles", "--packing", "--box", "--radius", "--radius-min", "--radius-max",
          "--mass", "--mass-min", "--mass-max", "--speed", "--seed", "--dt", "--gravity", "--boundary", "--collisions"})
        resume->excludes(command.get_option(scene));
    command.add_flag("--quiet", o.quiet, "No progress line on stderr");
    command
        .add_option("--domains", o.domains,
                    "Under mpirun: split the box into NX x NY domains, one per process (default: as square as the "
                    "process count allows)")
        ->expected(2)
        ->type_name("NX NY")
        ->check(CLI::NonNegativeNumber);
}

namespace {

// ---------------------------------------------------------------------------
// What the run starts from: a scene (options or file) or a checkpoint.

struct Start {
    WorldDef world;                                // the run's world, with its --max-travel
    Setup setup;                                   // a new scene: its disks
    std::optional<io::CheckpointFile> checkpoint;  // a resumed run: the checkpoint
    bool resumed = false;                          // from a checkpoint, whose step the previous run sampled
    std::uint64_t step = 0;                        // steps the scene has taken before this run
    std::uint64_t steps = 0;                       // steps this run takes
    OutputDef outputs;
    OutputPlan plan;            // the files the run reads and writes, under the options (or scene keys) that name them
    std::string backendReason;  // why the world runs on its engine (engineChoiceOf)
};

// A command-line path wins over the scene file's.
void chooseOutputs(const RunOptions& o, Start& start) {
    const std::tuple<const char*, const char*, std::string*, const std::string*> outputs[] = {
        {"--trajectory", "output.trajectory", &start.outputs.trajectory, &o.trajectory},
        {"--stats", "output.stats", &start.outputs.stats, &o.stats},
        {"--checkpoint", "output.checkpoint", &start.outputs.checkpoint, &o.checkpoint},
        {"--output-state", "output.state", &start.outputs.state, &o.outputState}};
    for (const auto& [option, sceneKey, path, given] : outputs) {
        if (!given->empty()) *path = *given;
        if (!path->empty()) start.plan.output(given->empty() ? sceneKey : option, *path);
    }
}

Start planRun(const RunOptions& o) {
    const bool stepsGiven = o.scene.given.count("--steps") > 0;
    Start start;
    start.steps = o.steps;
    if (!o.resume.empty()) {
        start.checkpoint = io::readCheckpoint(o.resume);
        start.resumed = true;
        start.world = start.checkpoint->world();
        start.step = start.checkpoint->step();
        start.world.maxTravel = o.scene.world.maxTravel;  // run options, not part of the checkpoint
        start.world.skin = o.scene.world.skin;
        refuseSubstepsWithEvents(start.world, maxTravelOption(start.world.maxTravel));
    } else {
        start.setup = makeSetup(o.scene);
        start.world = start.setup.world;
        if (start.setup.sceneFile) {
            start.outputs = start.setup.sceneFile->output;
            if (!stepsGiven) start.steps = start.setup.sceneFile->steps;
        }
    }
    if (start.steps > std::numeric_limits<std::uint64_t>::max() - start.step)
        throw Error("--steps " + std::to_string(start.steps) + " would take the step count past 2^64");
    chooseOutputs(o, start);
    for (const auto& [option, path] : {std::pair{"--resume", o.resume}, std::pair{"--input-state", o.scene.inputState},
                                       std::pair{"--scene", o.scene.sceneFile}})
        if (!path.empty()) start.plan.input(option, path);
    // Read whole before it is replaced whole.
    start.plan.allowReplacing("--resume", "--checkpoint");
    if (o.scene.given.count("--every") || o.scene.sceneFile.empty()) start.outputs.every = o.every;
    return start;
}

// The world the run steps, on the engine the options ask for: the
// checkpoint's, continuing bit for bit, or the new scene's.
World startWorld(Start& start, const RunOptions& o) {
    WorldDef def = start.world;
    def.decomposition = runDecomposition(o.domains[0], o.domains[1]);
    EngineChoice choice;  // every process learns of one that cannot (its node lacks the device)
    everyProcess(def.decomposition.get(), [&] { choice = engineChoiceOf(start.world, o.scene); });
    if (def.decomposition && o.scene.backend.kind == "auto" && choice.engine.engine != ComputeEngine::Cpu)
        choice = {EngineDef{}, "--backend auto: the processes of mpirun step their domains on the CPU"};
    start.backendReason = choice.reason;
    def = onEngine(def, choice.engine);
    if (start.checkpoint) {
        World world = io::loadCheckpoint(std::move(*start.checkpoint), def);
        start.checkpoint.reset();  // spent
        return world;
    }
    World world(def);
    world.setDisks(start.setup.disks, start.setup.source);
    std::vector<Disk>().swap(start.setup.disks);  // the world has them: no second copy for the whole run
    return world;
}

// ---------------------------------------------------------------------------
// The output files. Trajectory and statistics stream into temporary files
// renamed into place at the end; the checkpoint is replaced whole each time.

// `text` as one word for a POSIX shell: quoted when it holds anything but
// letters, digits and _./-+=:,@%.
std::string shellWord(const std::string& text) {
    const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) ||
               std::string_view("_./-+=:,@%").find(c) != std::string_view::npos;
    });
    if (plain) return text;
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

class Outputs {
public:
    // Opens the trajectory and statistics (check() has passed). A resumed
    // run appends to them (see io::TrajectoryWriter), so that they continue
    // the previous run's.
    Outputs(const Start& start, const World& world)
        : def_(start.outputs), resumed_(start.resumed), maxTravel_(start.world.maxTravel) {
        if (!def_.trajectory.empty())
            trajectory_ = resumed_ ? io::TrajectoryWriter(def_.trajectory, world, def_.every, "the checkpoint")
                                   : io::TrajectoryWriter(def_.trajectory);
        if (!def_.stats.empty())
            stats_ = resumed_ ? io::StatisticsWriter(def_.stats, world, def_.every, "the checkpoint")
                              : io::StatisticsWriter(def_.stats);
    }

    // Writes the checkpoint, a frame and a row at `step`. An output whose
    // write fails is dropped (its previous file, if any, stays) and the
    // others go on: the run stops after this sample (failed()) and keeps them.
    // The checkpoint goes first, and a sample whose checkpoint failed adds no
    // frame or row: the trajectory and statistics never run past the step the
    // checkpoint holds, so the run resumed from it can append to them.
    void sample(const World& world) {
        checkpoint(world);
        if (!failures_[kCheckpoint].empty()) return;
        attempt(kTrajectory, [&] {
            trajectory_->write(world);
            trajectoryStep_ = world.stepCount();
        });
        attempt(kStats, [&] {
            stats_->write(world);
            statsStep_ = world.stepCount();
        });
    }

    // Only finite states reach the outputs: World::step stops at a step that
    // leaves a disk non-finite, before it is read.
    void checkpoint(const World& world) {
        if (checkpointStep_ == world.stepCount()) return;
        attempt(kCheckpoint, [&] {
            io::saveCheckpoint(def_.checkpoint, world);
            checkpointStep_ = world.stepCount();
        });
    }

    // Renames the trajectory and statistics into place: every frame and row
    // in them is complete. One that took no sample in this run (its
    // checkpoint failed at the first) is dropped: the file under its name,
    // if any, stays as it was, never replaced by an empty one.
    void commitStreams() {
        if (trajectory_ && trajectory_->frames() == 0) {
            trajectory_.reset();
            unsampled_[kTrajectory] = true;
        }
        if (stats_ && stats_->rows() == 0) {
            stats_.reset();
            unsampled_[kStats] = true;
        }
        attempt(kTrajectory, [&] { trajectory_->close(); });
        attempt(kStats, [&] { stats_->close(); });
    }

    // Every output at `step`, each attempted whatever happened to the others.
    void finish(const World& world) {
        checkpoint(world);
        commitStreams();
        attempt(kState, [&] {
            io::writeState(def_.state, world);
            stateStep_ = world.stepCount();
        });
    }

    std::uint64_t every() const { return def_.every; }
    bool failed() const {
        return std::any_of(std::begin(failures_), std::end(failures_), [](const std::string& f) { return !f.empty(); });
    }

    // "run.xyz (21 frames), run.csv (21 rows), run.ckpt (step 2000)": the
    // files written while stepping; `withState` adds the final state's.
    std::string written(bool withState = true) const {
        std::string list;
        auto add = [&list](const std::string& item) { list += (list.empty() ? "" : ", ") + item; };
        if (trajectory_) add(def_.trajectory + " (" + std::to_string(trajectory_->frames()) + " frames)");
        if (stats_) add(def_.stats + " (" + std::to_string(stats_->rows()) + " rows)");
        if (checkpointStep_) add(def_.checkpoint + " (step " + std::to_string(*checkpointStep_) + ")");
        if (withState && !def_.state.empty()) add(def_.state);
        return list;
    }

    // A line per output that holds something: what it holds, and at
    // which step. The trajectory and statistics hold the samples (multiples
    // of --every; a resumed run counts those it appended); the checkpoint
    // and state, the step the run reached.
    std::string holdings() const {
        std::string lines;
        auto samples = [this](std::size_t count, const char* unit, const std::optional<std::uint64_t>& last) {
            return std::to_string(count) + " " + unit + (count == 1 ? "" : "s") + (resumed_ ? " from this run" : "") +
                   (last ? ", the last at step " + std::to_string(*last) : std::string());
        };
        if (trajectory_) lines += line(kTrajectory, samples(trajectory_->frames(), "frame", trajectoryStep_));
        if (stats_) lines += line(kStats, samples(stats_->rows(), "row", statsStep_));
        if (checkpointStep_) lines += line(kCheckpoint, "step " + std::to_string(*checkpointStep_));
        if (stateStep_) lines += line(kState, "step " + std::to_string(*stateStep_));
        for (Output output : {kTrajectory, kStats})
            if (unsampled_[output]) lines += line(output, "nothing from this run; the file, if any, is as it was");
        return lines;
    }

    // A line per output whose write failed, with the reason.
    std::string failures() const {
        std::string lines;
        for (int output = 0; output < kOutputCount; ++output)
            if (!failures_[output].empty()) lines += line(Output(output), "FAILED: " + failures_[output]);
        return lines;
    }

    // How to continue from the checkpoint to `last`, checkpointing as before,
    // with the same substeps (--max-travel is not in the checkpoint), and
    // appending to the trajectory and statistics that were kept; empty
    // without a checkpoint.
    std::string resumeCommand(std::uint64_t last) const {
        if (!checkpointStep_) return {};
        const std::string checkpoint = shellWord(def_.checkpoint);
        std::string command = "carom run --resume " + checkpoint + " --steps " +
                              std::to_string(last - *checkpointStep_) + " --checkpoint " + checkpoint;
        if (!def_.trajectory.empty() && failures_[kTrajectory].empty())
            command += " --trajectory " + shellWord(def_.trajectory);
        if (!def_.stats.empty() && failures_[kStats].empty()) command += " --stats " + shellWord(def_.stats);
        if (maxTravel_ > 0.0f) command += " " + maxTravelOption(maxTravel_);
        return command + " --every " + std::to_string(def_.every);
    }

    const std::string& statePath() const { return def_.state; }

private:
    enum Output { kTrajectory, kStats, kCheckpoint, kState, kOutputCount };

    const std::string& path(Output output) const {
        const std::string* paths[] = {&def_.trajectory, &def_.stats, &def_.checkpoint, &def_.state};
        return *paths[output];
    }

    std::string line(Output output, const std::string& text) const {
        static const char* const names[] = {"trajectory", "statistics", "checkpoint", "final state"};
        return "\n  " + std::string(names[output]) + " " + path(output) + ": " + text;
    }

    // Runs `write` for an output that is asked for and has not failed; a
    // failure is recorded and drops the output, whose temporary file goes.
    template <class Write>
    void attempt(Output output, Write write) {
        if (path(output).empty() || !failures_[output].empty() || unsampled_[output]) return;
        try {
            write();
        } catch (const Error& e) {
            failures_[output] = e.what();
            if (output == kTrajectory) trajectory_.reset();
            if (output == kStats) stats_.reset();
        }
    }

    OutputDef def_;
    bool resumed_;     // from a checkpoint: the trajectory and statistics are appended to
    float maxTravel_;  // the run's --max-travel, which a resumed run must be given again
    std::optional<io::TrajectoryWriter> trajectory_;
    std::optional<io::StatisticsWriter> stats_;
    std::optional<std::uint64_t> trajectoryStep_, statsStep_;  // of the last frame and row written
    std::optional<std::uint64_t> checkpointStep_;
    std::optional<std::uint64_t> stateStep_;
    std::string failures_[kOutputCount];  // why each output failed; empty while it has not
    bool unsampled_[kOutputCount] = {};   // dropped at the end for want of a sample
};

// ---------------------------------------------------------------------------
// Progress: one line on stderr, rewritten in place, for runs longer than a
// couple of seconds, and only when stderr is a terminal.

bool stderrIsTerminal() {
#ifdef _WIN32
    return _isatty(_fileno(stderr)) != 0;
#else
    return isatty(fileno(stderr)) != 0;
#endif
}

class Progress {
public:
    using Clock = std::chrono::steady_clock;

    Progress(bool enabled, std::uint64_t first, std::uint64_t last)
        : enabled_(enabled), first_(first), last_(last), start_(Clock::now()), shownAt_(start_) {}

    void update(std::uint64_t step) {
        if (!enabled_) return;
        const Clock::time_point now = Clock::now();
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        if (elapsed < kDelaySeconds || std::chrono::duration<double>(now - shownAt_).count() < kPeriodSeconds) return;
        shownAt_ = now;
        const double rate = double(step - first_) / elapsed;
        const double eta = rate > 0 ? double(last_ - step) / rate : 0.0;
        const int length =
            std::fprintf(stderr, "\rcarom: step %llu of %llu (%.0f%%), %.3g steps/s, ETA %s   ",
                         static_cast<unsigned long long>(step), static_cast<unsigned long long>(last_),
                         100.0 * double(step - first_) / double(std::max<std::uint64_t>(last_ - first_, 1)), rate,
                         duration(eta).c_str());
        std::fflush(stderr);
        shownLength_ = std::max(shownLength_, length);
    }

    // Clears the line, so the summary starts on a clean one.
    void finish() {
        if (shownLength_ > 0) std::fprintf(stderr, "\r%*s\r", shownLength_, "");
    }

private:
    static constexpr double kDelaySeconds = 2.0;
    static constexpr double kPeriodSeconds = 0.25;

    static std::string duration(double seconds) {
        const auto s = static_cast<unsigned long long>(std::min(seconds, 359999.0));
        char text[32];
        std::snprintf(text, sizeof text, "%llu:%02llu:%02llu", s / 3600, s / 60 % 60, s % 60);
        return text;
    }

    bool enabled_;
    std::uint64_t first_, last_;
    Clock::time_point start_, shownAt_;
    int shownLength_ = 0;  // of the longest line printed, 0 before the first
};

// Steps per backend call: doubled while a call takes under 50 ms, halved
// above 200 ms, so Ctrl-C and the progress line respond quickly without a
// call per step. Results do not depend on it: n steps are n steps.
class Chunk {
public:
    std::uint64_t size() const { return size_; }
    void adapt(double seconds) {
        if (seconds < 0.05 && size_ < (std::uint64_t{1} << 20)) size_ *= 2;
        if (seconds > 0.2 && size_ > 1) size_ /= 2;
    }

private:
    std::uint64_t size_ = 1;
};

// ---------------------------------------------------------------------------
// The summary.

nlohmann::json pair(double x, double y) { return nlohmann::json::array({x, y}); }

// A run whose energy changes by more than this fraction gets a warning.
constexpr double kEnergyWarningChange = 0.01;

// The relative change from `initial` to `final`; 0 when it started at 0.
double changeFrom(double initial, double final) {
    return initial != 0.0 ? (final - initial) / std::fabs(initial) : 0.0;
}

// The events scheme's own account of a run: what happened, and the total
// energy of its double state, whose change the float32 samples show only to
// their rounding.
struct EventsResult {
    EventCounts counts;
    double initialEnergy = 0.0, finalEnergy = 0.0;  // World::totalEnergy
    double relativeChange() const { return changeFrom(initialEnergy, finalEnergy); }
};

// The energies and momentum of the float disks.
struct Motion {
    double kineticEnergy = 0.0, potentialEnergy = 0.0;
    std::array<double, 2> momentum{};
    double totalEnergy() const { return kineticEnergy + potentialEnergy; }
};

Motion motionOf(const World& world) { return {world.kineticEnergy(), world.potentialEnergy(), world.momentum()}; }

struct Result {
    std::uint64_t firstStep = 0, lastStep = 0;
    double seconds = 0.0;
    Motion initial, final;
    double maxOverlap = 0.0;  // at the end
    std::size_t escaped = 0;  // at the end
    Measurements run;         // over this run: collisions, pressure, Z and rates at the mean of the first and last kT
    double initialTemperature = 0.0, finalTemperature = 0.0;
    bool interrupted = false;
    std::optional<EventsResult> events;         // with the events scheme
    std::string backendReason;                  // Start::backendReason
    std::vector<DecompositionCosts> processes;  // under mpirun, on process 0: each process's
};

// The command line's name of the world's backend.
const char* backendName(const World& world) { return world.def().engine == ComputeEngine::Cpu ? "cpu" : "opencl"; }

bool hasGravity(const WorldDef& w) { return w.gravity.x != 0.0f || w.gravity.y != 0.0f; }

// The relative change of the total energy (kinetic without gravity) over the
// run.
double energyChange(const Result& r) { return changeFrom(r.initial.totalEnergy(), r.final.totalEnergy()); }

// A periodic box has no floor: gravity accelerates the centre of mass
// forever, and -sum m g.x jumps by m g H whenever a disk wraps. What the
// collisions conserve there is the kinetic energy in the centre of mass's
// (freely falling) frame, (N - 1) kT.
bool fallsFreely(const WorldDef& w) { return w.boundary == Boundary::Periodic && hasGravity(w); }

// Under mpirun: where the slowest process spent its time in the
// decomposition's parts, and what all the processes sent a step.
void printProcesses(const std::vector<DecompositionCosts>& processes, std::uint64_t steps) {
    const auto total = [](const DecompositionCosts& c) {
        return c.computeSeconds + c.exchangeSeconds + c.migrationSeconds + c.agreementSeconds + c.gatherSeconds;
    };
    const DecompositionCosts& slowest = *std::max_element(
        processes.begin(), processes.end(), [&](const auto& a, const auto& b) { return total(a) < total(b); });
    const double seconds = std::max(total(slowest), 1e-300);
    std::uint64_t bytes = 0, messages = 0;
    for (const DecompositionCosts& c : processes) {
        bytes += c.bytes;
        messages += c.messages;
    }
    const double perStep = steps > 0 ? 1.0 / double(steps) : 0.0;
    std::printf(
        "  processes    %zu; the slowest spent %.3g s: compute %.0f %%, halo %.0f %%, handing on %.0f %%, "
        "agreeing %.0f %%, gathering %.0f %%; a step sends %.3g MB in %.3g messages\n",
        processes.size(), total(slowest), 100 * slowest.computeSeconds / seconds,
        100 * slowest.exchangeSeconds / seconds, 100 * slowest.migrationSeconds / seconds,
        100 * slowest.agreementSeconds / seconds, 100 * slowest.gatherSeconds / seconds, double(bytes) * perStep * 1e-6,
        double(messages) * perStep);
}

nlohmann::json processesJson(const std::vector<DecompositionCosts>& processes) {
    nlohmann::json all = nlohmann::json::array();
    for (const DecompositionCosts& c : processes)
        all.push_back({{"substeps", c.substeps},
                       {"retaken_substeps", c.retakenSubsteps},
                       {"halo_copies", c.haloCopies},
                       {"migrants", c.migrants},
                       {"messages", c.messages},
                       {"bytes", c.bytes},
                       {"seconds",
                        {{"compute", c.computeSeconds},
                         {"exchange", c.exchangeSeconds},
                         {"migration", c.migrationSeconds},
                         {"agreement", c.agreementSeconds},
                         {"gather", c.gatherSeconds}}}});
    return all;
}

void printSummary(const World& world, const Result& r, const std::string& resumedFrom, const Outputs& outputs) {
    const WorldDef& w = world.def();
    const std::uint64_t steps = r.lastStep - r.firstStep;
    std::printf("carom run: %zu disks, %llu steps of dt %g in a %g x %g box, %s\n", world.diskCount(),
                static_cast<unsigned long long>(steps), w.dt, w.width, w.height, boundaryName(w.boundary));
    if (w.maxTravel > 0)
        std::printf("  substeps     %llu (at most %g x the smallest radius per substep)\n",
                    static_cast<unsigned long long>(r.run.substeps), w.maxTravel);
    if (!resumedFrom.empty())
        std::printf("  resumed      from %s at step %llu, now at step %llu\n", resumedFrom.c_str(),
                    static_cast<unsigned long long>(r.firstStep), static_cast<unsigned long long>(r.lastStep));
    std::printf("  backend      %s on %s (%s)\n", backendName(world), world.deviceName().c_str(),
                r.backendReason.c_str());
    if (w.collisions == CollisionScheme::Pairwise)
        std::printf("  scheme       pairwise (at most %u collision rounds per substep, %llu late contacts)\n",
                    r.run.maxRounds, static_cast<unsigned long long>(r.run.lateContacts));
    else if (r.events)
        std::printf(
            "  scheme       events (%llu collisions, %llu wall bounces, %llu cell crossings; %llu stale and "
            "%llu overlapping events)\n",
            static_cast<unsigned long long>(r.events->counts.collisions),
            static_cast<unsigned long long>(r.events->counts.wallBounces),
            static_cast<unsigned long long>(r.events->counts.cellCrossings),
            static_cast<unsigned long long>(r.events->counts.stale),
            static_cast<unsigned long long>(r.events->counts.overlapping));
    else
        std::printf("  scheme       %s\n", collisionSchemeName(w.collisions));
    std::printf("  wall time    %.3f s, %.3g particle-steps/s\n", r.seconds,
                r.seconds > 0 ? double(world.diskCount()) * steps / r.seconds : 0.0);
    if (!r.processes.empty()) printProcesses(r.processes, steps);
    if (hasGravity(w))
        std::printf(
            "  energy       total %.9g -> %.9g (relative change %+.2e)\n"
            "               kinetic %.9g -> %.9g, potential %.9g -> %.9g\n",
            r.initial.totalEnergy(), r.final.totalEnergy(), energyChange(r), r.initial.kineticEnergy,
            r.final.kineticEnergy, r.initial.potentialEnergy, r.final.potentialEnergy);
    else
        std::printf("  energy       %.9g -> %.9g (relative change %+.2e)\n", r.initial.kineticEnergy,
                    r.final.kineticEnergy, energyChange(r));
    if (fallsFreely(w))
        std::printf(
            "               in the centre-of-mass frame (conserved: the box is periodic) %.9g -> %.9g "
            "(relative change %+.2e)\n",
            r.initialTemperature * (double(world.diskCount()) - 1),
            r.finalTemperature * (double(world.diskCount()) - 1), changeFrom(r.initialTemperature, r.finalTemperature));
    if (r.events)
        std::printf("               %s in double, the engine's state: %.17g -> %.17g (relative change %+.2e)\n",
                    hasGravity(w) ? "total" : "kinetic", r.events->initialEnergy, r.events->finalEnergy,
                    r.events->relativeChange());
    std::printf("  momentum     (%.6g, %.6g) -> (%.6g, %.6g)\n", r.initial.momentum[0], r.initial.momentum[1],
                r.final.momentum[0], r.final.momentum[1]);
    std::printf("  collisions   %llu, max overlap %.3g, escaped %zu\n",
                static_cast<unsigned long long>(r.run.collisions), r.maxOverlap, r.escaped);
    std::printf("  temperature  kT %.6g, %.4g collisions per disk per unit time\n", r.finalTemperature,
                r.run.collisionRate);
    if (w.boundary == Boundary::Periodic)
        std::printf("  pressure     %.6g (collision virial), Z = PA/NkT = %.5g\n", r.run.pressure,
                    r.run.compressibility);
    else
        std::printf("  pressure     %.6g on the walls (left %.4g, right %.4g, bottom %.4g, top %.4g), Z = %.5g\n",
                    r.run.pressure, r.run.wallPressure[0], r.run.wallPressure[1], r.run.wallPressure[2],
                    r.run.wallPressure[3], r.run.compressibility);
    const double n = double(world.diskCount());
    const DeviceMemoryUse device = world.deviceMemory();
    const std::uint64_t host = peakResidentBytes();
    if (device.peakBytes > 0)
        std::printf(
            "  memory       device %.3g GB at peak (%.0f bytes a disk), host %.3g GB at peak (%.0f bytes a disk)\n",
            double(device.peakBytes) * 1e-9, double(device.peakBytes) / n, double(host) * 1e-9, double(host) / n);
    else if (host > 0)
        std::printf("  memory       host %.3g GB at peak (%.0f bytes a disk)\n", double(host) * 1e-9, double(host) / n);
    const std::string written = outputs.written();
    if (!written.empty()) std::printf("  wrote        %s\n", written.c_str());
}

void printJson(const World& world, const Result& r) {
    const WorldDef& w = world.def();
    const std::uint64_t steps = r.lastStep - r.firstStep;
    const double n = double(world.diskCount());
    nlohmann::json summary = {
        {"backend", backendName(world)},
        {"backend_reason", r.backendReason},
        {"device", world.deviceName()},
        {"exact_arithmetic", world.bitwiseReproducible()},
        {"particles", world.diskCount()},
        {"steps", steps},
        {"step", r.lastStep},
        {"time", double(r.lastStep) * w.dt},
        {"interrupted", r.interrupted},
        {"dt", w.dt},
        {"max_travel", w.maxTravel},
        {"substeps", r.run.substeps},
        {"boundary", boundaryName(w.boundary)},
        {"scheme", collisionSchemeName(w.collisions)},
        {"late_contacts", r.run.lateContacts},
        {"max_rounds", r.run.maxRounds},
        {"box", pair(w.width, w.height)},
        {"gravity", pair(w.gravity.x, w.gravity.y)},
        {"wall_seconds", r.seconds},
        {"particle_steps_per_second", r.seconds > 0 ? n * steps / r.seconds : 0.0},
        {"kinetic_energy", {{"initial", r.initial.kineticEnergy}, {"final", r.final.kineticEnergy}}},
        {"energy",
         {{"kinetic", {{"initial", r.initial.kineticEnergy}, {"final", r.final.kineticEnergy}}},
          {"potential", {{"initial", r.initial.potentialEnergy}, {"final", r.final.potentialEnergy}}},
          {"total", {{"initial", r.initial.totalEnergy()}, {"final", r.final.totalEnergy()}}}}},
        {"momentum",
         {{"initial", pair(r.initial.momentum[0], r.initial.momentum[1])},
          {"final", pair(r.final.momentum[0], r.final.momentum[1])}}},
        {"collisions", r.run.collisions},
        {"max_overlap", r.maxOverlap},
        {"escaped", r.escaped},
        {"temperature", r.finalTemperature},
        {"collision_rate", r.run.collisionRate},
        {"memory", {{"device_bytes_peak", world.deviceMemory().peakBytes}, {"host_bytes_peak", peakResidentBytes()}}},
    };
    if (!r.processes.empty()) summary["processes"] = processesJson(r.processes);
    if (r.events) {
        const EventCounts& counts = r.events->counts;
        summary["events"] = {{"collisions", counts.collisions},
                             {"wall_bounces", counts.wallBounces},
                             {"cell_crossings", counts.cellCrossings},
                             {"stale", counts.stale},
                             {"overlapping", counts.overlapping}};
        // The float32 samples' energies above change by their rounding; the engine's double state by its own.
        summary["energy"]["exact_total"] = {{"initial", r.events->initialEnergy}, {"final", r.events->finalEnergy}};
        summary["energy"]["exact_relative_change"] = r.events->relativeChange();
    }
    if (w.boundary == Boundary::Periodic) {
        summary["pressure"] = {{"virial", r.run.pressure}, {"Z", r.run.compressibility}};
    } else {
        summary["wall_pressure"] = {{"mean", r.run.pressure},         {"left", r.run.wallPressure[0]},
                                    {"right", r.run.wallPressure[1]}, {"bottom", r.run.wallPressure[2]},
                                    {"top", r.run.wallPressure[3]},   {"Z", r.run.compressibility}};
    }
    std::cout << summary.dump(2) << '\n';
}

// Runs `steps` steps, naming the steps that failed in the error.
void advance(World& world, std::uint64_t from, std::uint64_t steps, Outputs& outputs) {
    try {
        world.step(steps);
    } catch (const Error& e) {
        outputs.commitStreams();  // keep the complete frames and rows written so far
        std::string message =
            "steps " + std::to_string(from + 1) + " to " + std::to_string(from + steps) + " failed: " + e.what();
        const std::string kept = outputs.written(false);
        if (!kept.empty()) message += "; kept what was written before: " + kept;
        if (!outputs.statePath().empty()) message += "; '" + outputs.statePath() + "' was not written";
        throw Error(message + outputs.failures());
    }
}

// Steps from the world's step to `last`, or until a stop signal or an
// output's failure, sampling on every multiple of the outputs' `every`;
// returns the step reached. A step that goes non-finite stops the world
// there (advance reports it).
std::uint64_t runSteps(World& world, bool resumed, std::uint64_t last, Outputs& outputs, Progress& progress) {
    const std::uint64_t every = outputs.every();
    Chunk chunk;
    std::uint64_t step = world.stepCount();
    if (!resumed) outputs.sample(world);  // a new scene records its start
    // Every process takes the same calls: process 0's chunks, and a stop
    // where any process has a reason. Processes step from sample to sample,
    // as each call ends with the whole world gathered on every one (World::step).
    while (step < last && !anyProcess(StopSignals::received() || outputs.failed())) {
        const std::uint64_t n =
            processZeros(std::min({last - step, every - step % every, processCount() > 1 ? every : chunk.size()}));
        const auto callStart = std::chrono::steady_clock::now();
        advance(world, step, n, outputs);
        chunk.adapt(std::chrono::duration<double>(std::chrono::steady_clock::now() - callStart).count());
        const std::uint64_t from = step;
        step = world.stepCount();  // short of from + n where a stop signal cut the call short
        if (step == from + n && step % every == 0) outputs.sample(world);
        progress.update(step);
    }
    progress.finish();
    return step;
}

// The simultaneous scheme does not conserve energy in dense gases (it
// heats them); the pairwise and events schemes do, so a change there is a
// bug (the events scheme's measured in double, on its exact state).
void warnAboutEnergy(const Result& r, const WorldDef& world) {
    const bool free = fallsFreely(world);
    const double change = free       ? changeFrom(r.initialTemperature, r.finalTemperature)
                          : r.events ? r.events->relativeChange()
                                     : energyChange(r);
    if (!(std::fabs(change) > kEnergyWarningChange)) return;
    std::fprintf(stderr, "carom: warning: the %s changed by %+.3g %% over this run",
                 free                ? "kinetic energy in the centre-of-mass frame"
                 : hasGravity(world) ? "total energy"
                                     : "kinetic energy",
                 100 * change);
    if (world.collisions == CollisionScheme::Simultaneous)
        std::fprintf(stderr,
                     ": the simultaneous collision scheme does not conserve it in dense or crowded "
                     "systems; use --collisions pairwise, or a smaller --dt\n");
    else
        std::fprintf(stderr,
                     ", although the %s scheme conserves it: this is a bug in carom; please report it "
                     "with the command line\n",
                     collisionSchemeName(world.collisions));
}

// What each output holds (the samples end at the last multiple of --every,
// the checkpoint and state at the step reached), and how to continue.
std::string outputsAndResume(const Outputs& outputs, std::uint64_t last) {
    std::string text = outputs.holdings();
    const std::string resume = outputs.resumeCommand(last);
    if (!resume.empty()) text += "\ncontinue with: " + resume;
    return text;
}

// Every output was attempted (finish); those that failed say why, the
// others what they hold.
Error outputFailure(const Outputs& outputs, std::uint64_t step, std::uint64_t last) {
    std::string message = "the run stopped at step " + std::to_string(step) + " of " + std::to_string(last) +
                          ": writing an output failed" + outputs.failures();
    if (!outputs.holdings().empty()) message += "\nkept what could be written:" + outputsAndResume(outputs, last);
    return Error(message);
}

void reportInterruption(const Outputs& outputs, int signal, std::uint64_t step, std::uint64_t last) {
    std::cerr << "carom: interrupted at step " << step << " of " << last << " by " << signalName(signal);
    if (!outputs.holdings().empty()) std::cerr << "; the outputs hold:" << outputsAndResume(outputs, last);
    std::cerr << '\n';
}

}  // namespace

int runCommand(const RunOptions& o) {
    // A signal while the files are read and checked, the world is made and
    // the outputs are opened ends the run at once, every file as it was;
    // from the first step on, it stops the run with every output written.
    StopSignals stopSignals(StopSignals::FirstSignal::Ends, "carom run");
    Start start = planRun(o);
    start.plan.check();
    if (processRank() != 0) {  // process 0 writes the files
        OutputDef none;
        none.every = start.outputs.every;
        start.outputs = none;
    }
    World world = startWorld(start, o);
    for (const std::string& warning : world.warnings()) std::cerr << "carom: warning: " << warning << '\n';
    Outputs outputs(start, world);
    stopSignals.setFirstSignal(StopSignals::FirstSignal::Stops);
    world.setStopCheck(&StopSignals::received);  // within a step too: one may take minutes

    Result r;
    r.backendReason = start.backendReason;
    r.firstStep = start.step;
    r.initial = motionOf(world);
    r.initialTemperature = world.temperature();
    const bool events = world.def().collisions == CollisionScheme::Events;
    if (events) r.events.emplace().initialEnergy = world.totalEnergy();
    const std::uint64_t last = start.step + start.steps;
    Progress progress(!o.quiet && !o.json && stderrIsTerminal(), start.step, last);
    const auto began = std::chrono::steady_clock::now();
    r.lastStep = runSteps(world, start.resumed, last, outputs, progress);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    const int signal = r.lastStep < last ? StopSignals::received() : 0;  // one after the last step stopped nothing
    r.interrupted = signal != 0;
    r.final = motionOf(world);
    r.maxOverlap = world.maxOverlap();
    r.escaped = world.escapedCount();
    r.finalTemperature = world.temperature();
    r.run = world.measurements();
    r.processes = processCosts(world.decompositionCosts());
    if (events) {
        r.events->counts = world.eventCounts();
        r.events->finalEnergy = world.totalEnergy();
    }
    outputs.finish(world);
    if (outputs.failed()) throw outputFailure(outputs, r.lastStep, last);

    if (r.escaped > 0)
        std::cerr << "carom: warning: " << r.escaped
                  << " particles left the box: the step is unstable at this dt (try a smaller --dt)\n";
    if (o.json) {
        printJson(world, r);
    } else {
        printSummary(world, r, o.resume, outputs);
    }
    warnAboutEnergy(r, world.def());
    if (!r.interrupted) return 0;
    reportInterruption(outputs, signal, r.lastStep, last);
    return signalExitStatus(signal);
}

}  // namespace carom::app
