// The results of a `carom bench` run and their forms: a table on stdout,
// JSON, CSV and an SVG plot of throughput against N.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <carom/types.h>

#include "app/bench/measure.h"
#include "app/bench/methods.h"

namespace carom::bench {

struct Row {
    Variant variant;
    std::uint32_t particles = 0;
    double cellsPerParticle = 0;  // of the grid the scene gets under the scheme (cellsPerParticle)
    Timing timing;
    std::map<std::string, double> profile;  // with --profile: seconds per step by part (profileMethod)
};

// A method under a scheme left out of the larger N, because its step at
// `particles` took longer than the budget.
struct Dropped {
    Variant variant;
    std::uint32_t particles = 0;
    double secondsPerStep = 0;
};

struct Report {
    std::string date;  // UTC, ISO 8601
    std::string host;  // CPU model
    int hostThreads = 1;
    int processes = 1;     // under mpirun: each world split among them (each row's time is the slowest's)
    double hostLoad = -1;  // 1-minute load average at the start (Linux), -1 if unknown: others' work skews CPU timings
    std::optional<DeviceDescription> device;
    SceneDef scene;  // particles varies; the rest is the scene of every row
    float dt = 0;
    TimingPlan plan;
    Bandwidth bandwidth;
    std::vector<Row> rows;
    std::vector<Dropped> dropped;
};

// "cpu" for the simultaneous scheme, "cpu pairwise" for the pairwise one;
// "events" for the events method (it runs that scheme only).
std::string variantLabel(const Variant& variant);

double particleStepsPerSecond(const Row& row);
// Time per step of `method` under the row's scheme over this row's at the
// same N, when measured.
std::optional<double> speedupOver(const Report& report, const Row& row, const std::string& method);
// For a pairwise row: its time per step over the same method's under the
// simultaneous scheme at the same N, when measured.
std::optional<double> pairwiseOverSimultaneous(const Report& report, const Row& row);
// The naive method on the same hardware as the row's method.
std::string naiveCounterpart(const Method& method);
double floorSecondsPerStep(const Report& report, const Row& row);

void printTable(std::ostream& out, const Report& report);
void writeJson(std::ostream& out, const Report& report);
void writeCsv(std::ostream& out, const Report& report);
void writeSvgPlot(std::ostream& out, const Report& report);

}  // namespace carom::bench
