// The OpenMP CPU backend: the shared grid builder, then the collision scheme
// in parallel loops over particles: resolveCollisions and integrate from
// kernels/physics.h in one loop (simultaneous), or the rounds of
// kernels/pairwise.h (pairwise). The all-pairs baseline of `carom bench`
// (app/bench/all_pairs_cpu.h) derives from it.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include "backends/backend.h"
#include "engine/neighbour_lists.h"

namespace carom {

class CpuBackend : public Backend {
public:
    explicit CpuBackend(const WorldDef& world);

    std::string device() const override;
    bool exactArithmetic() const override { return true; }

    void readParticles(std::vector<Particle>& particles) override { particles = *state_; }
    // Whether pairwise substeps may search neighbour lists (the default)
    // instead of the grid: the same bits either way, which the tests check.
    void useNeighbourLists(bool use) {
        useLists_ = use;
        lists_.clear();
    }
    // How many times the lists were built since the backend was made.
    std::uint64_t neighbourListBuilds() const { return listBuilds_; }
    std::shared_ptr<const std::vector<Particle>> sharedState() override { return state_; }

protected:
    // The state before the step, shared with World::diskMemory's views: a
    // view keeps its buffer alive, and while one does, the steps and loads of
    // the same number of disks write into that buffer (views follow them).
    std::shared_ptr<std::vector<Particle>> state_ = std::make_shared<std::vector<Particle>>();
    // Simultaneous: written by the step, then swapped in (copied in while a view holds state_).
    std::shared_ptr<std::vector<Particle>> next_ = std::make_shared<std::vector<Particle>>();
    std::vector<ContactTally> tallies_;  // by particle id
    // keepStepStart's copies of *state_ and tallies_.
    std::vector<Particle> stepStart_;
    std::vector<ContactTally> stepStartTallies_;

private:
    void load(const std::vector<Particle>& particles) override;
    // Swaps the share in and out: a copy of each would cost a share's bytes twice a substep.
    void loadShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies) override;
    void readShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies) override {
        particles.swap(*state_);
        tallies.swap(tallies_);
    }
    void prepare(std::size_t n);  // load's: the scheme's buffers for n disks, the tallies left alone
    std::uint64_t advance(std::uint64_t substeps, float dt) override;
    void keepStepStart() override;
    void returnToStepStart() override;
    // The step that wrote the state also took its largest speed (max is
    // exact in any order: the same bits as maxSpeedSquaredOf).
    float maxSpeedSquared() override {
        return speedKnown_ ? maxSpeedSquared_ : maxSpeedSquaredOf(state_->data(), state_->size());
    }
    void readTallies(std::vector<ContactTally>& tallies) override { tallies = tallies_; }
    void readLastRounds(std::vector<unsigned int>& rounds) override;
    void drainTallies(ContactTotals& totals) override {
        drainTallyArray(tallies_.data(), tallies_.size(), totals, images_.data());
    }
    // One substep each; they return the lowest id of a disk the substep left
    // non-finite, or kAllFinite.
    std::uint32_t stepSimultaneous(float dt);
    std::uint32_t stepPairwise(float dt);
    // What a pairwise substep of dt does with the neighbour lists: search
    // them where they hold, else build them afresh in its region (the team
    // of `threads`, in chunks of `chunk` disks) where they can be; neither
    // searches the grid.
    struct ListPlan {
        bool hold = false, build = false;
    };
    ListPlan planLists(float dt, int threads, std::size_t chunk);
    // The threads of the next substep's team: one below kParallelPassLength
    // disks, or while one thread has lately been faster (teamChoice_).
    int teamSize() const;

    // Whether the substeps run on the whole team or on one thread: whichever
    // was faster lately, measured (the results are the same bits either
    // way). While other processes keep the cores busy, a team's threads
    // share cores with them and wait for each other (a thread that loses
    // its core in the middle of its chunk holds the pass up for a time
    // slice), and one thread on a core of its own is faster. The current
    // choice runs; now and then a trial of a few substeps runs the other,
    // which takes over when it was faster by a margin (a trial substep three
    // times slower than the current choice ends it at once). Trials are
    // spaced by at least 50 times their own length, doubling while they
    // lose (up to about a second), so that they cost at most ~2 %; one
    // comes at once when the current choice has become 1.5 times slower
    // than when it was chosen.
    class TeamChoice {
    public:
        bool team() const { return trial_ ? !teamBest_ : teamBest_; }
        // A substep on the team (or on one thread) took `seconds`.
        void record(bool team, double seconds);

    private:
        static constexpr unsigned kTrialSteps = 32;  // substeps of a trial; the first is not compared
        static constexpr unsigned kFirstTrial = 4;   // substeps before the first trial
        bool teamBest_ = true, trial_ = false;
        double elapsed_ = 0.0, nextTrial_ = 0.0, wait_ = 0.0;  // seconds of substeps
        double expected_ = HUGE_VAL;                           // the current choice's mean when chosen
        double currentSeconds_ = 0.0;                          // the current choice's, since the last trial
        unsigned currentSteps_ = 0;
        double trialSeconds_ = 0.0, trialCompared_ = 0.0;
        unsigned trialSteps_ = 0;
    };
    TeamChoice teamChoice_;

    GridBuilder gridBuilder_;  // the grid, built by the substep's team
    // The largest v.x^2 + v.y^2 of the state, taken by the step that wrote it.
    float maxSpeedSquared_ = 0.0f;
    bool speedKnown_ = false;

    // Pairwise: each disk's earliest event and the round's lists, by sorted
    // position (kernels/pairwise.h), and the marks that keep each list free
    // of repeats within a round (epoch: a step's first search and round r
    // use epoch_ + 1 and epoch_ + 1 + r).
    std::vector<CaromEvent> events_;
    std::vector<unsigned int> pending_, nextPending_, changed_, dirty_;
    std::vector<unsigned int> pendingMark_, changedMark_, dirtyMark_;
    unsigned int epoch_ = 0;
    unsigned int substepEpoch_ = 0;  // the last pairwise substep's first epoch (readLastRounds)
    // Pairwise with neighbour lists: a disk's position is its id (identity_
    // serves as the ids and the slots), the cell each disk starts the
    // substep in (the grid's geometry, for the walls it can reach), and the
    // farthest any disk has moved since the lists were built, squared.
    bool useLists_ = true;
    bool listsTooLong_ = false;  // more entries than 32-bit offsets reach: the grid until the next load
    NeighbourLists lists_;
    std::vector<unsigned int> identity_, startCells_;
    float maxDisplacementSquared_ = 0.0f;
    std::uint64_t listBuilds_ = 0;
};

}  // namespace carom
