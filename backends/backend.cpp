#include "backends/backend.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "kernels/physics.h"

namespace carom {

namespace {

// A float tally sums at most this many substeps before it is drained into
// the double totals: its rounding error stays below ~1e-4 relative even if
// a particle collided in every one of them.
constexpr std::uint64_t kTallySubsteps = 1024;

}  // namespace

Backend::Backend(const WorldDef& world) : world_(world) { validate(world_); }

void Backend::setParticles(const std::vector<Particle>& particles, std::uint64_t step,
                           const std::vector<Image>& images) {
    validateParticles(particles, world_, "particles");
    if (!images.empty() && images.size() != particles.size())
        throw Error("images: " + std::to_string(images.size()) + " for " + std::to_string(particles.size()) +
                    " particles; allowed: one per particle, or none (all {0, 0})");
    float maxRadius = 0.0f;
    for (const Particle& p : particles) maxRadius = std::max(maxRadius, p.radius);
    grid_.geometry = gridGeometryFor(world_, maxRadius, particles.size());
    gridTravel_ = gridTravelAllowance(grid_.geometry, world_.width, world_.height, maxRadius, world_.boundary);
    minRadius_ = particles.front().radius;
    for (const Particle& p : particles) minRadius_ = std::min(minRadius_, p.radius);
    particleCount_ = particles.size();
    // A step starts with every disk at time 0 and no last partner.
    std::vector<Particle> start = particles;
    for (Particle& p : start) {
        p.time = 0.0f;
        p.lastPartner = 0u;
    }
    stepNumber_ = step;
    substepsTaken_ = 0;
    batch_ = previousBatch_ = Batch{};
    nonFinite_.reset();
    images_ = images.empty() ? std::vector<Image>(particles.size(), Image{0, 0}) : images;
    load(std::move(start));
    totals_ = ContactTotals{};
    substepsSinceDrain_ = 0;
}

double Backend::travelLimit() const {
    double limit = HUGE_VAL;
    if (world_.collisions == CollisionScheme::Events) return limit;  // exact: no substeps
    if (world_.maxTravel > 0.0f) limit = double(world_.maxTravel) * minRadius_;
    if (world_.collisions == CollisionScheme::Pairwise)
        limit = std::min(limit, double(gridTravel_) / kPairwiseSpeedMargin);
    return limit;
}

void Backend::step(std::uint64_t steps) {
    requireFinite();
    const float dt = world_.dt;
    const double allowed = travelLimit();
    if (allowed == HUGE_VAL) {
        // Fixed dt: in batches, so that no tally sums more than kTallySubsteps.
        for (std::uint64_t done = 0; done < steps;) {
            const std::uint64_t batch = std::min(steps - done, kTallySubsteps);
            advanceCounted(Batch{substepsTaken_, stepNumber_ + done + 1, 1}, batch, dt);
            done += batch;
        }
        awaitSteps();
        requireFinite();
        stepNumber_ += steps;
        totals_.steps += steps;
        totals_.time += double(dt) * double(steps);
        return;
    }
    // The fewest equal substeps in which the fastest disk, sped up by gravity
    // for the whole step, moves at most `allowed`. The maximum and this
    // arithmetic are the same on every backend, so the substeps are too.
    const double gravity = std::hypot(double(world_.gravity.x), double(world_.gravity.y));
    for (std::uint64_t s = 0; s < steps; ++s) {
        const double speed = double(maxSpeed()) + gravity * dt;
        requireFinite();  // the wait for the largest speed may find the step before non-finite
        const double needed = std::ceil(speed * dt / allowed);
        if (!(needed <= double(kMaxSubsteps)))
            throw Error(
                "a step of dt " + std::to_string(dt) + " at the largest speed " + std::to_string(speed) +
                " would need " + (std::isfinite(needed) ? std::to_string(needed) : std::string("unbounded")) +
                " substeps to keep each move within " +
                (allowed == double(world_.maxTravel) * minRadius_
                     ? "maxTravel " + std::to_string(world_.maxTravel) + " x radius " + std::to_string(minRadius_)
                     : "the pairwise grid's allowance " + std::to_string(allowed)) +
                "; at most " + std::to_string(kMaxSubsteps) +
                " are allowed (the state may have blown up, or use a smaller dt)");
        const auto substeps = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(needed));
        const float substepDt = substeps == 1 ? dt : static_cast<float>(double(dt) / double(substeps));
        for (std::uint64_t done = 0; done < substeps;) {
            const std::uint64_t batch = std::min(substeps - done, kTallySubsteps);
            advanceCounted(Batch{substepsTaken_, stepNumber_ + 1, substeps}, batch, substepDt);
            done += batch;
        }
        ++stepNumber_;
        totals_.time += dt;
        ++totals_.steps;
    }
    awaitSteps();
    requireFinite();
}

void Backend::recordNonFinite(std::uint64_t substep, std::uint32_t particle) {
    if (nonFinite_) return;
    const Batch& b = substep >= batch_.firstSubstep ? batch_ : previousBatch_;
    nonFinite_ = NonFiniteState{b.firstStep + (substep - b.firstSubstep) / b.substepsPerStep, particle};
}

void Backend::requireFinite() const {
    if (!nonFinite_) return;
    std::ostringstream message;
    message << "the state went non-finite at step " << nonFinite_->step << ": particle " << nonFinite_->particle
            << " (the lowest id of those) has a position or velocity that is not finite";
    if (world_.collisions == CollisionScheme::Simultaneous)
        message << "; the simultaneous scheme is unstable at dt " << world_.dt
                << ": try a smaller dt or the pairwise scheme";
    else
        message << " at dt " << world_.dt << ": try a smaller dt";
    throw Error(message.str());
}

void Backend::recordRounds(unsigned int rounds) { totals_.maxRounds = std::max(totals_.maxRounds, rounds); }

CaromStepParams Backend::stepParams(float dt) const {
    CaromStepParams step;
    step.grid = grid_.geometry;
    step.box = caromBoxOf(world_);
    step.gravityX = world_.gravity.x;
    step.gravityY = world_.gravity.y;
    step.duration = dt;
    step.tolerance = carom_rounding_tolerance(step.box);
    step.count = static_cast<unsigned int>(particleCount_);
    return step;
}

void Backend::advanceCounted(const Batch& batch, std::uint64_t substeps, float dt) {
    if (substepsSinceDrain_ + substeps > kTallySubsteps) {
        drainTallies(totals_);
        substepsSinceDrain_ = 0;
    }
    previousBatch_ = batch_;
    batch_ = batch;
    advance(substeps, dt);
    requireFinite();
    substepsTaken_ += substeps;
    substepsSinceDrain_ += substeps;
    totals_.substeps += substeps;
}

const ContactTotals& Backend::contacts() {
    if (substepsSinceDrain_ > 0) {
        drainTallies(totals_);
        substepsSinceDrain_ = 0;
    }
    return totals_;
}

std::vector<Image> Backend::images() {
    contacts();  // drains the wraps into images_
    return images_;
}

void Backend::resetContacts() {
    contacts();
    totals_ = ContactTotals{};
}

float Backend::maxSpeed() { return std::sqrt(maxSpeedSquared()); }

void Backend::restoreState(const EventEngineState& state) {
    throw Error("an events state of " + std::to_string(state.disks.size()) + " disks; this engine (" + device() +
                ", the " + collisionSchemeName(world_.collisions) +
                " scheme) keeps no exact state: only CollisionScheme::Events does");
}

void Backend::setMotion(float dt, float2 gravity) {
    WorldDef changed = world_;
    changed.dt = dt;
    changed.gravity = gravity;
    validate(changed);
    world_ = changed;
    motionChanged();
}

void drainTallyArray(ContactTally* tallies, std::size_t count, ContactTotals& totals, Image* images) {
    for (std::size_t i = 0; i < count; ++i) {
        ContactTally& t = tallies[i];
        totals.collisions += t.collisions;
        totals.lateContacts += t.lateContacts;
        totals.virial += t.virial;
        for (int w = 0; w < 4; ++w) totals.wallImpulse[w] += t.wallImpulse[w];
        for (int axis = 0; axis < 2; ++axis) addToImage(images[i][axis], t.image[axis]);
        t = ContactTally{};
    }
}

float maxSpeedSquaredOf(const Particle* particles, std::size_t count) {
    float largest = 0.0f;
    const auto n = static_cast<std::int64_t>(count);
#pragma omp parallel for reduction(max : largest) schedule(static) if (n >= kParallelPassLength)
    for (std::int64_t i = 0; i < n; ++i) largest = std::max(largest, carom_speed_squared(particles[i]));
    return largest;
}

}  // namespace carom
