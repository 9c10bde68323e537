#include "backends/backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <utility>

#include "engine/error_message.h"
#include "engine/exact_sum.h"
#include "engine/parallel.h"
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
    const auto n = static_cast<std::int64_t>(particles.size());
    float maxRadius = 0.0f, minRadius = HUGE_VALF;
    std::int64_t midStep = 0;  // disks with a time or a last partner
#pragma omp parallel for schedule(static) reduction(max : maxRadius) reduction(min : minRadius) \
    reduction(+ : midStep) if (n >= kParallelLength)
    for (std::int64_t i = 0; i < n; ++i) {
        const Particle& p = particles[std::size_t(i)];
        maxRadius = std::max(maxRadius, p.radius);
        minRadius = std::min(minRadius, p.radius);
        midStep += p.time != 0.0f || p.lastPartner != 0u;
    }
    if (world_.skin > kMaxSkinRadii * maxRadius)
        fail("skin ", world_.skin, " is more than ", kMaxSkinRadii, " times the largest radius ", maxRadius,
             " (neighbour lists that long would hold most of the box); allowed: up to ", kMaxSkinRadii * maxRadius,
             ", or 0 (automatic)");
    grid_.geometry = gridGeometryFor(world_, maxRadius, particles.size());
    gridTravel_ = gridTravelAllowance(grid_.geometry, world_.width, world_.height, maxRadius, world_.boundary);
    minRadius_ = minRadius;
    maxRadius_ = maxRadius;
    particleCount_ = particles.size();
    stepNumber_ = step;
    substepsTaken_ = 0;
    batch_ = previousBatch_ = Batch{};
    nonFinite_.reset();
    images_ = images.empty() ? std::vector<Image>(particles.size(), Image{0, 0}) : images;
    if (midStep == 0) {
        load(particles);
    } else {
        // A step starts with every disk at time 0 and no last partner.
        std::vector<Particle> start(particles.size());
        parallelFor(start.size(), [&](std::size_t i) {
            start[i] = particles[i];
            start[i].time = 0.0f;
            start[i].lastPartner = 0u;
        });
        load(start);
    }
    totals_ = ContactTotals{};
    substepsSinceDrain_ = 0;
}

CaromSubstepRule Backend::substepRule() const {
    CaromSubstepRule rule;
    rule.dt = world_.dt;
    rule.gravity = carom_sqrt(world_.gravity.x * world_.gravity.x + world_.gravity.y * world_.gravity.y);
    rule.allowed = HUGE_VALF;
    rule.maxSubsteps = static_cast<unsigned int>(kMaxSubsteps);
    if (world_.collisions == CollisionScheme::Events) return rule;  // exact: no substeps
    if (world_.maxTravel > 0.0f) rule.allowed = world_.maxTravel * minRadius_;
    if (world_.collisions == CollisionScheme::Pairwise)
        rule.allowed = std::min(rule.allowed, gridTravel_ / CAROM_PAIRWISE_SPEED_MARGIN);
    return rule;
}

void Backend::step(std::uint64_t steps) {
    requireFinite();
    stopped_ = false;
    stopAllowed_ = true;
    nextStopCheck_ = std::chrono::steady_clock::now() + kStopCheckInterval;
    const float dt = world_.dt;
    const CaromSubstepRule rule = substepRule();
    if (rule.allowed == HUGE_VALF) {
        // Fixed dt: in batches, so that no tally sums more than kTallySubsteps.
        // Each substep is a step, so a stop between two leaves whole steps.
        std::uint64_t done = 0;
        while (done < steps && !stopped_)
            done += advanceCounted(Batch{substepsTaken_, stepNumber_ + done + 1, 1},
                                   std::min(steps - done, kTallySubsteps), dt);
        awaitSteps();
        requireFinite();
        stepNumber_ += done;
        totals_.steps += done;
        totals_.time += double(dt) * double(done);
        return;
    }
    // Each step is split by the fastest disk at its start
    // (carom_substeps_needed): the same count on every backend.
    for (std::uint64_t done = 0; done < steps && !stopHere();) {
        const float speedSquared = maxSpeedSquared();
        requireFinite();  // the wait for the largest speed may find the step before non-finite
        const unsigned int substeps = carom_substeps_needed(speedSquared, rule);
        if (substeps == 0) throw Error(tooManySubsteps(speedSquared, rule));
        const float substepDt = substeps == 1 ? dt : static_cast<float>(double(dt) / double(substeps));
        std::uint64_t taken = 1;
        if (substeps <= kTallySubsteps / 2 && !(stopCheckSet() && substeps >= kStoppableSubsteps)) {
            // Whole steps at this count, as many as one drain of the tallies
            // allows; the backend may stop at a step that needs another.
            if (substepsSinceDrain_ + substeps > kTallySubsteps) drainCounted();
            const std::uint64_t most = std::min(steps - done, (kTallySubsteps - substepsSinceDrain_) / substeps);
            previousBatch_ = batch_;
            batch_ = Batch{substepsTaken_, stepNumber_ + 1, substeps};
            stopAllowed_ = false;
            taken = advanceWhileSubstepsHold(most, substeps, substepDt, rule);
            stopAllowed_ = true;
            requireFinite();
            countSubsteps(taken * substeps);
        } else {
            substepped(substeps, substepDt);
            if (stopped_) break;
        }
        done += taken;
        stepNumber_ += taken;
        totals_.time += double(dt) * double(taken);
        totals_.steps += taken;
    }
    awaitSteps();
    requireFinite();
}

std::string Backend::tooManySubsteps(float speedSquared, const CaromSubstepRule& rule) const {
    const float speed = carom_sqrt(speedSquared) + rule.gravity * rule.dt;
    const float needed = carom_ceil(speed * rule.dt / rule.allowed);
    return "a step of dt " + std::to_string(rule.dt) + " at the largest speed " + std::to_string(speed) +
           " would need " + (std::isfinite(needed) ? std::to_string(needed) : std::string("unbounded")) +
           " substeps to keep each move within " +
           (world_.maxTravel > 0.0f && rule.allowed == world_.maxTravel * minRadius_
                ? "maxTravel " + std::to_string(world_.maxTravel) + " x radius " + std::to_string(minRadius_)
                : "the pairwise grid's allowance " + std::to_string(rule.allowed)) +
           "; at most " + std::to_string(kMaxSubsteps) +
           " are allowed (the state may have blown up, or use a smaller dt)";
}

std::uint64_t Backend::advanceWhileSubstepsHold(std::uint64_t steps, std::uint64_t substeps, float dt,
                                                const CaromSubstepRule& rule) {
    (void)steps;
    (void)rule;
    advance(substeps, dt);
    return 1;
}

void Backend::substepped(std::uint64_t substeps, float substepDt) {
    const bool keep = stopCheckSet() && substeps >= kStoppableSubsteps;
    // What the step changes besides the state and the tallies, as it began.
    const ContactTotals totals = totals_;
    const std::uint64_t taken = substepsTaken_, sinceDrain = substepsSinceDrain_;
    const Batch batch = batch_, previousBatch = previousBatch_;
    // A drain within the step adds to the images; the tallies it drained
    // come back with the step's start, and are drained again.
    std::vector<Image> images;
    if (keep && sinceDrain + substeps > kTallySubsteps) images = images_;
    if (keep) keepStepStart();
    stopAllowed_ = keep;
    for (std::uint64_t done = 0; done < substeps && !stopped_;)
        done += advanceCounted(Batch{substepsTaken_, stepNumber_ + 1, substeps},
                               std::min(substeps - done, kTallySubsteps), substepDt);
    stopAllowed_ = true;
    if (!stopped_) return;
    awaitSteps();
    totals_ = totals;
    substepsTaken_ = taken;
    substepsSinceDrain_ = sinceDrain;
    batch_ = batch;
    previousBatch_ = previousBatch;
    if (!images.empty()) images_ = std::move(images);
    returnToStepStart();
}

bool Backend::stopHere() {
    if (stopped_) return true;
    if (!stopAllowed_ || !stopCheck_) return false;
    const auto now = std::chrono::steady_clock::now();
    if (!stopCheckCollective()) {
        if (now < nextStopCheck_) return false;
        nextStopCheck_ = now + kStopCheckInterval;
    }
    stopped_ = agreedStop(stopCheck_());
    return stopped_;
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

unsigned int Backend::stepShare(Share& share, const Backend& whole, float dt) {
    const std::size_t n = share.particles.size();
    if (share.tallies.size() != n)
        throw Error("a share of " + std::to_string(n) + " disks with " + std::to_string(share.tallies.size()) +
                    " tallies; allowed: one per disk");
    if (n == 0) {  // nothing to step (and an OpenCL buffer cannot be empty)
        share.lastRounds.clear();
        return 0;
    }
    const unsigned int rounds = stepLoadedShare(n, whole, dt, [&] { loadShare(share.particles, share.tallies); });
    readLastRounds(share.lastRounds);  // first: readShare may leave this backend without the share
    readShare(share.particles, share.tallies);
    return rounds;
}

unsigned int Backend::stepLoadedShare(std::size_t count, const Backend& whole, float dt,
                                      const std::function<void()>& load) {
    grid_.geometry = whole.grid_.geometry;
    gridTravel_ = whole.gridTravel_;
    minRadius_ = whole.minRadius_;
    maxRadius_ = whole.maxRadius_;
    particleCount_ = count;  // images_ stays unused: the wraps stay in the tallies, for the whole world's drain
    substepsTaken_ = 0;
    batch_ = previousBatch_ = Batch{};
    nonFinite_.reset();  // the whole world's backend looks for non-finite disks among its own
    totals_ = ContactTotals{};
    substepsSinceDrain_ = 0;
    load();
    advance(1, dt);
    return totals_.maxRounds;
}

void Backend::loadShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies) {
    load(particles);
    writeTallies(tallies);
}

void Backend::readShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies) {
    readParticles(particles);
    readTallies(tallies);
}

void Backend::refuseShares() const {
    throw Error("the " + device() + " engine does not step a share of a decomposed world; allowed: the CPU engine");
}

void Backend::writeTallies(const std::vector<ContactTally>& tallies) {
    (void)tallies;
    refuseShares();
}

void Backend::readTallies(std::vector<ContactTally>& tallies) {
    (void)tallies;
    throw Error("the " + device() + " engine keeps no tallies per disk");
}

void Backend::readLastRounds(std::vector<unsigned int>& rounds) {
    (void)rounds;
    refuseShares();
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

std::uint64_t Backend::advanceCounted(const Batch& batch, std::uint64_t substeps, float dt) {
    // Drains every kTallySubsteps substeps, wherever the calls begin and end.
    if (substepsSinceDrain_ == kTallySubsteps) drainCounted();
    substeps = std::min(substeps, kTallySubsteps - substepsSinceDrain_);
    previousBatch_ = batch_;
    batch_ = batch;
    const std::uint64_t taken = advance(substeps, dt);
    requireFinite();
    countSubsteps(taken);
    return taken;
}

void Backend::countSubsteps(std::uint64_t substeps) {
    substepsTaken_ += substeps;
    substepsSinceDrain_ += substeps;
    totals_.substeps += substeps;
}

void Backend::drainCounted() {
    drainTallies(totals_);
    substepsSinceDrain_ = 0;
}

const ContactTotals& Backend::contacts() {
    reported_ = totals_;
    if (substepsSinceDrain_ > 0) addUndrained(reported_);
    return reported_;
}

void Backend::addUndrained(ContactTotals& totals) {
    std::vector<ContactTally> tallies;
    readTallies(tallies);
    sumTallies(tallies.data(), tallies.size()).addTo(totals);
}

void Backend::readOwnDisks(std::vector<std::uint32_t>& ids, std::vector<Particle>& particles,
                           std::vector<Image>& images) {
    readParticles(particles);
    images = this->images();
    ids.resize(particles.size());
    parallelFor(ids.size(), [&](std::size_t i) { ids[i] = std::uint32_t(i); });
}

std::vector<Image> Backend::images() {
    std::vector<Image> images = images_;
    if (substepsSinceDrain_ > 0) {  // plus the wraps not yet drained
        std::vector<ContactTally> tallies;
        readTallies(tallies);
        addWraps(images.data(), tallies.data(), images.size());
    }
    return images;
}

void Backend::resetContacts() {
    if (substepsSinceDrain_ > 0) drainCounted();
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

void TallySums::add(const TallySums& other) {
    collisions += other.collisions;
    lateContacts += other.lateContacts;
    virial.add(other.virial);
    for (std::size_t w = 0; w < 4; ++w) wallImpulse[w].add(other.wallImpulse[w]);
}

void TallySums::addTo(ContactTotals& totals) const {
    totals.collisions += collisions;
    totals.lateContacts += lateContacts;
    totals.virial += virial.value();
    for (std::size_t w = 0; w < 4; ++w) totals.wallImpulse[w] += wallImpulse[w].value();
}

TallySums sumTallies(const ContactTally* tallies, std::size_t count) {
    // Each thread's share of the disks' tallies, summed exactly: the same
    // whatever the order and whoever adds them up.
    std::vector<TallySums> shares(static_cast<std::size_t>(parallelThreads()));
    const auto n = static_cast<std::int64_t>(count);
#pragma omp parallel if (n >= kParallelLength)
    {
        TallySums& mine = shares[std::size_t(threadNumber())];
#pragma omp for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) {
            const ContactTally& t = tallies[i];
            mine.collisions += t.collisions;
            mine.lateContacts += t.lateContacts;
            mine.virial.add(t.virial);
            for (int w = 0; w < 4; ++w) mine.wallImpulse[std::size_t(w)].add(t.wallImpulse[w]);
        }
    }
    TallySums all;
    for (const TallySums& share : shares) all.add(share);
    return all;
}

void addWraps(Image* images, const ContactTally* tallies, std::size_t count) {
    parallelFor(count, [&](std::size_t i) {
        for (int axis = 0; axis < 2; ++axis) addToImage(images[i][axis], tallies[i].image[axis]);
    });
}

void clearTallies(ContactTally* tallies, std::size_t count, Image* images) {
    addWraps(images, tallies, count);
    parallelFor(count, [&](std::size_t i) { tallies[i] = ContactTally{}; });
}

void drainTallyArray(ContactTally* tallies, std::size_t count, ContactTotals& totals, Image* images) {
    sumTallies(tallies, count).addTo(totals);
    clearTallies(tallies, count, images);
}

float maxSpeedSquaredOf(const Particle* particles, std::size_t count) {
    float largest = 0.0f;
    const auto n = static_cast<std::int64_t>(count);
#pragma omp parallel for reduction(max : largest) schedule(static) if (n >= kParallelPassLength)
    for (std::int64_t i = 0; i < n; ++i) largest = std::max(largest, carom_speed_squared(particles[i]));
    return largest;
}

}  // namespace carom
