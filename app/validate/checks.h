// The physics validation suite of `carom validate`: simulations compared
// with the published hard-disk results (shared/physics/hard-disks.md). Each
// part returns its measurements (for the report's tables and plots) and its
// checks, each with its tolerance and verdict.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "app/validate/statistics.h"
#include "engine/carom.h"

namespace carom::validation {

// The step the equation-of-state, relaxation and conservation runs take by
// default (disks of radius 1 at kT = 1: Z is then within about 0.5 % of the
// reference up to eta = 0.6), and the range --dt accepts.
constexpr float kDefaultDt = 0.0025f;
constexpr float kMaxDt = 0.05f;  // a disk of mean speed then moves 6 % of its radius per step, the fastest 25 %
// The range --particles accepts for the equation-of-state runs.
constexpr std::uint32_t kMinEosParticles = 256;
constexpr std::uint32_t kMaxEosParticles = 100'000'000;

struct SuiteOptions {
    bool quick = false;      // the reduced suite for CI
    BackendDef backend;      // runs the equation of state, convergence, relaxation and exact cases
    std::uint64_t seed = 1;  // initial positions and velocities
    float dt = kDefaultDt;   // the step of the equation-of-state, relaxation and conservation runs
    std::uint32_t eosParticles = 0;  // N of the equation-of-state runs; 0 = the suite's default
};

// Throws Error naming the value and the allowed range for a bad --dt or --particles.
void validate(const SuiteOptions& options);

// One comparison with its tolerance: passes when `deviation` <= `limit`, or
// for a lower bound when `deviation` > `limit` (a NaN deviation fails).
struct Check {
    std::string section;   // "equation of state", ...
    std::string name;      // what was checked, e.g. "Z at eta = 0.3"
    double measured = 0.0;
    double expected = 0.0;   // NaN when the check is a bound, not a comparison with a value
    double deviation = 0.0;  // the quantity held against the limit
    double limit = 0.0;
    bool lowerBound = false;
    std::string criterion;  // the test in words, e.g. "|Z - Z_ref| / Z_ref <= 1 %"
    bool passed = false;
};

// --- 1. Equation of state -------------------------------------------------

struct EosPoint {
    double packing = 0.0;
    std::uint32_t particles = 0;
    double equilibrationTime = 0.0;  // [time] before the first block
    double blockTime = 0.0;          // [time] per block
    MeanAndError z;            // from the block values of the collision virial
    double zReference = 0.0;   // the table of the reference
    double tolerance = 0.0;    // relative
    double collisionRate = 0.0;   // collisions per disk per unit time, each pair once
    double kT = 0.0;              // mean of the block temperatures
    double energyChangeRms = 0.0; // rms relative change of E_kin over a block
};

struct EosResult {
    double dt = 0.0;
    int blocks = 0;
    std::vector<EosPoint> points;
};

// --- 2. Convergence in dt ---------------------------------------------------

struct ConvergencePoint {
    double dt = 0.0;
    MeanAndError z;
    double zError = 0.0;      // |Z - Z_ref|
    // The rms relative change of E_kin over a block, divided by the block
    // time: the rate at which the energy wanders [1/time].
    double energyDriftRate = 0.0;
};

struct ConvergenceResult {
    double packing = 0.0;
    std::uint32_t particles = 0;
    double zReference = 0.0;
    double equilibrationTime = 0.0;
    double blockTime = 0.0;
    int blocks = 0;
    std::vector<ConvergencePoint> points;  // dt descending
    PowerLaw zErrorFit;    // |Z - Z_ref| against dt
    PowerLaw driftFit;     // energy drift rate against dt
};

// --- 3. Relaxation to Maxwell-Boltzmann -------------------------------------

struct RelaxationSample {
    double time = 0.0;
    double h = 0.0;   // plug-in histogram estimate of H
    double ks = 0.0;  // KS statistic of the speeds against Rayleigh at the state's kT
    double kT = 0.0;
};

struct RelaxationResult {
    double packing = 0.0;
    std::uint32_t particles = 0;
    double dt = 0.0;
    double halfWidth = 0.0;  // a: initial velocities uniform on [-a, a]^2
    VelocityHistogram histogram;
    std::vector<RelaxationSample> samples;
    int finalSnapshots = 0;  // the equilibrium H is the mean over this many last samples
    double hInitial = 0.0, hFinal = 0.0;
    // The known errors of the final H estimate: its plug-in bias
    // (occupied bins - 1) / (2 n), the binning bias of a Gaussian (negative,
    // this is its size), and the tolerance of the check built from them.
    double hPluginBias = 0.0, hBinningBias = 0.0, hTolerance = 0.0;
    double ksCritical = 0.0;
    double kTFinal = 0.0;
    std::vector<double> speedBinEdges;   // the final speed histogram
    std::vector<double> speedDensity;    // per unit speed
};

// --- 5. Conservation per backend ------------------------------------------

struct ConservationRun {
    std::string backend;  // "cpu", "opencl seed", "opencl resident"
    std::string device;
    std::uint32_t particles = 0;
    double packing = 0.0;
    double dt = 0.0;
    std::uint64_t steps = 0;
    double momentumError = 0.0;  // |P_end - P_start| / sum m|v|
    double energyChange = 0.0;   // (E_end - E_start) / E_start
};

struct SuiteResult {
    SuiteOptions options;
    std::string device;  // the heavy runs' backend and device, in words
    EosResult eos;
    ConvergenceResult convergence;
    RelaxationResult relaxation;
    std::vector<ConservationRun> conservation;
    std::vector<Check> checks;  // every check of every part, in order
    double wallSeconds = 0.0;
    bool passed() const;
};

// The backend and device `def` selects, in words; throws Error for a bad
// kind, device or pipeline, so a run can refuse them before any work.
std::string describeBackend(const BackendDef& def);

// Runs the whole suite, printing one progress line per run to `progress`.
SuiteResult runSuite(const SuiteOptions& options, std::ostream& progress);

}  // namespace carom::validation
