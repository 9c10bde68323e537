#include "backends/cpu.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <limits>
#include <mutex>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "engine/parallel.h"
#include "kernels/pairwise.h"

namespace carom {

namespace {

// What stepSimultaneous and stepPairwise return when every disk stayed finite.
constexpr std::uint32_t kAllFinite = std::numeric_limits<std::uint32_t>::max();

// A substep runs in one OpenMP parallel region (each region is a fork and
// a join; a pairwise step had a dozen, and the largest speed another).
// Within it, each pass is shared out in chunks that the threads claim as
// they come, and a pass is over when all its items are done, not when every
// thread has arrived: a thread that other processes keep off its core takes
// fewer chunks or none, and the others wait for it only while it holds a
// chunk. The wait for a pass to finish is chosen here rather than left to
// the OpenMP runtime, whose default spins for milliseconds (libgomp) and
// which can only be changed through OMP_WAIT_POLICY before the program
// starts: a waiting thread spins for kSpin, long enough for running
// partners to finish a chunk, then sleeps on a condition variable until the
// pass ends, leaving its core to the threads it waits for. What each item
// computes does not depend on which thread runs it, so the results are the
// same bits for any number of threads and any schedule.
constexpr std::chrono::microseconds kSpin{50};

template <std::size_t Passes>
class PassProgress {
public:
    PassProgress() {
        for (std::size_t p = 0; p < Passes; ++p) {
            next_[p].store(0, std::memory_order_relaxed);
            done_[p].store(0, std::memory_order_relaxed);
        }
    }

    // Runs item(e) for the chunks of pass p (e < length) that this thread claims.
    template <class Item>
    void share(std::size_t p, std::size_t length, std::size_t chunk, Item&& item) {
        for (;;) {
            const std::size_t begin = next_[p].fetch_add(chunk, std::memory_order_relaxed);
            if (begin >= length) return;
            const std::size_t end = std::min(length, begin + chunk);
            for (std::size_t e = begin; e < end; ++e) item(e);
            if (done_[p].fetch_add(end - begin, std::memory_order_acq_rel) + (end - begin) == length) {
                { const std::lock_guard<std::mutex> lock(mutex_); }
                if (sleepers_.load(std::memory_order_acquire) > 0) wake_.notify_all();
            }
        }
    }

    // Returns once every item of pass p is done (what they wrote is visible).
    void await(std::size_t p, std::size_t length) {
        auto finished = [&] { return done_[p].load(std::memory_order_acquire) >= length; };
        if (finished()) return;
        const auto until = std::chrono::steady_clock::now() + kSpin;
        for (unsigned spins = 1;; ++spins) {
            if (finished()) return;
            if (spins % 64 == 0 && std::chrono::steady_clock::now() >= until) break;
        }
        std::unique_lock<std::mutex> lock(mutex_);
        sleepers_.fetch_add(1, std::memory_order_acq_rel);
        wake_.wait(lock, finished);
        sleepers_.fetch_sub(1, std::memory_order_acq_rel);
    }

    // This thread has reached the end of the passes (pass p counts arrivals).
    void arrive(std::size_t p, std::size_t threads) {
        if (done_[p].fetch_add(1, std::memory_order_acq_rel) + 1 == threads) {
            { const std::lock_guard<std::mutex> lock(mutex_); }
            if (sleepers_.load(std::memory_order_acquire) > 0) wake_.notify_all();
        }
    }

    // share, then await.
    template <class Item>
    void run(std::size_t p, std::size_t length, std::size_t chunk, Item&& item) {
        share(p, length, chunk, item);
        await(p, length);
    }

private:
    std::array<std::atomic<std::size_t>, Passes> next_, done_;
    std::atomic<int> sleepers_{0};
    std::mutex mutex_;
    std::condition_variable wake_;
};

// The passes over every disk (the search, the finish, the simultaneous
// step) are cut into a few large chunks per thread: contiguous runs of
// disks keep their neighbours in a core's cache (at N = 10^4 on 2 threads,
// chunks of N/8 made a pairwise step 10 % faster than chunks of 256), while
// a thread that loses its core still leaves most of the pass to the others.
constexpr std::size_t kChunksPerThread = 4;
constexpr std::size_t kMinChunk = 256;
std::size_t chunkFor(std::size_t count, int threads) {
    const std::size_t chunks = kChunksPerThread * static_cast<std::size_t>(std::max(threads, 1));
    return std::max(kMinChunk, (count + chunks - 1) / chunks);
}
// The rounds' passes: lists of disks, in chunks of this many.
constexpr std::size_t kRoundChunk = 64;
// A pairwise step's rounds run on one thread of the team while fewer disks
// than this are pending (a dozen events at N = 10^4 take less than the
// waits of a shared round would).
constexpr unsigned int kParallelRoundLength = 1024;

// Per thread: the largest speed squared and the lowest non-finite id of its
// share of a step's last pass (own cache line).
struct alignas(64) ThreadResult {
    float maxSpeedSquared = 0.0f;
    float maxDisplacementSquared = 0.0f;  // pairwise with neighbour lists: since they were built
    std::uint32_t nonFinite = kAllFinite;
};

// The grid's phases, each shared among the region's threads (the same grid,
// bit for bit, whoever runs which block).
template <class Progress>
void buildGridInRegion(Progress& passes, std::size_t firstPass, GridBuilder& builder, Grid& grid,
                       const Particle* particles, std::size_t count) {
    const auto blocks = static_cast<std::size_t>(builder.blocks());
    for (int phase = 0; phase < GridBuilder::kPhases; ++phase)
        passes.run(firstPass + std::size_t(phase), blocks, 1,
                   [&](std::size_t b) { builder.run(phase, static_cast<int>(b), particles, count, grid); });
}

// The threads' shares of a step's last pass, combined: the largest speed
// (max is exact in any order) and the lowest id left non-finite.
ThreadResult combined(const std::vector<ThreadResult>& results) {
    ThreadResult all;
    for (const ThreadResult& r : results) {
        all.nonFinite = std::min(all.nonFinite, r.nonFinite);
        all.maxSpeedSquared = std::max(all.maxSpeedSquared, r.maxSpeedSquared);
        all.maxDisplacementSquared = std::max(all.maxDisplacementSquared, r.maxDisplacementSquared);
    }
    return all;
}

int teamThreads() {
#ifdef _OPENMP
    return omp_get_num_threads();
#else
    return 1;
#endif
}

// The end of a substep's region: every thread arrives, and the threads wait
// (spinning briefly, then asleep) until all have. The OpenMP join that
// follows then finds them all there, rather than spinning, as libgomp's
// join does, for a thread that waits for the very core the spinning holds.
template <class Progress>
void arriveAll(Progress& passes, std::size_t p) {
    const auto team = static_cast<std::size_t>(teamThreads());
    passes.arrive(p, team);
    passes.await(p, team);
}

}  // namespace

CpuBackend::CpuBackend(const WorldDef& world) : Backend(world) {}

std::string CpuBackend::device() const {
#ifdef _OPENMP
    return "CPU, OpenMP with " + std::to_string(omp_get_max_threads()) + " threads";
#else
    return "CPU, single thread (built without OpenMP)";
#endif
}

int CpuBackend::teamSize() const {
#ifdef _OPENMP
    if (static_cast<std::int64_t>(state_->size()) >= kParallelPassLength && teamChoice_.team())
        return std::max(1, omp_get_max_threads());
#endif
    return 1;
}

void CpuBackend::TeamChoice::record(bool team, double seconds) {
    elapsed_ += seconds;
    if (!trial_) {
        currentSeconds_ += seconds;
        ++currentSteps_;
        // Far slower than when it was chosen (other work started): try the other now.
        const bool worse = currentSteps_ >= kTrialSteps && currentSeconds_ / currentSteps_ > 1.5 * expected_;
        if ((currentSteps_ >= kFirstTrial && elapsed_ >= nextTrial_) || worse) {
            trial_ = true;
            trialSeconds_ = trialCompared_ = 0.0;
            trialSteps_ = 0;
        }
        return;
    }
    if (team == teamBest_) return;  // not a trial substep
    // The current choice's mean substep since the last trial (many substeps:
    // the rare long ones, a thread waiting for a time slice, count).
    const double mean = currentSeconds_ / currentSteps_;
    trialSeconds_ += seconds;
    if (trialSteps_++ > 0) trialCompared_ += seconds;  // the first wakes the team, or leaves it
    // A trial substep far slower than the current choice's ends the trial at once.
    const bool hopeless = trialSteps_ > 1 && seconds > 3.0 * mean;
    if (trialSteps_ < kTrialSteps && !hopeless) return;
    trial_ = false;
    const bool won = !hopeless && trialCompared_ / (trialSteps_ - 1) < 0.9 * mean;
    const double spacing = 50.0 * trialSeconds_;
    expected_ = won ? trialCompared_ / (trialSteps_ - 1) : mean;
    if (won) {
        teamBest_ = !teamBest_;
        wait_ = spacing;
    } else {
        wait_ = std::min(std::max(2.0 * wait_, spacing), std::max(1.0, spacing));
    }
    currentSeconds_ = 0.0;
    currentSteps_ = 0;
    nextTrial_ = elapsed_ + wait_;
}

void CpuBackend::load(const std::vector<Particle>& particles) {
    const std::size_t n = particles.size();
    if (state_.use_count() == 1 || (state_.use_count() > 1 && state_->size() == n))
        state_->assign(particles.begin(), particles.end());  // its buffer again (a view's, where one holds it)
    else
        state_ = std::make_shared<std::vector<Particle>>(particles);
    tallies_.assign(n, ContactTally{});
    prepare(n);
}

void CpuBackend::loadShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies) {
    if (state_.use_count() > 1) state_ = std::make_shared<std::vector<Particle>>();  // a view keeps the old one
    state_->swap(particles);
    tallies_.swap(tallies);
    prepare(state_->size());
}

void CpuBackend::prepare(std::size_t n) {
    speedKnown_ = false;
    teamChoice_ = TeamChoice{};  // measured afresh for these disks
    if (world_.collisions == CollisionScheme::Simultaneous) {
        next_->resize(n);
        return;
    }
    events_.resize(n);
    lists_.clear();
    listsTooLong_ = false;
    identity_.resize(n);
    parallelFor(n, [&](std::size_t i) { identity_[i] = static_cast<unsigned int>(i); });
    startCells_.resize(n);
    for (auto* list : {&pending_, &nextPending_, &changed_, &dirty_}) list->resize(n);
    for (auto* marks : {&pendingMark_, &changedMark_, &dirtyMark_}) marks->assign(n, 0u);
    epoch_ = 0;
}

void CpuBackend::keepStepStart() {
    stepStart_ = *state_;
    stepStartTallies_ = tallies_;
}

void CpuBackend::returnToStepStart() {
    std::copy(stepStart_.begin(), stepStart_.end(), state_->begin());  // into the views' buffer
    tallies_ = stepStartTallies_;
    speedKnown_ = false;
    lists_.clear();  // their displacement was measured from a later state
}

std::uint64_t CpuBackend::advance(std::uint64_t substeps, float dt) {
#ifdef _OPENMP
    const bool choose = static_cast<std::int64_t>(state_->size()) >= kParallelPassLength && omp_get_max_threads() > 1;
#else
    const bool choose = false;
#endif
    for (std::uint64_t s = 0; s < substeps; ++s) {
        if (stopHere()) return s;
        const bool team = teamChoice_.team();
        const auto start = std::chrono::steady_clock::now();
        const std::uint32_t nonFinite =
            world_.collisions == CollisionScheme::Pairwise ? stepPairwise(dt) : stepSimultaneous(dt);
        if (choose)
            teamChoice_.record(team, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        if (nonFinite != kAllFinite) {
            speedKnown_ = false;
            lists_.clear();
            recordNonFinite(substepsTaken() + s, nonFinite);
            return s + 1;
        }
    }
    return substeps;
}

std::uint32_t CpuBackend::stepSimultaneous(float dt) {
    const std::size_t count = state_->size();
    const WorldDef& w = world_;
    const CaromBox box = caromBoxOf(w);
    const int threads = teamSize();
    gridBuilder_.prepare(count, grid_, threads);
    const Particle* in = state_->data();
    Particle* out = next_->data();
    const unsigned int* sorted = grid_.sortedIndices.data();
    const GridCell* cells = grid_.cells.data();
    ContactTally* tallies = tallies_.data();
    const GridGeometry geometry = grid_.geometry;
    std::vector<ThreadResult> results(static_cast<std::size_t>(threads));
    PassProgress<GridBuilder::kPhases + 2> passes;
    // One region: the grid's phases, then resolveCollisions and integrate
    // fused per particle (integrate only reads the particle that
    // resolveCollisions just wrote, so this equals two separate passes bit
    // for bit).
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
        buildGridInRegion(passes, 0, gridBuilder_, grid_, in, count);
        ThreadResult mine;
        passes.share(GridBuilder::kPhases, count, chunkFor(count, threads), [&](std::size_t i) {
            const auto id = static_cast<unsigned int>(i);
            carom_resolve_collisions(id, in, sorted, cells, geometry, box, out, tallies);
            carom_integrate_into(id, out, dt, w.gravity.x, w.gravity.y, box, tallies);
            if (!carom_is_finite(out[i])) mine.nonFinite = std::min(mine.nonFinite, std::uint32_t(id));
            mine.maxSpeedSquared = std::max(mine.maxSpeedSquared, carom_speed_squared(out[i]));
        });
        results[static_cast<std::size_t>(threadNumber())] = mine;
        arriveAll(passes, GridBuilder::kPhases + 1);
    }
    // While a view holds the state's buffer, the step is copied into it, so that the view follows.
    if (state_.use_count() > 1)
        std::copy(next_->begin(), next_->end(), state_->begin());
    else
        std::swap(state_, next_);
    const ThreadResult all = combined(results);
    maxSpeedSquared_ = all.maxSpeedSquared;
    speedKnown_ = true;
    return all.nonFinite;
}

std::uint32_t CpuBackend::stepPairwise(float dt) {
    const std::size_t count = state_->size();
    const CaromStepParams step = stepParams(dt);
    const int threads = teamSize();
    const std::size_t chunk = chunkFor(count, threads);
    const ListPlan plan = planLists(dt, threads, chunk);
    if (!plan.hold && !plan.build) gridBuilder_.prepare(count, grid_, threads);  // only the grid's searches allocate it
    // The step's epochs, epoch_ + 1 .. epoch_ + 1 + kMaxPairwiseRounds, must
    // not wrap; when they would, the marks are cleared once.
    if (epoch_ > std::numeric_limits<unsigned int>::max() - (kMaxPairwiseRounds + 1)) {
        for (auto* marks : {&pendingMark_, &changedMark_, &dirtyMark_}) std::fill(marks->begin(), marks->end(), 0u);
        epoch_ = 0;
    }
    const unsigned int firstEpoch = epoch_ + 1;
    Particle* state = state_->data();
    ContactTally* tallies = tallies_.data();
    CaromEvent* events = events_.data();
    // The list lengths of the first search (index 0) and of each round, so
    // that no thread has to reset one while another may still read it; the
    // pending lists alternate: round r reads pendingLists[(r - 1) % 2] and
    // fills pendingLists[r % 2].
    std::array<unsigned int, kMaxPairwiseRounds + 1> pendingCount{}, changedCount{};
    unsigned int dirtyCount = 0;  // the first search's dirty list
    std::vector<unsigned int>* pendingLists[2] = {&pending_, &nextPending_};
    auto listOf = [](std::vector<unsigned int>& items, unsigned int& length, std::vector<unsigned int>& marks) {
        return CaromList{items.data(), &length, marks.data()};
    };
    // The substep's passes, each with its own counters: a build of the
    // lists (their grid's phases, collect, sum, place), the grid's phases (or
    // with the lists the start cells), the forward search, the first dirty
    // search, two per round, the rest of the rounds on one thread, the
    // finish.
    constexpr std::size_t kCollectPass = GridBuilder::kPhases, kSumPass = kCollectPass + 1, kPlacePass = kSumPass + 1,
                          kGridPass = kPlacePass + 1, kForwardPass = kGridPass + GridBuilder::kPhases,
                          kDirtyPass = kForwardPass + 1, kTailPass = kDirtyPass + 1 + 2 * kMaxPairwiseRounds,
                          kFinishPass = kTailPass + 1, kEnd = kFinishPass + 1;
    PassProgress<kEnd + 1> passes;
    std::vector<ThreadResult> results(static_cast<std::size_t>(threads));
    unsigned int roundsUsed = 0;  // rounds run

#pragma omp parallel num_threads(threads) if (threads > 1)
    {
        if (plan.build) {
            buildGridInRegion(passes, 0, lists_.builder(), lists_.grid(), state, count);
            passes.run(kCollectPass, count, chunk, [&](std::size_t i) { lists_.collect(i); });
            passes.run(kSumPass, 1, 1, [&](std::size_t) { lists_.sum(); });
            passes.run(kPlacePass, lists_.chunks(), 1, [&](std::size_t c) { lists_.place(c); });
        }
        // Every thread reads the same after the lists' last pass. Lists too
        // long for their offsets leave the substep undone: it starts over on
        // the grid (below).
        const bool listed = plan.hold || (plan.build && lists_.built());
        if (plan.build && !listed) {
            arriveAll(passes, kEnd);
        } else {
            if (!listed) buildGridInRegion(passes, kGridPass, gridBuilder_, grid_, state, count);
            // The state is by id. Without the lists a disk's sorted position
            // k gives sortedIndices[k], both its slot and its id; with them
            // the positions are the ids (identity_), and no slots are looked
            // up (carom_slot).
            const unsigned int* sorted = listed ? identity_.data() : grid_.sortedIndices.data();
            const unsigned int* slots = listed ? nullptr : sorted;
            const CaromNeighbours neighbours =
                listed ? CaromNeighbours{startCells_.data(), grid_.cells.data(), lists_.starts(), lists_.starts() + 1,
                                         lists_.list()}
                       : carom_grid_neighbours(grid_.cellOf.data(), grid_.cells.data());

            // Every disk's earliest event: forward over each pair once, then the
            // disks met from behind look at all their neighbours.
            const CaromList firstChanged = listOf(changed_, changedCount[0], changedMark_);
            const CaromList firstDirty = listOf(dirty_, dirtyCount, dirtyMark_);
            const CaromList firstPending = listOf(pending_, pendingCount[0], pendingMark_);
            passes.run(kForwardPass, count, chunk, [&](std::size_t k) {
                // With the lists, the cell disk k starts in (the grid's cellOf,
                // without the grid), for the walls it can reach: only its own
                // searches read it.
                if (listed)
                    startCells_[k] = static_cast<unsigned int>(carom_cell_index(state[k].position, grid_.geometry));
                carom_find_event(static_cast<unsigned int>(k), state, slots, sorted, neighbours, step, events,
                                 CAROM_SEARCH_FORWARD, firstChanged, firstDirty, firstPending, firstEpoch);
            });
            auto dirtySearch = [&](std::size_t e) {
                carom_find_event(dirty_[e], state, slots, sorted, neighbours, step, events, CAROM_SEARCH_ALL,
                                 firstChanged, firstDirty, firstPending, firstEpoch);
            };

            // Round r: resolve, then the changed disks search (and search the
            // dirty ones they find); each pass shared among the team, or run by
            // the calling thread alone.
            auto runRound = [&](unsigned int round, bool shared) {
                const unsigned int epoch = firstEpoch + round;
                const CaromList changed = listOf(changed_, changedCount[round], changedMark_);
                const CaromList dirty = {nullptr, nullptr, dirtyMark_.data()};  // its marks only
                const CaromList next = listOf(*pendingLists[round % 2], pendingCount[round], pendingMark_);
                const unsigned int* pending = pendingLists[(round - 1) % 2]->data();
                const std::size_t pass = kDirtyPass + 1 + 2 * std::size_t(round - 1);
                auto run = [&](std::size_t p, std::size_t length, auto&& item) {
                    if (shared)
                        passes.run(p, length, kRoundChunk, item);
                    else
                        for (std::size_t e = 0; e < length; ++e) item(e);
                };
                run(pass, pendingCount[round - 1], [&](std::size_t e) {
                    carom_resolve_event(pending[e], state, slots, sorted, events, step, tallies, changed, next, epoch);
                });
                run(pass + 1, changedCount[round], [&](std::size_t e) {
                    carom_find_event(changed_[e], state, slots, sorted, neighbours, step, events, CAROM_SEARCH_CHANGED,
                                     changed, dirty, next, epoch);
                });
            };
            // The rest of the rounds, on the thread that claims them: while few
            // disks are pending (a dozen events at N = 10^4), a round costs less
            // than the waits of a shared one.
            auto tail = [&](unsigned int round, bool firstDirtySearch) {
                if (firstDirtySearch)
                    for (std::size_t e = 0; e < dirtyCount; ++e) dirtySearch(e);
                for (; round <= kMaxPairwiseRounds && pendingCount[round - 1] > 0; ++round) runRound(round, false);
                roundsUsed = round - 1;
            };
            // Every thread reads the same lengths once a pass is over, so all take the same path.
            if (threads == 1 || dirtyCount < kParallelRoundLength) {
                passes.run(kTailPass, 1, 1, [&](std::size_t) { tail(1, true); });
            } else {
                passes.run(kDirtyPass, dirtyCount, kRoundChunk, dirtySearch);
                unsigned int round = 1;
                for (; round <= kMaxPairwiseRounds && pendingCount[round - 1] >= kParallelRoundLength; ++round) {
                    runRound(round, true);
                }
                passes.run(kTailPass, 1, 1, [&](std::size_t) { tail(round, false); });
            }

            // Every disk flies to the end of the step; its largest speed is the
            // next step's (maxSpeedSquared).
            ThreadResult mine;
            passes.share(kFinishPass, count, chunk, [&](std::size_t i) {
                state[i] = carom_finish_step(state[i], step, &tallies[i]);
                if (!carom_is_finite(state[i]))
                    mine.nonFinite = std::min(mine.nonFinite, static_cast<std::uint32_t>(i));
                mine.maxSpeedSquared = std::max(mine.maxSpeedSquared, carom_speed_squared(state[i]));
                if (listed)
                    mine.maxDisplacementSquared =
                        std::max(mine.maxDisplacementSquared, lists_.displacementSquared(i, state[i].position));
            });
            results[static_cast<std::size_t>(threadNumber())] = mine;
            arriveAll(passes, kEnd);
        }
    }
    if (plan.build && !lists_.built()) {
        listsTooLong_ = true;
        return stepPairwise(dt);
    }
    epoch_ = firstEpoch + roundsUsed;
    substepEpoch_ = firstEpoch;
    unsigned int roundsChanged = 0;  // the last round that changed a disk
    for (unsigned int round = 1; round <= roundsUsed; ++round)
        if (changedCount[round] > 0) roundsChanged = round;
    recordRounds(roundsChanged);
    const ThreadResult all = combined(results);
    maxSpeedSquared_ = all.maxSpeedSquared;
    maxDisplacementSquared_ = all.maxDisplacementSquared;
    listBuilds_ += plan.build;
    speedKnown_ = true;
    return all.nonFinite;
}

void CpuBackend::readLastRounds(std::vector<unsigned int>& rounds) {
    rounds.assign(state_->size(), 0u);
    if (world_.collisions != CollisionScheme::Pairwise) return;
    // Round r marks the disks it changed with the epoch substepEpoch_ + r.
    parallelFor(rounds.size(), [&](std::size_t i) {
        if (changedMark_[i] > substepEpoch_) rounds[i] = changedMark_[i] - substepEpoch_;
    });
}

CpuBackend::ListPlan CpuBackend::planLists(float dt, int threads, std::size_t chunk) {
    if (!useLists_ || listsTooLong_) return {};
    // At most gridTravel(): the substeps are sized so.
    const float travel = carom_substep_travel(maxSpeedSquared(), std::hypot(world_.gravity.x, world_.gravity.y), dt);
    if (lists_.hold(maxDisplacementSquared_, travel)) return {true, false};
    // Lists built now with a skin this substep can cross (a small WorldDef::skin) would not hold: the grid then.
    const float skin = NeighbourLists::skinFor(world_.skin, maxRadius_, gridTravel());
    if (!carom_lists_cover(skin, 0.0f, travel)) {
        lists_.clear();
        return {};
    }
    maxDisplacementSquared_ = 0.0f;
    return {false, lists_.begin(state_->data(), state_->size(), maxRadius_, skin, caromBoxOf(world_), threads, chunk)};
}

}  // namespace carom
