// The OpenMP CPU backend: the shared grid builder, then the collision scheme
// in parallel loops over particles: resolveCollisions and integrate from
// kernels/physics.h in one loop (simultaneous), or the rounds of
// kernels/pairwise.h (pairwise). The all-pairs baseline of `carom bench`
// (bench/all_pairs_cpu.h) derives from it.
#pragma once

#include <memory>
#include <vector>

#include "backends/backend.h"

namespace carom {

class CpuBackend : public Backend {
public:
    explicit CpuBackend(const WorldDef& world);

    std::string device() const override;
    bool exactArithmetic() const override { return true; }

    void readParticles(std::vector<Particle>& particles) override { particles = *state_; }
    std::shared_ptr<const std::vector<Particle>> sharedState() override { return state_; }

protected:
    // The state before the step, shared with World::diskMemory's views: a
    // view keeps its buffer alive, and while one does, the steps and loads of
    // the same number of disks write into that buffer (views follow them).
    std::shared_ptr<std::vector<Particle>> state_ = std::make_shared<std::vector<Particle>>();
    // Simultaneous: written by the step, then swapped in (copied in while a view holds state_).
    std::shared_ptr<std::vector<Particle>> next_ = std::make_shared<std::vector<Particle>>();
    std::vector<ContactTally> tallies_;  // by particle id

private:
    void load(std::vector<Particle> particles) override;
    void advance(std::uint64_t substeps, float dt) override;
    float maxSpeedSquared() override { return maxSpeedSquaredOf(state_->data(), state_->size()); }
    void drainTallies(ContactTotals& totals) override { drainTallyArray(tallies_.data(), tallies_.size(), totals); }
    // One substep each; they return the lowest id of a disk the substep left
    // non-finite, or kAllFinite.
    std::uint32_t stepSimultaneous(float dt);
    std::uint32_t stepPairwise(float dt);
    unsigned int nextEpoch();

    // Pairwise: each disk's earliest event and the round's lists, by sorted
    // position (kernels/pairwise.h), and the marks that keep each list free
    // of repeats within a round (epoch).
    std::vector<CaromEvent> events_;
    std::vector<unsigned int> pending_, nextPending_, changed_, dirty_;
    std::vector<unsigned int> pendingMark_, changedMark_, dirtyMark_;
    unsigned int epoch_ = 0;
};

}  // namespace carom
