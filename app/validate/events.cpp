#include "app/validate/events.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ostream>

#include <carom/carom.h>

#include "app/validate/runs.h"

namespace carom::validation {

namespace {

// How long an event-driven run warms up and measures, in collisions per
// disk (mean collision times at the reference Z): the lattice melts within
// a few, so the warm-up is generous, and the blocks are long enough that
// 8 merged ones (blockingAverage) outlast the pressure's correlations.
struct EventsProtocol {
    double warmup = 0.0;
    int blocks = 0;
    double perBlock = 0.0;
};

EventsProtocol eosProtocol(bool quick) { return quick ? EventsProtocol{50, 32, 5} : EventsProtocol{100, 64, 40}; }
// Near the liquid-hexatic transition the lattice takes far longer to melt.
EventsProtocol denseProtocol(bool quick) { return quick ? EventsProtocol{200, 32, 5} : EventsProtocol{2000, 64, 40}; }

// Energy is conserved but for the rounding of doubles: the target,
// 1e-12 over 10^6 collisions, growing linearly with the collisions.
double energyTolerance(std::uint64_t collisions) { return 1e-12 * std::max(1.0, double(collisions) / 1e6); }

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EventsRun eventsRun(std::uint32_t particles, double packing, std::uint64_t seed, const EventsProtocol& protocol) {
    const auto start = std::chrono::steady_clock::now();
    EventsRun run;
    run.packing = packing;
    run.particles = particles;
    run.warmupCollisions = protocol.warmup;
    // dt only sets when the state is sampled: once per mean collision time.
    const float sampling = float(collisionTime(packing));
    const Box box = periodicBox(particles, packing, sampling, seed, CollisionScheme::Events);
    World world(box.world);
    world.setDisks(box.disks);
    const double energyStart = world.totalEnergy();  // the engine's, in double
    const std::uint64_t warmupSteps = stepsFor(protocol.warmup, 1.0);
    world.step(warmupSteps);
    run.warmupTime = double(warmupSteps) * sampling;
    run.measured = runBlocks(world, protocol.blocks, protocol.perBlock * sampling);
    run.energyChange = world.totalEnergy() / energyStart - 1.0;
    const EventCounts counts = world.eventCounts();
    run.collisions = counts.collisions;
    run.cellCrossings = counts.cellCrossings;
    run.overlapping = counts.overlapping;
    run.energyTolerance = energyTolerance(run.collisions);
    run.seconds = secondsSince(start);
    return run;
}

std::string at(double packing) { return "eta = " + format("%.2f", packing); }

void energyCheck(const std::string& section, const EventsRun& run, std::vector<Check>& checks) {
    checks.push_back(
        makeCheck(section, "energy over the run at " + at(run.packing), run.energyChange, 0.0,
                  std::abs(run.energyChange), run.energyTolerance,
                  "|E_end - E_start| / E_start <= 1e-12 per 10^6 collisions = " + format("%.2g", run.energyTolerance)));
}

void progressLine(std::ostream& progress, const std::string& what, const EventsRun& run) {
    const BlockStatistics& m = run.measured;
    progress << "  " << what << ", eta " << run.packing << ": Z " << m.z.mean << " +- " << m.z.error << ", rate ratio "
             << m.rateRatio.mean << " +- " << m.rateRatio.error << ", energy change " << run.energyChange << ", "
             << run.collisions << " collisions in " << run.seconds << " s" << std::endl;
}

// The pressures published at eta = 0.70, beta P sigma^2 with sigma the
// diameter, from the authors' data as collected by Li et al. in
// github.com/jellyfysh/HistoricDisks (DigitizedData: Bernard_2011.csv,
// Engel_2013.csv, ThisWork.csv; periodic boxes, square unless noted).
std::vector<PublishedPressure> publishedAt070() {
    const std::string bernard = "Bernard & Krauth, Phys. Rev. Lett. 107, 155704 (2011)";
    const std::string engel = "Engel et al., Phys. Rev. E 87, 042134 (2013)";
    const std::string li = "Li et al., J. Chem. Phys. 157, 234111 (2022)";
    return {{bernard, "event-chain Monte Carlo", "1024^2", 9.18545, 0.00011},
            {engel, "event-driven MD", "512^2", 9.18640, 0.00047},
            {engel, "event-driven MD", "256^2", 9.18896, 0.00024},
            {li, "event-chain Monte Carlo, box 29 : 30 sqrt(3)/2", "870", 9.12956, 0.00017},
            {li, "event-chain Monte Carlo", "224", 8.6876, 0.0012}};
}

// --- 9.3 ---------------------------------------------------------------------

// A few disks of radius 1 and mass 1 between walls: one per cell of a 4 x 4
// grid, jittered, with thermal velocities at kT = 1 (packing 0.2); several
// independent starts, so that the distances do not hang on one start's
// chaos.
constexpr std::uint32_t kGridSide = 4;
constexpr double kCellSide = 4.0;
constexpr std::uint32_t kStarts = 4;
// A short run: each disk collides with another one to two times and bounces
// off a wall about as often; by twice this time the stepped runs' collision
// sequences start to differ from the exact one (measured).
constexpr double kTrajectoryTime = 4.0;
// The stepped schemes' dts: kLargestDt, halved kHalvings times. The
// simultaneous scheme's own error dominates down to kLargestDt / 2^5; below
// that the float32 rounding of the positions, which grows as 1/dt (every
// step rounds x + v dt, the same way while v is constant), takes over.
constexpr double kLargestDt = 0.04;
constexpr int kHalvings = 9;
constexpr int kTruncationHalvings = 5;
// The pairwise scheme collides at the exact contact times: at the largest dt
// it is off only by the rounding of 100 float32 steps, amplified by the
// collisions (1e-4 measured), far below the simultaneous scheme (1e-1).
constexpr double kPairwiseRoundingBound = 1e-3;

std::vector<Disk> fewDisks(std::uint64_t seed) {
    Random random(seed);
    std::vector<Disk> disks;
    const double jitter = kCellSide / 2 - 1.0 - 0.1;  // keeps a gap of 0.2 between neighbours
    for (std::uint32_t row = 0; row < kGridSide; ++row)
        for (std::uint32_t column = 0; column < kGridSide; ++column) {
            Disk d;
            d.position.x = float((column + 0.5) * kCellSide + random.uniform(-jitter, jitter));
            d.position.y = float((row + 0.5) * kCellSide + random.uniform(-jitter, jitter));
            d.velocity.x = float(random.normal());
            d.velocity.y = float(random.normal());
            disks.push_back(d);
        }
    return disks;
}

WorldDef fewDisksWorld(double dt, CollisionScheme scheme) {
    WorldDef world;
    world.width = world.height = float(kGridSide * kCellSide);
    world.dt = float(dt);
    world.boundary = Boundary::Walls;
    world.collisions = scheme;
    return world;
}

// The distances of stepped positions from exact ones, over all starts.
struct Distance {
    double squares = 0.0, max = 0.0;
    std::size_t disks = 0;
    std::uint64_t collisions = 0;
    void add(const std::vector<Disk>& stepped, const std::vector<std::array<double, 2>>& exact) {
        for (std::size_t i = 0; i < exact.size(); ++i) {
            const double r = std::hypot(stepped[i].position.x - exact[i][0], stepped[i].position.y - exact[i][1]);
            squares += r * r;
            max = std::max(max, r);
        }
        disks += exact.size();
    }
    double rms() const { return std::sqrt(squares / double(disks)); }
};

}  // namespace

std::string eventsDevice() {
    WorldDef world;
    world.width = world.height = 10.0f;
    world.collisions = CollisionScheme::Events;
    return World(world).deviceName();
}

double compressibility(const PublishedPressure& p, double packing) { return kPi * p.betaPSigma2 / (4.0 * packing); }

std::vector<EventsEosPoint> eventsEquationOfState(const SuiteOptions& o, std::vector<Check>& checks,
                                                  std::ostream& progress) {
    const std::string section = "events: equation of state";
    std::vector<EventsEosPoint> points;
    for (const ReferenceZ& reference : referenceTable()) {
        EventsEosPoint point;
        point.run = eventsRun(kEventsParticles, reference.packing, o.seed, eosProtocol(o.quick));
        point.zReference = referenceZ(reference.packing);
        point.zReferenceError = reference.uncertainty;
        const MeanAndError& z = point.run.measured.z;
        point.zTolerance = kEventsZTarget * point.zReference + 2.0 * std::hypot(z.error, point.zReferenceError);
        point.rateTolerance = statisticalTolerance(0.0, point.run.measured.rateRatio.error);
        points.push_back(point);
        const std::string where = at(reference.packing);
        checks.push_back(makeCheck(
            section, "Z at " + where, z.mean, point.zReference, std::abs(z.mean - point.zReference), point.zTolerance,
            "|Z - Z_ref| <= 0.1 % of Z_ref + 2 standard errors of Z and Z_ref = " + format("%.2g", point.zTolerance)));
        checks.push_back(rateCheck(section, "collision-rate identity at " + where, point.run.measured.rateRatio,
                                   point.rateTolerance, 0.0));
        energyCheck(section, point.run, checks);
        progressLine(progress, "events", point.run);
    }
    return points;
}

EventsDense eventsDense(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    EventsDense result;
    result.run = eventsRun(kEventsParticles, 0.70, o.seed, denseProtocol(o.quick));
    result.rateTolerance = statisticalTolerance(0.0, result.run.measured.rateRatio.error);
    result.published = publishedAt070();
    checks.push_back(rateCheck("events: dense", "collision-rate identity at " + at(0.70), result.run.measured.rateRatio,
                               result.rateTolerance, 0.0));
    energyCheck("events: dense", result.run, checks);
    progressLine(progress, "events, dense", result.run);
    return result;
}

TrajectoryResult stepTrajectories(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    TrajectoryResult result;
    result.starts = kStarts;
    result.particles = kGridSide * kGridSide;
    result.width = result.height = kGridSide * kCellSide;
    result.duration = kTrajectoryTime;
    std::vector<std::vector<Disk>> starts;
    std::vector<std::vector<std::array<double, 2>>> exact;
    for (std::uint32_t k = 0; k < kStarts; ++k) {
        starts.push_back(fewDisks(o.seed + 0x9e3779b97f4a7c15ull * k));
        World events(fewDisksWorld(kTrajectoryTime, CollisionScheme::Events));
        events.setDisks(starts.back());
        events.step(1);
        exact.push_back(events.exactPositions());
        result.eventCollisions += events.eventCounts().collisions;
        result.eventWallBounces += events.eventCounts().wallBounces;
    }
    double dt = kLargestDt;
    for (int k = 0; k <= kHalvings; ++k, dt /= 2) {
        TrajectoryPoint point;
        point.dt = dt;
        for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous}) {
            Distance d;
            for (std::size_t start = 0; start < starts.size(); ++start) {
                World stepped(fewDisksWorld(dt, scheme));  // on the CPU
                stepped.setDisks(starts[start]);
                stepped.step(stepsFor(kTrajectoryTime, dt));
                d.add(stepped.disks(), exact[start]);
                d.collisions += stepped.collisionCount();
            }
            const bool pairwise = scheme == CollisionScheme::Pairwise;
            (pairwise ? point.pairwiseRms : point.simultaneousRms) = d.rms();
            (pairwise ? point.pairwiseMax : point.simultaneousMax) = d.max;
            (pairwise ? point.pairwiseCollisions : point.simultaneousCollisions) = d.collisions;
        }
        result.points.push_back(point);
        progress << "  trajectories, dt " << dt << ": rms distance to events, pairwise " << point.pairwiseRms
                 << ", simultaneous " << point.simultaneousRms << std::endl;
    }
    const std::string section = "events: trajectories";
    const TrajectoryPoint& largest = result.points.front();
    const TrajectoryPoint& resolved = result.points[kTruncationHalvings];
    const double order = std::log2(largest.simultaneousRms / resolved.simultaneousRms) / kTruncationHalvings;
    checks.push_back(makeCheck(
        section,
        "simultaneous: mean observed order from dt = " + format("%g", largest.dt) + " to " + format("%g", resolved.dt),
        order, NAN, -order, -0.5, "log2(distance ratio) per halving of dt >= 0.5"));
    checks.push_back(makeCheck(section, "pairwise: rms distance at dt = " + format("%g", largest.dt),
                               largest.pairwiseRms, NAN, largest.pairwiseRms, kPairwiseRoundingBound,
                               "rms |x - x_events| <= 1e-3 (float32 rounding, not dt)"));
    return result;
}

std::vector<SchemeComparison> schemeComparison(const SuiteOptions& o, const std::vector<EventsEosPoint>& eos,
                                               std::ostream& progress) {
    const std::vector<double> packings = o.quick ? std::vector<double>{0.5} : std::vector<double>{0.3, 0.5, 0.6};
    const std::vector<double> dts = o.quick ? std::vector<double>{0.02, 0.01} : std::vector<double>{0.02, 0.01, 0.005};
    const double warmup = o.quick ? 10.0 : 20.0, blockTime = o.quick ? 2.5 : 5.0;
    const int blocks = o.quick ? 8 : 16;
    std::vector<SchemeComparison> result;
    for (double packing : packings) {
        SchemeComparison comparison;
        comparison.packing = packing;
        comparison.particles = kEventsParticles;
        comparison.warmupTime = warmup;
        comparison.events = {NAN, NAN};
        for (const EventsEosPoint& point : eos)
            if (std::abs(point.run.packing - packing) < 1e-9) comparison.events = point.run.measured.z;
        for (double dt : dts) {
            SchemeZ run;
            run.dt = dt;
            for (CollisionScheme scheme : {CollisionScheme::Pairwise, CollisionScheme::Simultaneous}) {
                const bool pairwise = scheme == CollisionScheme::Pairwise;
                BlockStatistics& measured = pairwise ? run.pairwise : run.simultaneous;
                measured.z = {NAN, NAN};
                try {
                    World world =
                        loaded(o.backend, periodicBox(comparison.particles, packing, float(dt), o.seed, scheme));
                    world.step(stepsFor(warmup, dt));
                    measured = runBlocks(world, blocks, blockTime);
                } catch (const Error& e) {  // reported in the table; the comparison is not a check
                    (pairwise ? run.pairwiseFailure : run.simultaneousFailure) = e.what();
                }
            }
            comparison.runs.push_back(run);
            progress << "  schemes against events, eta " << packing << ", dt " << dt << ": Z pairwise "
                     << run.pairwise.z.mean << ", simultaneous " << run.simultaneous.z.mean << ", events "
                     << comparison.events.mean << std::endl;
        }
        result.push_back(comparison);
    }
    return result;
}

}  // namespace carom::validation
