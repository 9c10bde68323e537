#include "backends/cpu_backend.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "kernels/pairwise.h"

namespace carom {

namespace {

// What stepSimultaneous and stepPairwise return when every disk stayed finite.
constexpr std::uint32_t kAllFinite = std::numeric_limits<std::uint32_t>::max();

}  // namespace

CpuBackend::CpuBackend(const WorldDef& world) : Backend(world) {}

std::string CpuBackend::device() const {
#ifdef _OPENMP
    return "CPU, OpenMP with " + std::to_string(omp_get_max_threads()) + " threads";
#else
    return "CPU, single thread (built without OpenMP)";
#endif
}

void CpuBackend::load(std::vector<Particle> particles) {
    const std::size_t n = particles.size();
    if (state_.use_count() > 1 && state_->size() == n)
        std::copy(particles.begin(), particles.end(), state_->begin());
    else
        state_ = std::make_shared<std::vector<Particle>>(std::move(particles));
    tallies_.assign(n, ContactTally{});
    if (world_.collisions == CollisionScheme::Simultaneous) {
        next_->resize(n);
        return;
    }
    events_.resize(n);
    for (auto* list : {&pending_, &nextPending_, &changed_, &dirty_}) list->resize(n);
    for (auto* marks : {&pendingMark_, &changedMark_, &dirtyMark_}) marks->assign(n, 0u);
    epoch_ = 0;
}

void CpuBackend::advance(std::uint64_t substeps, float dt) {
    for (std::uint64_t s = 0; s < substeps; ++s) {
        buildGrid(state_->data(), state_->size(), grid_);
        const std::uint32_t nonFinite =
            world_.collisions == CollisionScheme::Pairwise ? stepPairwise(dt) : stepSimultaneous(dt);
        if (nonFinite != kAllFinite) {
            recordNonFinite(substepsTaken() + s, nonFinite);
            return;
        }
    }
}

std::uint32_t CpuBackend::stepSimultaneous(float dt) {
    const auto count = static_cast<std::int64_t>(state_->size());
    const WorldDef& w = world_;
    const CaromBox box = caromBoxOf(w);
    const Particle* in = state_->data();
    Particle* out = next_->data();
    const unsigned int* sorted = grid_.sortedIndices.data();
    const GridCell* cells = grid_.cells.data();
    ContactTally* tallies = tallies_.data();
    const GridGeometry geometry = grid_.geometry;
    // resolveCollisions and integrate fused per particle: integrate only
    // reads the particle that resolveCollisions just wrote, so this equals
    // two separate passes bit for bit.
    std::uint32_t nonFinite = kAllFinite;
#pragma omp parallel for schedule(static) reduction(min : nonFinite) if (count >= kParallelPassLength)
    for (std::int64_t i = 0; i < count; ++i) {
        const auto id = static_cast<unsigned int>(i);
        carom_resolve_collisions(id, in, sorted, cells, geometry, box, out, tallies);
        carom_integrate_into(id, out, dt, w.gravity.x, w.gravity.y, box, tallies);
        if (!carom_is_finite(out[i])) nonFinite = std::min(nonFinite, id);
    }
    // While a view holds the state's buffer, the step is copied into it, so that the view follows.
    if (state_.use_count() > 1)
        std::copy(next_->begin(), next_->end(), state_->begin());
    else
        std::swap(state_, next_);
    return nonFinite;
}

// Each round's marks carry a new epoch, so no list needs clearing; when the
// counter wraps, the marks are cleared once.
unsigned int CpuBackend::nextEpoch() {
    if (++epoch_ == 0) {
        for (auto* marks : {&pendingMark_, &changedMark_, &dirtyMark_}) std::fill(marks->begin(), marks->end(), 0u);
        epoch_ = 1;
    }
    return epoch_;
}

std::uint32_t CpuBackend::stepPairwise(float dt) {
    const auto count = static_cast<std::int64_t>(state_->size());
    const CaromStepParams step = stepParams(dt);
    Particle* state = state_->data();
    // State by id, so a disk's slot is its id: sortedIndices serves as both.
    const unsigned int* sorted = grid_.sortedIndices.data();
    const unsigned int* cellOf = grid_.cellOf.data();
    const GridCell* cells = grid_.cells.data();
    ContactTally* tallies = tallies_.data();
    CaromEvent* events = events_.data();
    unsigned int pendingCount = 0, nextCount = 0, changedCount = 0, dirtyCount = 0;
    auto list = [](std::vector<unsigned int>& items, unsigned int& count, std::vector<unsigned int>& marks) {
        return CaromList{items.data(), &count, marks.data()};
    };
    // Runs pass(k) for the first `length` entries of `items`, in parallel when it pays.
    auto forEach = [](const unsigned int* items, unsigned int length, auto&& pass) {
        const auto n = static_cast<std::int64_t>(length);
#pragma omp parallel for schedule(static) if (n >= kParallelPassLength)
        for (std::int64_t e = 0; e < n; ++e) pass(items[e]);
    };

    // Every disk's earliest event: forward over each pair once, then the
    // disks met from behind look at all their neighbours.
    unsigned int epoch = nextEpoch();
    CaromList changed = list(changed_, changedCount, changedMark_);
    CaromList dirty = list(dirty_, dirtyCount, dirtyMark_);
    CaromList pending = list(pending_, pendingCount, pendingMark_);
#pragma omp parallel for schedule(static) if (count >= kParallelPassLength)
    for (std::int64_t k = 0; k < count; ++k)
        carom_find_event(static_cast<unsigned int>(k), state, sorted, sorted, cellOf, cells, step, events,
                         CAROM_SEARCH_FORWARD, changed, dirty, pending, epoch);
    forEach(dirty_.data(), dirtyCount, [&](unsigned int k) {
        carom_find_event(k, state, sorted, sorted, cellOf, cells, step, events, CAROM_SEARCH_ALL, changed, dirty,
                         pending, epoch);
    });

    unsigned int rounds = 0;
    for (unsigned int round = 1; pendingCount > 0 && round <= kMaxPairwiseRounds; ++round) {
        epoch = nextEpoch();
        nextCount = changedCount = dirtyCount = 0;
        CaromList next = list(nextPending_, nextCount, pendingMark_);
        forEach(pending_.data(), pendingCount, [&](unsigned int k) {
            carom_resolve_event(k, state, sorted, sorted, events, step, tallies, changed, next, epoch);
        });
        forEach(changed_.data(), changedCount, [&](unsigned int k) {
            carom_find_event(k, state, sorted, sorted, cellOf, cells, step, events, CAROM_SEARCH_CHANGED, changed,
                             dirty, next, epoch);
        });
        forEach(dirty_.data(), dirtyCount, [&](unsigned int k) {
            carom_find_event(k, state, sorted, sorted, cellOf, cells, step, events, CAROM_SEARCH_ALL, changed, dirty,
                             next, epoch);
        });
        if (changedCount > 0) rounds = round;
        std::swap(pending_, nextPending_);
        pendingCount = nextCount;
    }
    recordRounds(rounds);
    std::uint32_t nonFinite = kAllFinite;
#pragma omp parallel for schedule(static) reduction(min : nonFinite) if (count >= kParallelPassLength)
    for (std::int64_t i = 0; i < count; ++i) {
        state[i] = carom_finish_step(state[i], step, &tallies[i]);
        if (!carom_is_finite(state[i])) nonFinite = std::min(nonFinite, static_cast<std::uint32_t>(i));
    }
    return nonFinite;
}

}  // namespace carom
