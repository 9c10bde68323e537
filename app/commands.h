// The carom subcommands.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/scene_options.h"

namespace carom::app {

struct RunOptions {
    SceneOptions scene;
    std::uint64_t steps = 1000;  // steps to take (a scene file's `steps` unless given)
    std::string outputState;     // final state CSV; empty = none
    bool json = false;
    std::string trajectory;     // extended XYZ frames every `every` steps; empty = none
    std::string stats;          // CSV statistics every `every` steps; empty = none
    std::string checkpoint;     // checkpoint every `every` steps and at the end; empty = none
    std::uint64_t every = 100;  // steps between samples and checkpoints, >= 1
    std::string resume;         // continue from this checkpoint instead of a scene
    bool quiet = false;         // no progress line on stderr
    // Under mpirun: domains across and up, one per process; 0 0 = chosen from the box.
    std::vector<int> domains{0, 0};
};

void addRunOptions(CLI::App& command, RunOptions& options);

// `carom run`: simulate, writing trajectory, statistics and checkpoints as
// asked, then print a summary (or JSON) and write the state. Ctrl-C, SIGTERM
// or SIGHUP stops at the next step and still writes every output (exit status
// 128 + the signal); an output that fails stops the run and keeps the others.
int runCommand(const RunOptions& options);

// `carom devices`: list the OpenCL platforms and devices with their index.
int devicesCommand();

struct BenchOptions {
    std::vector<std::string> methods;     // empty = every method this build has
    std::vector<std::string> collisions;  // scheme names; empty = all (each method under those it runs)
    std::vector<std::string> sizes;       // N as written ("1e6"); empty = the default sweep
    float packing = 0.5f;
    float radius = 1.0f;
    float speed = 1.0f;
    float dt = 0.01f;
    std::uint64_t seed = 1;
    std::string device;  // OpenCL device selector
    int samples = 0;     // 0 = the default (7, or 3 with --quick)
    double budgetMs = 1000;
    std::string json, csv, plot;  // output files; empty = none
    bool profile = false;         // also where a step's time goes (per kernel for the OpenCL methods)
    bool quick = false;
    bool list = false;
};

void addBenchOptions(CLI::App& command, BenchOptions& options);

// `carom bench`: time each method over a sweep of N and report the results
// against the measured memory bandwidth.
int benchCommand(const BenchOptions& options);

struct ValidateOptions {
    bool quick = false;                        // the reduced suite for CI
    std::string report = "validation-report";  // folder for README.md and the SVG plots
    std::string json;                          // every check and measurement as JSON; empty = none
    std::string backend = "cpu";               // runs the equation of state, convergence, relaxation and exact cases
    std::string device;                        // OpenCL device selector (also for the conservation runs)
    std::string pipeline = "auto";
    std::uint64_t seed = 1;
    float dt = 0.0f;              // the step; addValidateOptions sets the suite's default (app/validate/checks.h)
    std::uint32_t particles = 0;  // N of the equation-of-state runs; 0 = the suite's default
};

void addValidateOptions(CLI::App& command, ValidateOptions& options);

// `carom validate`: the physics validation suite against the published
// hard-disk results; writes the report and exits 1 if any check fails.
int validateCommand(const ValidateOptions& options);

// Registers `carom view` and returns what runs it once parsed: the viewer,
// or a clear refusal in a build without SDL2/OpenGL/ImGui.
std::function<int()> addViewCommand(CLI::App& app);

}  // namespace carom::app
