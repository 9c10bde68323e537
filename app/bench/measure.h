// Timing a method's steps, and the memory bandwidths the results are read
// against.
#pragma once

#include <functional>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "app/bench/methods.h"

namespace carom::bench {

struct TimingPlan {
    int samples = 7;             // timed samples; the median is reported
    double sampleSeconds = 0.1;  // each sample runs enough steps to last about this long
    double warmupSeconds = 0.2;  // untimed steps first (caches, clocks, lazy allocations)
    double budgetSeconds = 1.0;  // a step slower than this: fewer samples, and larger N is dropped
    int samplesOverBudget = 3;
    // The events method also warms up until this many collisions per
    // disk: the gas leaves its starting lattice before it is timed.
    double warmupCollisionsPerDisk = 3;
    // A timing as every process of a decomposed world takes it (the
    // slowest's), so that all take the same steps; null in one process.
    std::function<double(double)> agreed;
};

// What the events method did per wall-clock second, each the median
// over the samples: its collisions, its events of every kind (collisions,
// wall bounces, cell crossings and stale events recomputed) and its
// particle-time (N x the simulated time).
struct EventRates {
    double collisionsPerSecond = 0;
    double eventsPerSecond = 0;
    double particleTimePerSecond = 0;
    std::vector<double> sampleCollisionsPerSecond;
    double warmupCollisionsPerDisk = 0;  // collisions per disk before the first sample
    EventCounts sampled;                 // counted over all the samples
};

// The events the calendar handed out, of every kind (EventRates).
std::uint64_t eventsOf(const EventCounts& counts);

struct Timing {
    double secondsPerStep = 0;                 // median over the samples
    std::vector<double> sampleSecondsPerStep;  // each sample's mean step time
    std::uint64_t stepsPerSample = 1;
    std::uint64_t warmupSteps = 0;
    double substepsPerStep = 1;         // the mean over every step taken (Stepper::substepsPerStep)
    std::uint64_t devicePeakBytes = 0;  // Stepper::devicePeakBytes, after the samples
    std::optional<EventRates> events;   // for the events method
};

// Warms the stepper up, then times plan.samples samples of whole steps; the
// events method's events are counted too.
Timing timeSteps(Stepper& stepper, const TimingPlan& plan);

// Host memory: an OpenMP-parallel copy between two buffers of `bytes`, best
// of `repeats`.
double measureHostCopy(std::size_t bytes, int repeats);

// The OpenCL device named by `selector`: its copy kernel (kernels/bench.cl)
// between two buffers of `bytes`, and uploads and downloads of `bytes`, each
// best of `repeats`. Fills the device fields of `bandwidth`; returns the device's
// description.
struct DeviceDescription {
    std::string name, platform, version, driver;
};
DeviceDescription measureDeviceBandwidth(const std::string& selector, std::size_t bytes, int repeats,
                                         Bandwidth& bandwidth);

}  // namespace carom::bench
