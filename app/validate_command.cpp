// `carom validate`: runs the physics validation suite (app/validate/checks.h)
// and writes its report: Markdown with SVG plots, and JSON when asked.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <carom/carom.h>
#include <carom/files.h>

#include "app/commands.h"
#include "app/host_info.h"
#include "app/number_options.h"
#include "app/output_plan.h"
#include "app/scene_options.h"
#include "app/stop_signals.h"
#include "app/validate/checks.h"
#include "app/validate/report.h"

namespace carom::app {

namespace {

// The --backend kinds this build has: "cpu", and "opencl" where it has OpenCL.
// The command line that reproduces the run, every option spelled out.
std::string commandLine(const ValidateOptions& o) {
    std::ostringstream command;
    command << "carom validate" << (o.quick ? " --quick" : "") << " --backend " << o.backend;
    if (o.backend == "opencl") command << " --pipeline " << o.pipeline;
    if (!o.device.empty()) command << " --device '" << o.device << "'";
    command << " --seed " << o.seed << " --dt " << o.dt;
    if (o.particles) command << " --particles " << o.particles;
    command << " --report " << o.report;
    if (!o.json.empty()) command << " --json " << o.json;
    return command.str();
}

}  // namespace

void addValidateOptions(CLI::App& command, ValidateOptions& o) {
    o.dt = validation::kDefaultDt;
    command.add_flag("--quick", o.quick,
                     "The reduced suite for CI (under a minute on one core): fewer disks and shorter runs; where "
                     "they cannot resolve a target, the tolerance is three standard errors");
    fileOption(command.add_option("--report", o.report, "Folder for the report: README.md and its SVG plots"))
        ->capture_default_str();
    fileOption(command.add_option("--json", o.json, "Also write every check and measurement as JSON to this file"));
    command
        .add_option("--backend", o.backend,
                    "Backend of every run but the conservation checks, which run on all (pairwise scheme), "
                    "and the event-driven runs, which run on the CPU")
        ->check(CLI::IsMember(backendKinds()))
        ->capture_default_str();
    command.add_option("--device", o.device,
                       "OpenCL device: index from `carom devices` or part of its name (default: first GPU, else "
                       "first device); also used by the OpenCL conservation runs");
    addPipelineOption(command, o.pipeline,
                      "OpenCL pipeline of the heavy runs: host-grid, resident, or auto (resident on a GPU, "
                      "host-grid on other devices); the conservation checks run both");
    command.add_option("--seed", o.seed, "Random seed of the initial positions and velocities")
        ->transform(wholeNumber(0))
        ->capture_default_str();
    std::ostringstream dtHelp;
    dtHelp << "Time step of the equation-of-state, relaxation, conservation, dense-gas and gravity runs, in (0, "
           << validation::kMaxDt << "]";
    command.add_option("--dt", o.dt, dtHelp.str())->transform(realNumber())->capture_default_str();
    command
        .add_option("--particles", o.particles,
                    "Disks in each equation-of-state run of the stepped scheme (default " +
                        std::to_string(validation::kEosParticles(false)) + ", " +
                        std::to_string(validation::kEosParticles(true)) + " with --quick; the event-driven runs use " +
                        std::to_string(validation::kEventsParticles) + ")")
        ->transform(particleCount(validation::kMinEosParticles, validation::kMaxEosParticles));
}

int validateCommand(const ValidateOptions& o) {
    // The report is written at the end: a signal before then ends the
    // suite at once, with no file written (the checks so far are on stderr).
    StopSignals stopSignals(StopSignals::FirstSignal::Ends, "carom validate");
    validation::SuiteOptions suite;
    suite.quick = o.quick;
    if (o.backend == "cpu" && o.pipeline != "auto")
        throw Error("--pipeline " + o.pipeline + " needs --backend opencl; the CPU backend has one pipeline");
    suite.backend = engineOf(BackendOptions{o.backend, o.device, o.pipeline});
    suite.seed = o.seed;
    suite.dt = o.dt;
    suite.eosParticles = o.particles;
    validation::validate(suite);
    validation::describeBackend(suite.backend);  // refuses a bad --device or --pipeline at once

    // Refuse unwritable outputs before the runs, not after them.
    const std::vector<std::string>& reportNames = validation::reportFileNames();
    OutputPlan plan;
    if (!o.json.empty()) plan.output("--json", o.json);
    plan.outputFolder("--report", o.report, [&reportNames](const std::string& name) {
        return std::find(reportNames.begin(), reportNames.end(), name) != reportNames.end();
    });
    plan.check();
    std::optional<io::AtomicFile> json;
    if (!o.json.empty()) json.emplace(o.json);
    createFolder("--report", o.report);
    const std::filesystem::path folder(o.report);
    std::map<std::string, std::unique_ptr<io::AtomicFile>> reportOutputs;
    for (const std::string& name : reportNames)
        reportOutputs[name] = std::make_unique<io::AtomicFile>((folder / name).string());

    validation::RunContext context;
    context.date = utcNow();
    context.host = hostCpu();
    context.hostThreads = hostThreads();
    context.hostLoad = hostLoad();
    context.command = commandLine(o);
    std::cerr << "validate: " << (o.quick ? "quick" : "full") << " suite on " << o.backend << '\n';
    const validation::SuiteResult result = validation::runSuite(suite, std::cerr);

    stopSignals.setFirstSignal(StopSignals::FirstSignal::Stops);  // each file is written whole
    for (const auto& [name, contents] : validation::reportFiles(result, context)) {
        io::AtomicFile& file = *reportOutputs.at(name);
        file.append(contents);
        file.commit();
    }
    if (json) {
        json->append(validation::toJson(result, context).dump(2) + "\n");
        json->commit();
    }
    validation::printSummary(std::cout, result);
    std::cout << "report: " << (folder / "README.md").string() << (json ? ", " + o.json : std::string()) << '\n';
    if (const int signal = StopSignals::received()) return signalExitStatus(signal);
    return result.passed() ? 0 : 1;
}

}  // namespace carom::app
