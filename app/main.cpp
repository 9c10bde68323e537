// carom: the command line. Parsing lives here; each subcommand is in its own file.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>

#include <CLI/CLI.hpp>
#include <carom/carom.h>

#include "app/commands.h"
#include "app/processes.h"

namespace {

int runCarom(int argc, char** argv) {
    using namespace carom::app;
    CLI::App app{"carom: 2D elastic disk collisions on OpenCL and CPU backends"};
    app.require_subcommand(1, 1);
    app.set_version_flag("--version", std::string("carom ") + carom::version());

    RunOptions runOptions;
    CLI::App* run = app.add_subcommand("run", "Simulate a scene headless and print a summary");
    addRunOptions(*run, runOptions);
    CLI::App* devices = app.add_subcommand("devices", "List OpenCL platforms and devices with their index");
    const std::function<int()> runView = addViewCommand(app);
    BenchOptions benchOptions;
    CLI::App* bench = app.add_subcommand("bench", "Compare the speed of the methods over a sweep of N");
    addBenchOptions(*bench, benchOptions);
    ValidateOptions validateOptions;
    CLI::App* validate =
        app.add_subcommand("validate", "Check the physics against published hard-disk results and write a report");
    addValidateOptions(*validate, validateOptions);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        if (*run) return runCommand(runOptions);
        if (*devices) return devicesCommand();
        if (*bench) return benchCommand(benchOptions);
        if (*validate) return validateCommand(validateOptions);
        if (app.got_subcommand("view")) return runView();
    } catch (const carom::Error& e) {
        return reportError(e.what());
    } catch (const std::bad_alloc&) {
        return reportError("out of memory; try fewer particles");
    } catch (const std::exception& e) {  // a library's own error: still a message, never an abort
        return reportError(e.what());
    }
    return 1;
}

// What was printed on stdout (a summary, JSON, a list) reached it: a full
// disk or a closed pipe behind `> file` is an error, not a silent exit 0.
int checkStandardOutput(int status) {
    errno = 0;
    std::cout.flush();
    std::fflush(stdout);
    const int error = errno;  // of the write that failed, if it came in these flushes
    if (!std::ferror(stdout) && std::cout.good()) return status;
#ifdef SIGPIPE
    // The reader went away (`carom ... | head`): end quietly, with the status
    // SIGPIPE itself would have given.
    if (error == EPIPE) return status != 0 ? status : 128 + SIGPIPE;
#endif
    std::cerr << "carom: error: writing to standard output failed"
              << (error != 0 ? std::string(": ") + std::strerror(error) : std::string())
              << "; what was printed there is incomplete\n";
    return status != 0 ? status : 1;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef SIGXFSZ
    // Past a file size limit (ulimit -f) a write fails (EFBIG) and is
    // reported, keeping the other outputs, instead of killing carom.
    std::signal(SIGXFSZ, SIG_IGN);
#endif
#ifdef SIGPIPE
    // Likewise a FIFO output whose reader went away (EPIPE).
    std::signal(SIGPIPE, SIG_IGN);
#endif
    carom::app::Processes processes(argc, argv);
    return checkStandardOutput(runCarom(argc, argv));
}
