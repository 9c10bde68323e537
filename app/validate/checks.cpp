#include "app/validate/checks.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ostream>
#include <sstream>

#include <carom/carom.h>

#include "app/validate/events.h"
#include "app/validate/runs.h"

namespace carom::validation {

namespace {

constexpr double kDegree = kPi / 180.0;

// |P_end - P_start| / sum m|v| at the end: momentum lost or gained, relative
// to the momentum the disks carry.
double momentumError(const std::array<double, 2>& start, const World& end) {
    double scale = 0;
    for (const Disk& d : end.disks()) scale += d.mass * std::hypot(double(d.velocity.x), double(d.velocity.y));
    const std::array<double, 2> momentum = end.momentum();
    return std::hypot(momentum[0] - start[0], momentum[1] - start[1]) / scale;
}

// --- 1. Equation of state ---------------------------------------------------

EosResult equationOfState(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    EosResult result;
    result.dt = o.dt;
    const std::uint32_t particles = o.eosParticles ? o.eosParticles : kEosParticles(o.quick);
    // The full suite resolves the 0.3 % target at every packing: three
    // standard errors, its own and the reference's combined, stay under
    // 0.3 %. The quick suite's, about a third of a percent to a half, do not.
    const int blocks = o.quick ? 30 : 40;
    for (const ReferenceZ& reference : referenceTable()) {
        const double packing = reference.packing;
        // Long enough, even at low density, for 20 collisions per disk to
        // melt the lattice and two per block.
        EosPoint point;
        point.packing = packing;
        point.particles = particles;
        point.equilibrationTime = std::max(o.quick ? 20.0 : 50.0, 20.0 * collisionTime(packing));
        const double blockTime = std::max(o.quick ? 5.0 : 10.0, 2.0 * collisionTime(packing));
        World world = loaded(o.backend, periodicBox(particles, packing, o.dt, o.seed));
        world.step(stepsFor(point.equilibrationTime, o.dt));
        point.measured = runBlocks(world, blocks, blockTime);
        point.zReference = referenceZ(packing);
        point.zReferenceError = reference.uncertainty;
        const MeanAndError& z = point.measured.z;
        point.zTolerance =
            statisticalTolerance(kZTarget, std::hypot(z.error, point.zReferenceError) / point.zReference);
        point.rateTolerance = statisticalTolerance(kRateTarget, point.measured.rateRatio.error);
        result.points.push_back(point);
        const std::string at = "eta = " + format("%.1f", packing);
        checks.push_back(makeCheck("equation of state", "Z at " + at, z.mean, point.zReference,
                                   std::abs(z.mean - point.zReference) / point.zReference, point.zTolerance,
                                   "|Z - Z_ref| / Z_ref <= max(0.3 %, 3 standard errors of Z and Z_ref) = " +
                                       format("%.2g", 100 * point.zTolerance) + " %"));
        checks.push_back(rateCheck("equation of state", "collision frequency at " + at, point.measured.rateRatio,
                                   point.rateTolerance, kRateTarget));
        progress << "  equation of state, eta " << packing << ": Z " << z.mean << " +- " << z.error << " (reference "
                 << point.zReference << "), rate ratio " << point.measured.rateRatio.mean << ", energy change "
                 << point.measured.energyChange << std::endl;
    }
    return result;
}

// --- 2. Convergence in dt -----------------------------------------------------

ConvergenceResult convergence(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    ConvergenceResult result;
    result.packing = 0.5;
    result.particles = o.quick ? 1024 : 8192;
    result.zReference = referenceZ(result.packing);
    result.equilibrationTime = o.quick ? 10.0 : 20.0;
    const int blocks = 20;
    const double blockTime = o.quick ? 2.0 : 5.0;
    // Up to dt = 0.04, where the pairwise grid's allowance splits steps of
    // the fastest disks into substeps.
    const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005, 0.0025};

    // One melted state, continued at each dt.
    const Box box = periodicBox(result.particles, result.packing, kDefaultDt, o.seed);
    World world = loaded(o.backend, box);
    world.step(stepsFor(result.equilibrationTime, kDefaultDt));
    const std::vector<Disk> melted = world.disks();
    for (double dt : dts) {
        world.setMotion(float(dt), box.world.gravity);
        world.setDisks(melted);
        world.step(stepsFor(blockTime, dt));  // the contacts settle at this dt
        ConvergencePoint point;
        point.dt = dt;
        point.measured = runBlocks(world, blocks, blockTime);
        result.points.push_back(point);
        progress << "  convergence, dt " << dt << ": Z " << point.measured.z.mean << " +- " << point.measured.z.error
                 << ", energy change " << point.measured.energyChange << ", late contacts "
                 << point.measured.lateContacts << std::endl;
    }
    // Exact contact times: Z should not depend on dt. Each dt against the smallest.
    const MeanAndError& finest = result.points.back().measured.z;
    for (ConvergencePoint& point : result.points) {
        point.zDifference = point.measured.z.mean - finest.mean;
        point.differenceError = std::hypot(point.measured.z.error, finest.error);
        if (&point == &result.points.back()) continue;
        const double tolerance = statisticalTolerance(0.0, point.differenceError);
        checks.push_back(makeCheck(
            "convergence", "Z at dt = " + format("%g", point.dt) + " equals Z at dt = " + format("%g", dts.back()),
            point.measured.z.mean, finest.mean, std::abs(point.zDifference), tolerance,
            "|Z - Z(dt = " + format("%g", dts.back()) + ")| <= 3 standard errors = " + format("%.2g", tolerance)));
    }
    return result;
}

// --- 3. Relaxation to Maxwell-Boltzmann --------------------------------------

std::vector<double> speedsOf(const std::vector<Disk>& disks) {
    std::vector<double> speeds;
    speeds.reserve(disks.size());
    for (const Disk& d : disks) speeds.push_back(std::hypot(double(d.velocity.x), double(d.velocity.y)));
    return speeds;
}

HEstimate hOf(const std::vector<Disk>& disks, const VelocityHistogram& histogram) {
    std::vector<double> vx, vy;
    for (const Disk& d : disks) {
        vx.push_back(d.velocity.x);
        vy.push_back(d.velocity.y);
    }
    return hFunction(vx, vy, histogram);
}

// The world's state at `time`: its kT (a periodic box) and velocity statistics.
RelaxationSample sampleOf(const World& world, double time, const VelocityHistogram& histogram) {
    const std::vector<Disk> disks = world.disks();
    RelaxationSample sample;
    sample.time = time;
    sample.kT = world.temperature();
    sample.h = hOf(disks, histogram).value;
    sample.ks = ksRayleigh(speedsOf(disks), sample.kT / disks.front().mass);
    return sample;
}

RelaxationResult relaxation(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    RelaxationResult result;
    result.packing = 0.3;
    result.particles = o.quick ? 16384 : 65536;
    result.dt = o.dt;
    // kT = m a^2 / 3 = 1. Bins of a/4 put +-a on bin edges (the uniform start
    // is binned exactly); +-3a is 5.2 thermal widths.
    result.halfWidth = std::sqrt(3.0);
    result.histogram.range = 3.0 * result.halfWidth;
    result.histogram.binsPerAxis = 24;
    const double sampleInterval = 0.5, duration = 20.0;
    result.finalSnapshots = 11;  // t = 15 ... 20: several collision times after relaxation

    Box box = periodicBox(result.particles, result.packing, o.dt, o.seed);
    Random random(o.seed + 1);
    for (Disk& d : box.disks) {
        d.velocity.x = float(random.uniform(-result.halfWidth, result.halfWidth));
        d.velocity.y = float(random.uniform(-result.halfWidth, result.halfWidth));
    }
    removeDrift(box.disks);
    World world = loaded(o.backend, box);
    const std::uint64_t stepsPerSample = stepsFor(sampleInterval, o.dt);
    const int samples = int(std::lround(duration / sampleInterval));
    for (int k = 0; k <= samples; ++k) {
        if (k > 0) world.step(stepsPerSample);
        result.samples.push_back(sampleOf(world, k * sampleInterval, result.histogram));
    }
    const std::vector<Disk> state = world.disks();

    const std::size_t n = state.size();
    result.hInitial = result.samples.front().h;
    for (int k = 0; k < result.finalSnapshots; ++k) result.hFinal += result.samples[result.samples.size() - 1 - k].h;
    result.hFinal /= result.finalSnapshots;
    result.kTFinal = result.samples.back().kT;
    result.ksCritical = ksCritical05(n);

    // H of the uniform square exactly, and of the equilibrium at the final
    // kT (any energy error of the scheme moves it by -ln(kT_end / kT_start)).
    const double hUniform = -std::log(4.0 * result.halfWidth * result.halfWidth);
    const double expectedChange = hEquilibrium(result.kTFinal) - hUniform;
    result.hPluginBias = hOf(state, result.histogram).bias();
    // The tolerance is the sum of the estimator's known errors: its plug-in
    // bias, the binning of a Gaussian of variance kT/m per axis with bins of
    // width w, -w^2 / (12 kT/m) in 2D, and three standard errors of one
    // snapshot (the variance of ln f under a 2D Gaussian is 1).
    const double binWidth = 2.0 * result.histogram.range / result.histogram.binsPerAxis;
    result.hBinningBias = binWidth * binWidth / (12.0 * result.kTFinal);
    result.hTolerance = result.hPluginBias + result.hBinningBias + 3.0 / std::sqrt(double(n));
    const double change = result.hFinal - result.hInitial;
    checks.push_back(makeCheck(
        "relaxation", "H falls by ln(6/pi) - 1", change, expectedChange, std::abs(change - expectedChange),
        result.hTolerance,
        "|dH - dH_exact| <= plug-in bias + binning bias + 3 standard errors = " + format("%.4f", result.hTolerance)));
    const double ks = result.samples.back().ks;
    checks.push_back(makeCheck("relaxation", "KS statistic of the final speeds against Rayleigh", ks, NAN, ks,
                               result.ksCritical, "D < 1.358 / sqrt(n), the 5 % critical value"));

    // The final speed histogram, per unit speed, over [0, 5 sqrt(kT/m)].
    const int bins = 40;
    const double top = 5.0 * std::sqrt(result.kTFinal);
    for (int b = 0; b <= bins; ++b) result.speedBinEdges.push_back(top * b / bins);
    result.speedDensity.assign(bins, 0.0);
    for (double v : speedsOf(state)) {
        const double bin = std::floor(v / top * bins);
        if (bin >= 0 && bin < bins) result.speedDensity[std::size_t(bin)] += bins / (top * double(n));
    }
    progress << "  relaxation: dH " << change << " (exact " << expectedChange << "), final KS " << ks << " (critical "
             << result.ksCritical << ")" << std::endl;
    return result;
}

// --- 4. Exact cases -----------------------------------------------------------

// The pairwise scheme resolves a collision at its contact time within the
// step, so the suite's default step does: the target is exactness at dt = 0.01.
constexpr float kExactDt = 0.01f;
// The pairwise scheme collides a pair at the exact contact time and normal:
// only the rounding of float positions near 50 (2^-18 = 3.8e-6) separates
// it from the formula, tilting the normal by up to about 2 x 3.8e-6 / sigma
// = 4e-6 rad (2e-4 degrees, 4e-6 of the speed); these tolerances are five
// times that.
constexpr double kVelocityTolerance = 2e-5;  // of the incoming relative speed
constexpr double kAngleTolerance = 1e-3;     // [degrees]

struct Vector {
    double x = 0, y = 0;
};

Vector velocity(const Disk& d) { return {d.velocity.x, d.velocity.y}; }
double length(Vector v) { return std::hypot(v.x, v.y); }
double angleOf(Vector v) { return std::atan2(v.y, v.x); }

// The formula of the reference, at the exact moment of contact.
std::array<Vector, 2> exactOutcome(const Disk& a, const Disk& b) {
    const double sigma = double(a.radius) + b.radius;
    const Vector d{double(a.position.x) - b.position.x, double(a.position.y) - b.position.y};
    const Vector u{double(a.velocity.x) - b.velocity.x, double(a.velocity.y) - b.velocity.y};
    const double uu = u.x * u.x + u.y * u.y, du = d.x * u.x + d.y * u.y;
    const double t = (-du - std::sqrt(du * du - uu * (d.x * d.x + d.y * d.y - sigma * sigma))) / uu;
    const Vector n{(d.x + u.x * t) / sigma, (d.y + u.y * t) / sigma};
    const double un = u.x * n.x + u.y * n.y, total = double(a.mass) + b.mass;
    const double ka = 2.0 * b.mass / total * un, kb = 2.0 * a.mass / total * un;
    return {Vector{a.velocity.x - ka * n.x, a.velocity.y - ka * n.y},
            Vector{b.velocity.x + kb * n.x, b.velocity.y + kb * n.y}};
}

Disk disk(double x, double y, double vx, double vy, double mass) {
    return Disk{Vec2{float(x), float(y)}, Vec2{float(vx), float(vy)}, float(mass), 1.0f};
}

// A projectile moving along +x at speed v towards a target at rest, at
// impact parameter b (the projectile passes below the target's centre),
// 0.05 short of contact.
std::array<Disk, 2> approachingPair(double projectileMass, double targetMass, double v, double b) {
    const double sigma = 2.0, start = 50.0 - std::sqrt(sigma * sigma - b * b) - 0.05;
    return {disk(start, 50.0 - b, v, 0, projectileMass), disk(50, 50, 0, 0, targetMass)};
}

// Two disks in a box far larger than their paths, stepped until they have
// collided and moved apart.
std::array<Vector, 2> simulatePair(const EngineDef& engine, const std::array<Disk, 2>& pair) {
    WorldDef def;
    def.width = def.height = 100.0f;
    def.dt = kExactDt;
    def.collisions = CollisionScheme::Pairwise;
    World world = loaded(engine, def, {pair[0], pair[1]});
    std::vector<Disk> state;
    for (int chunk = 0; chunk < 1000; ++chunk) {
        world.step(100);
        state = world.disks();
        const double distance = std::hypot(double(state[0].position.x) - state[1].position.x,
                                           double(state[0].position.y) - state[1].position.y);
        if (world.collisionCount() > 0 && distance > 2.1) break;
    }
    if (world.collisionCount() != 1)
        throw Error("exact case: expected one collision, the engine counted " + std::to_string(world.collisionCount()));
    return {velocity(state[0]), velocity(state[1])};
}

void addVelocityCheck(std::vector<Check>& checks, const std::string& name, double measured, double expected,
                      double incoming) {
    checks.push_back(makeCheck("exact cases", name, measured, expected, std::abs(measured - expected) / incoming,
                               kVelocityTolerance, "|v - v_exact| / |u_in| <= 2e-5"));
}

void addAngleCheck(std::vector<Check>& checks, const std::string& name, double measuredDegrees,
                   double expectedDegrees) {
    checks.push_back(makeCheck("exact cases", name, measuredDegrees, expectedDegrees,
                               std::abs(measuredDegrees - expectedDegrees), kAngleTolerance,
                               "|angle - exact| <= 1e-3 degrees"));
}

void headOn(const EngineDef& def, double m1, double m2, double v1, double expected1, double expected2,
            std::vector<Check>& checks) {
    const auto out = simulatePair(def, approachingPair(m1, m2, v1, 0));
    const std::string name = "head-on, m = " + format("%g", m1) + " and " + format("%g", m2) + ": v";
    addVelocityCheck(checks, name + "1' = " + format("%g", expected1), out[0].x, expected1, v1);
    addVelocityCheck(checks, name + "2' = " + format("%g", expected2), out[1].x, expected2, v1);
}

// Equal masses, target at rest, impact parameter sigma / 2.
void glancing(const EngineDef& def, std::vector<Check>& checks) {
    const double v = 1.0;
    const auto out = simulatePair(def, approachingPair(1, 1, v, 1));
    const double projectileAngle = angleOf(out[0]) / kDegree, targetAngle = angleOf(out[1]) / kDegree;
    addVelocityCheck(checks, "b = sigma/2: target speed = 0.866 v", length(out[1]), std::sqrt(3.0) / 2 * v, v);
    addAngleCheck(checks, "b = sigma/2: target at 30 degrees", targetAngle, 30.0);
    addVelocityCheck(checks, "b = sigma/2: projectile speed = 0.5 v", length(out[0]), 0.5 * v, v);
    addAngleCheck(checks, "b = sigma/2: projectile at -60 degrees", projectileAngle, -60.0);
    addAngleCheck(checks, "b = sigma/2: directions 90 degrees apart", targetAngle - projectileAngle, 90.0);
}

// A projectile of mass 4 on a target of mass 1 at impact parameters across
// the disk: each deflection against the formula, and the largest against
// the bound asin(m2 / m1).
void heavyProjectile(const EngineDef& def, std::vector<Check>& checks) {
    const double m1 = 4.0, m2 = 1.0, bound = std::asin(m2 / m1) / kDegree;
    double largest = 0.0, worst = 0.0;
    for (int k = 1; k <= 9; ++k) {
        const double b = 0.2 * k;  // sigma = 2
        const std::array<Disk, 2> pair = approachingPair(m1, m2, 1, b);
        const double deflection = std::abs(angleOf(simulatePair(def, pair)[0])) / kDegree;
        const double exact = std::abs(angleOf(exactOutcome(pair[0], pair[1])[0])) / kDegree;
        largest = std::max(largest, deflection);
        worst = std::max(worst, std::abs(deflection - exact));
    }
    checks.push_back(makeCheck("exact cases", "m = 4 on 1: deflections at b = 0.1 ... 0.9 sigma", worst, 0.0, worst,
                               kAngleTolerance, "largest |angle - exact| <= 1e-3 degrees"));
    checks.push_back(makeCheck("exact cases", "m = 4 on 1: largest deflection <= asin(1/4) = 14.48 degrees", largest,
                               bound, largest - bound, kAngleTolerance, "deflection - asin(m2/m1) <= 1e-3 degrees"));
}

// One disk between walls: the period of its x motion from the times it
// leaves the left wall (vx turning positive), against 2 (L - 2r) / |v_x|.
void wallBounce(const EngineDef& def, std::vector<Check>& checks) {
    WorldDef box;
    box.width = 10.0f;
    box.height = 7.0f;
    box.dt = 1e-3f;
    box.collisions = CollisionScheme::Pairwise;
    const double vx = 3.0;
    World world = loaded(def, box, {disk(5, 3.5, vx, 0.4, 1)});
    const double period = 2.0 * (box.width - 2.0) / vx;
    std::vector<double> bounces;
    float previous = float(vx);
    const std::uint64_t steps = stepsFor(3.5 * period, box.dt);
    for (std::uint64_t s = 1; s <= steps; ++s) {
        world.step(1);
        const float velocityX = world.disks()[0].velocity.x;
        if (previous < 0.0f && velocityX > 0.0f) bounces.push_back(double(s) * box.dt);
        previous = velocityX;
    }
    const double measured = bounces.size() >= 2 ? (bounces.back() - bounces.front()) / double(bounces.size() - 1) : NAN;
    // The wall reflects at the exact contact time; each bounce time is known
    // to the step that contains it, so the mean period is off by less than dt.
    checks.push_back(makeCheck("exact cases", "wall bounce period 2 (L - 2r) / |v_x|", measured, period,
                               std::abs(measured - period), box.dt, "|T - T_exact| <= dt"));
}

void exactCases(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    headOn(o.backend, 1, 3, 2, -1, 1, checks);
    headOn(o.backend, 3, 1, 1, 0.5, 1.5, checks);
    glancing(o.backend, checks);
    heavyProjectile(o.backend, checks);
    wallBounce(o.backend, checks);
    progress << "  exact cases: done" << std::endl;
}

// --- 5. Conservation per backend -----------------------------------------------

constexpr double kMomentumTolerance = 1e-5;  // of sum m|v|
// Each collision conserves kinetic energy exactly but for the rounding of
// the new float velocities, a relative error of the pair's energy of about
// the unit roundoff 2^-24: the tolerance is that, of one sign, for every
// collision of every disk. (Random signs would give far less.)
constexpr double kRoundingPerCollision = 0x1.0p-24;

std::vector<EngineDef> everyBackend(const EngineDef& chosen) {
    std::vector<EngineDef> defs;
    for (ComputeEngine engine : {ComputeEngine::Cpu, ComputeEngine::OpenClHostGrid, ComputeEngine::OpenClResident})
        if (engineAvailable(engine))
            defs.push_back(EngineDef{engine, engine == ComputeEngine::Cpu ? "" : chosen.device});
    return defs;
}

std::vector<ConservationRun> conservation(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    std::vector<ConservationRun> runs;
    const double packing = 0.3, duration = 10.0;
    const std::uint32_t particles = o.quick ? 1024 : 4096;
    const Box box = periodicBox(particles, packing, o.dt, o.seed);
    for (const EngineDef& def : everyBackend(o.backend)) {
        ConservationRun run;
        run.backend = engineLabel(def.engine);
        run.particles = particles;
        run.packing = packing;
        run.dt = o.dt;
        run.steps = stepsFor(duration, o.dt);
        World world = loaded(def, box);
        run.device = world.deviceName();
        const std::array<double, 2> momentumStart = world.momentum();
        const double energyStart = world.totalEnergy();
        world.step(run.steps);
        run.momentumError = momentumError(momentumStart, world);
        run.energyChange = world.totalEnergy() / energyStart - 1.0;
        const Measurements measured = world.measurements();
        run.lateContacts = measured.lateContacts;
        run.collisionsPerDisk = 2.0 * double(measured.collisions) / particles;
        const double energyTolerance = kRoundingPerCollision * run.collisionsPerDisk;
        runs.push_back(run);
        checks.push_back(makeCheck("conservation", run.backend + ": total momentum", run.momentumError, 0.0,
                                   run.momentumError, kMomentumTolerance, "|P_end - P_start| / sum m|v| <= 1e-5"));
        checks.push_back(makeCheck(
            "conservation", run.backend + ": kinetic energy", run.energyChange, 0.0, std::abs(run.energyChange),
            energyTolerance,
            "|E_end - E_start| / E_start <= 2^-24 x collisions per disk = " + format("%.2g", energyTolerance)));
        progress << "  conservation, " << run.backend << ": momentum " << run.momentumError << ", energy "
                 << run.energyChange << std::endl;
    }
    return runs;
}

// --- 6. Dense gas -------------------------------------------------------------------

constexpr double kDenseEnergyTolerance = 1e-4;  // relative, over the run
constexpr double kOverlapTolerance = 2e-3;      // 1e-3 sigma [length]

DenseResult dense(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    DenseResult result;
    result.packing = 0.7;
    result.particles = o.quick ? 1024 : 4096;
    result.dt = o.dt;
    result.equilibrationTime = o.quick ? 5.0 : 20.0;
    World world = loaded(o.backend, periodicBox(result.particles, result.packing, o.dt, o.seed));
    const std::array<double, 2> momentumStart = world.momentum();
    const double energyStart = world.totalEnergy();
    world.step(stepsFor(result.equilibrationTime, o.dt));
    result.measured = runBlocks(world, 10, o.quick ? 1.0 : 2.0);
    result.energyChange = world.totalEnergy() / energyStart - 1.0;
    result.momentumError = momentumError(momentumStart, world);
    result.maxOverlap = world.maxOverlap();
    result.escaped = world.escapedCount();
    result.rateTolerance = statisticalTolerance(kRateTarget, result.measured.rateRatio.error);
    checks.push_back(makeCheck("dense gas", "energy at eta = 0.7", result.energyChange, 0.0,
                               std::abs(result.energyChange), kDenseEnergyTolerance,
                               "|E_end - E_start| / E_start <= 1e-4 over the run"));
    checks.push_back(makeCheck("dense gas", "every disk finite and in the box", double(result.escaped), 0.0,
                               double(result.escaped), 0.0, "disks outside the box or non-finite = 0"));
    checks.push_back(makeCheck("dense gas", "largest overlap at the end", result.maxOverlap, 0.0, result.maxOverlap,
                               kOverlapTolerance, "max(r_i + r_j - |x_i - x_j|) <= 1e-3 sigma"));
    checks.push_back(rateCheck("dense gas", "collision frequency at eta = 0.7", result.measured.rateRatio,
                               result.rateTolerance, kRateTarget));
    progress << "  dense gas: energy change " << result.energyChange << ", Z " << result.measured.z.mean
             << ", rate ratio " << result.measured.rateRatio.mean << ", late contacts " << result.measured.lateContacts
             << ", max overlap " << result.maxOverlap << std::endl;
    return result;
}

// --- 7. Gravity ------------------------------------------------------------------------

constexpr double kGravityEnergyTolerance = 1e-3;  // relative, over the run

// scenes/gravity_settle.toml at the suite's dt and seed, with the pairwise
// scheme: 800 polydisperse disks of unequal mass released in the upper part
// of a walled box fall and pile up on the floor.
GravityResult gravity(const SuiteOptions& o, std::vector<Check>& checks, std::ostream& progress) {
    SceneFileDef scene;
    scene.world.width = 60.0f;
    scene.world.height = 80.0f;
    scene.world.dt = o.dt;
    scene.world.gravity = Vec2{0.0f, -2.0f};
    scene.world.collisions = CollisionScheme::Pairwise;
    scene.seed = o.seed;
    GroupDef grains;
    grains.name = "grains";
    grains.count = 800;
    grains.radiusMin = 0.5f;
    grains.radiusMax = 1.0f;
    grains.massMin = 0.5f;
    grains.massMax = 2.0f;
    grains.speed = 0.5f;
    grains.region = Region{0.0f, 30.0f, 60.0f, 80.0f};
    scene.groups.push_back(grains);

    GravityResult result;
    result.particles = grains.count;
    result.width = scene.world.width;
    result.height = scene.world.height;
    result.gravity = -scene.world.gravity.y;
    result.dt = o.dt;
    result.duration = 20.0;
    World world = loaded(o.backend, scene.world, makeScene(scene).disks);
    result.kineticStart = world.kineticEnergy();
    result.potentialStart = world.potentialEnergy();
    const double energyStart = world.totalEnergy();
    world.step(stepsFor(result.duration, o.dt));
    result.kineticEnd = world.kineticEnergy();
    result.potentialEnd = world.potentialEnergy();
    result.energyChange = world.totalEnergy() / energyStart - 1.0;
    const Measurements measured = world.measurements();
    result.lateContacts = measured.lateContacts;
    result.maxRounds = measured.maxRounds;
    result.escaped = world.escapedCount();
    checks.push_back(makeCheck("gravity", "K + U under gravity", result.energyChange, 0.0,
                               std::abs(result.energyChange), kGravityEnergyTolerance,
                               "|(K+U)_end - (K+U)_start| / (K+U)_start <= 1e-3 over the run"));
    checks.push_back(makeCheck("gravity", "every disk finite and in the box", double(result.escaped), 0.0,
                               double(result.escaped), 0.0, "disks outside the box or non-finite = 0"));
    progress << "  gravity: K " << result.kineticStart << " -> " << result.kineticEnd << ", U " << result.potentialStart
             << " -> " << result.potentialEnd << ", (K+U) change " << result.energyChange << ", late contacts "
             << result.lateContacts << std::endl;
    return result;
}

// --- 8. The simultaneous scheme, for comparison ---------------------------------------

// One run of the simultaneous scheme from the lattice at kT = 1: the energy
// every `sampleInterval` and its least-squares line, and Z over the second
// half, when the lattice has begun to melt.
SimultaneousRun simultaneousRun(const SuiteOptions& o, std::uint32_t particles, double packing, double dt,
                                double duration, double sampleInterval) {
    World world = loaded(o.backend, periodicBox(particles, packing, float(dt), o.seed, CollisionScheme::Simultaneous));
    const double energyStart = world.totalEnergy();
    std::vector<double> times = {0.0}, energies = {1.0};  // E(t) / E(0)
    const auto sample = [&](int count) {
        for (int k = 0; k < count; ++k) {
            world.step(stepsFor(sampleInterval, dt));
            times.push_back(double(times.size()) * sampleInterval);
            energies.push_back(world.totalEnergy() / energyStart);
        }
    };
    const int samples = int(std::lround(duration / sampleInterval));
    sample(samples / 2);
    world.resetMeasurements();  // Z over the second half, at the mean of its first and last kT
    sample(samples - samples / 2);
    SimultaneousRun run;
    run.packing = packing;
    run.dt = dt;
    run.energyChange = energies.back() - 1.0;
    const Line line = leastSquaresLine(times, energies);
    run.driftRate = line.slope;
    run.wander = line.rmsResidual;
    run.z = world.measurements().compressibility;
    return run;
}

// Measurements only: how the simultaneous scheme's energy drifts with dt and
// density, beside the pairwise scheme's.
SimultaneousResult simultaneous(const SuiteOptions& o, std::ostream& progress) {
    SimultaneousResult result;
    result.particles = o.quick ? 1024 : 4096;
    result.duration = o.quick ? 10.0 : 20.0;
    result.sampleInterval = 1.0;
    const auto add = [&](std::vector<SimultaneousRun>& runs, double packing, double dt) {
        runs.push_back(simultaneousRun(o, result.particles, packing, dt, result.duration, result.sampleInterval));
        progress << "  simultaneous scheme, eta " << packing << ", dt " << dt << ": energy change "
                 << runs.back().energyChange << ", drift " << runs.back().driftRate << " per unit time, Z "
                 << runs.back().z << std::endl;
    };
    for (double dt : {0.02, 0.01, 0.005, 0.0025}) add(result.dtSweep, 0.5, dt);
    for (const ReferenceZ& reference : referenceTable()) add(result.packingSweep, reference.packing, 0.01);
    return result;
}

}  // namespace

void validate(const SuiteOptions& o) {
    std::ostringstream message;
    if (!(std::isfinite(o.dt) && o.dt > 0.0f && o.dt <= kMaxDt)) {
        message << "--dt must be in (0, " << kMaxDt << "], got " << o.dt;
        throw Error(message.str());
    }
    if (o.eosParticles != 0 && (o.eosParticles < kMinEosParticles || o.eosParticles > kMaxEosParticles)) {
        message << "--particles must be in [" << kMinEosParticles << ", " << kMaxEosParticles << "], got "
                << o.eosParticles;
        throw Error(message.str());
    }
}

bool SuiteResult::passed() const {
    return std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.passed; });
}

std::string describeBackend(const EngineDef& def) {
    WorldDef box;
    box.width = box.height = 10.0f;
    box.collisions = CollisionScheme::Pairwise;  // refuses a backend that cannot run the suite
    const World world(onEngine(box, def));
    return (def.engine == ComputeEngine::Cpu ? std::string("cpu")
                                             : "opencl (" + pipelineName(def.engine) + " pipeline)") +
           ": " + world.deviceName();
}

std::string pipelineName(ComputeEngine engine) {
    switch (engine) {
        case ComputeEngine::Cpu: return "";
        case ComputeEngine::OpenClHostGrid: return "host-grid";
        case ComputeEngine::OpenClResident: return "resident";
    }
    return "unknown";
}

std::string engineLabel(ComputeEngine engine) {
    return engine == ComputeEngine::Cpu ? "cpu" : "opencl " + pipelineName(engine);
}

namespace {

// Runs one part; an error of the engine in it (a state gone non-finite at
// too large a dt, say) fails the part with its message instead of ending
// the suite without a report.
template <class Part>
void runPart(const std::string& section, std::vector<Check>& checks, std::ostream& progress, Part part) {
    try {
        part();
    } catch (const Error& e) {
        checks.push_back(makeCheck(section, "the runs complete", NAN, NAN, NAN, 0.0,
                                   std::string("no engine error; got: ") + e.what()));
        progress << "  " << section << ": failed: " << e.what() << std::endl;
    }
}

}  // namespace

SuiteResult runSuite(const SuiteOptions& o, std::ostream& progress) {
    validate(o);
    const auto start = std::chrono::steady_clock::now();
    SuiteResult result;
    result.options = o;
    result.device = describeBackend(o.backend);
    std::vector<Check>& checks = result.checks;
    runPart("equation of state", checks, progress, [&] { result.eos = equationOfState(o, checks, progress); });
    runPart("convergence", checks, progress, [&] { result.convergence = convergence(o, checks, progress); });
    runPart("relaxation", checks, progress, [&] { result.relaxation = relaxation(o, checks, progress); });
    runPart("exact cases", checks, progress, [&] { exactCases(o, checks, progress); });
    runPart("conservation", checks, progress, [&] { result.conservation = conservation(o, checks, progress); });
    runPart("dense gas", checks, progress, [&] { result.dense = dense(o, checks, progress); });
    runPart("gravity", checks, progress, [&] { result.gravity = gravity(o, checks, progress); });
    runPart("simultaneous scheme", checks, progress, [&] { result.simultaneous = simultaneous(o, progress); });
    EventsResult& events = result.events;
    events.device = eventsDevice();
    runPart("events: equation of state", checks, progress,
            [&] { events.eos = eventsEquationOfState(o, checks, progress); });
    runPart("events: dense", checks, progress, [&] { events.dense = eventsDense(o, checks, progress); });
    runPart("events: trajectories", checks, progress,
            [&] { events.trajectories = stepTrajectories(o, checks, progress); });
    runPart("events: schemes", checks, progress, [&] { events.schemes = schemeComparison(o, events.eos, progress); });
    result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace carom::validation
