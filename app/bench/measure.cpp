#include "app/bench/measure.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#ifdef CAROM_HAVE_OPENCL
#include "backends/opencl/runtime.h"
#include "app/bench/program.h"
#endif

namespace carom::bench {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double timedSteps(Stepper& stepper, std::uint64_t steps, const TimingPlan& plan) {
    const auto start = Clock::now();
    stepper.step(steps);
    const double seconds = secondsSince(start);
    return plan.agreed ? plan.agreed(seconds) : seconds;
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

// Runs `repeats` times and returns the shortest duration.
template <class Run>
double bestOf(int repeats, Run&& run) {
    double best = INFINITY;
    for (int r = 0; r < repeats; ++r) {
        const auto start = Clock::now();
        run();
        best = std::min(best, secondsSince(start));
    }
    return best;
}

}  // namespace

std::uint64_t eventsOf(const EventCounts& counts) {
    return counts.collisions + counts.wallBounces + counts.cellCrossings + counts.stale;
}

Timing timeSteps(Stepper& stepper, const TimingPlan& plan) {
    Timing timing;
    const double particles = double(stepper.diskCount());
    const auto leftLattice = [&] {
        const std::optional<EventProgress> events = stepper.events();
        return !events || double(events->counts.collisions) >= plan.warmupCollisionsPerDisk * particles;
    };
    // Warm-up: one step, then doubling batches until warmupSeconds have
    // passed (and the event-driven gas has left its lattice).
    double perStep = timedSteps(stepper, 1, plan);
    timing.warmupSteps = 1;
    const bool overBudget = perStep > plan.budgetSeconds;
    const int samples = overBudget ? std::min(plan.samples, plan.samplesOverBudget) : plan.samples;
    double warmed = perStep;
    for (std::uint64_t batch = 1; (!overBudget && warmed < plan.warmupSeconds) || !leftLattice(); batch *= 2) {
        const double seconds = timedSteps(stepper, batch, plan);
        warmed += seconds;
        timing.warmupSteps += batch;
        perStep = seconds / double(batch);
    }
    timing.stepsPerSample = std::max<std::uint64_t>(1, std::uint64_t(std::ceil(plan.sampleSeconds / perStep)));
    const std::optional<EventProgress> warm = stepper.events();
    std::vector<double> collisionRates, eventRates, particleTimeRates;
    for (int s = 0; s < samples; ++s) {
        const std::optional<EventProgress> before = stepper.events();
        const double seconds = timedSteps(stepper, timing.stepsPerSample, plan);
        timing.sampleSecondsPerStep.push_back(seconds / double(timing.stepsPerSample));
        if (!before) continue;
        const EventProgress after = *stepper.events();
        collisionRates.push_back(double(after.counts.collisions - before->counts.collisions) / seconds);
        eventRates.push_back(double(eventsOf(after.counts) - eventsOf(before->counts)) / seconds);
        particleTimeRates.push_back(particles * (after.time - before->time) / seconds);
    }
    timing.secondsPerStep = median(timing.sampleSecondsPerStep);
    timing.substepsPerStep = stepper.substepsPerStep();
    timing.devicePeakBytes = stepper.devicePeakBytes();
    if (warm) {
        const EventCounts end = stepper.events()->counts;
        const EventCounts& start = warm->counts;
        timing.events = EventRates{
            median(collisionRates),
            median(eventRates),
            median(particleTimeRates),
            collisionRates,
            double(start.collisions) / particles,
            {end.collisions - start.collisions, end.wallBounces - start.wallBounces,
             end.cellCrossings - start.cellCrossings, end.stale - start.stale, end.overlapping - start.overlapping}};
    }
    return timing;
}

double measureHostCopy(std::size_t bytes, int repeats) {
    const auto n = static_cast<std::int64_t>(bytes / sizeof(double));
    std::vector<double> from(static_cast<std::size_t>(n)), to(static_cast<std::size_t>(n));
    // First touch by the threads that copy, so pages sit near them.
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
        from[i] = double(i);
        to[i] = 0.0;
    }
    const double seconds = bestOf(repeats, [&] {
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) to[i] = from[i];
    });
    return 2.0 * double(n) * sizeof(double) / seconds;
}

#ifdef CAROM_HAVE_OPENCL
DeviceDescription measureDeviceBandwidth(const std::string& selector, std::size_t bytes, int repeats,
                                         Bandwidth& bandwidth) {
    using namespace opencl;
    const DeviceInfo device = selectDevice(selector);
    cl_int status = CL_SUCCESS;
    Context context(clCreateContext(nullptr, 1, &device.id, nullptr, nullptr, &status));
    check(status, "clCreateContext");
    Queue queue(clCreateCommandQueue(context.get(), device.id, 0, &status));
    check(status, "clCreateCommandQueue");
    const Program program = buildProgram(context.get(), device, bench::kernelSource(), false);
    const Kernel copy = createKernel(program.get(), "copyFloat4");

    const cl_uint vectors = static_cast<cl_uint>(bytes / 16);
    bytes = std::size_t(vectors) * 16;
    const Buffer from = createBuffer(context.get(), bytes, "bandwidth source");
    const Buffer to = createBuffer(context.get(), bytes, "bandwidth target");
    std::vector<unsigned char> host(bytes, 1);
    const std::size_t group = std::min<std::size_t>(256, kernelWorkGroupLimit(copy.get(), device.id));
    setKernelArgs(copy.get(), from.get(), to.get(), vectors);

    const double upload = bestOf(repeats, [&] {
        check(clEnqueueWriteBuffer(queue.get(), from.get(), CL_TRUE, 0, bytes, host.data(), 0, nullptr, nullptr),
              "clEnqueueWriteBuffer(bandwidth)");
    });
    // Copies back to back, so one wait for the device spreads over several.
    constexpr int copiesPerRepeat = 8;
    const auto copies = [&] {
        for (int c = 0; c < copiesPerRepeat; ++c) enqueue1d(queue.get(), copy.get(), vectors, group, "copyFloat4");
        check(clFinish(queue.get()), "clFinish");
    };
    copies();  // warm-up
    const double copySeconds = bestOf(repeats, copies) / copiesPerRepeat;
    const double download = bestOf(repeats, [&] {
        check(clEnqueueReadBuffer(queue.get(), to.get(), CL_TRUE, 0, bytes, host.data(), 0, nullptr, nullptr),
              "clEnqueueReadBuffer(bandwidth)");
    });
    bandwidth.deviceCopy = 2.0 * double(bytes) / copySeconds;
    bandwidth.upload = double(bytes) / upload;
    bandwidth.download = double(bytes) / download;
    return {device.name, device.platformName, device.version, device.driverVersion};
}
#else
DeviceDescription measureDeviceBandwidth(const std::string&, std::size_t, int, Bandwidth&) {
    throw Error("this carom was built without OpenCL: no device bandwidth to measure");
}
#endif

}  // namespace carom::bench
