// The Backend interface: one implementation per compute device family.
//
// A step is always: build the grid (engine/grid.h), then the collision
// scheme (WorldDef::collisions): simultaneous (resolveCollisions ->
// integrate, kernels/physics.h) or pairwise (rounds of events,
// kernels/pairwise.h). Backends differ only in where those loops run. The
// base class owns what is the same for all: splitting steps into substeps
// (WorldDef::maxTravel, and the pairwise scheme's grid allowance) and
// summing the per-particle contact tallies into ContactTotals.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/exact_sum.h"
#include "engine/scene.h"
#include "engine/grid.h"
#include "engine/observables.h"
#include "kernels/pairwise.h"

namespace carom {

// Passes over fewer disks than this run on one thread: a pass is short, and
// starting an OpenMP team for it costs more, far more when other processes
// keep the cores busy (a thread spins at the barrier for a descheduled one:
// 1 000 simultaneous steps of 2 disks on 2 loaded cores took up to 12 s in a
// team, 0.5 s on one thread; bench/under_load.sh). A pairwise step runs a
// dozen passes, a simultaneous one one; a step with substeps also takes the
// largest speed (maxSpeedSquaredOf).
constexpr std::int64_t kParallelPassLength = 4096;

// How often step() asks its stop check (Backend::setStopCheck), at most:
// often enough for a stop within a fraction of a second, rarely enough that
// a check that takes Python's lock costs nothing measurable.
constexpr std::chrono::milliseconds kStopCheckInterval{20};
// A step split into at least this many substeps keeps its start
// (Backend::keepStepStart), so a stop can cut it short: a copy of the state
// costs less than a few percent of such a step. Shorter ones run whole.
constexpr std::uint64_t kStoppableSubsteps = 8;

// The most rounds of a pairwise step; events still pending after them are
// left for the next step (they show up as late contacts).
constexpr unsigned int kMaxPairwiseRounds = 64;

// Where a state blew up: the first step that left a disk with a position or
// velocity that is not finite, and the lowest id among that step's such disks.
struct NonFiniteState {
    std::uint64_t step = 0;
    std::uint32_t particle = 0;
};

class Backend {
public:
    explicit Backend(const WorldDef& world);
    virtual ~Backend() = default;
    Backend(const Backend&) = delete;
    Backend& operator=(const Backend&) = delete;

    virtual std::string device() const = 0;  // human-readable device description
    // True when divide and sqrt are correctly rounded, so that this backend's
    // trajectories are bitwise identical to the CPU backend's.
    virtual bool exactArithmetic() const = 0;
    virtual DeviceMemoryUse deviceMemory() const { return {}; }
    virtual DecompositionCosts decompositionCosts() const { return {}; }

    // Validates the particles against the world, sizes the grid for their
    // largest radius (and the scheme), loads them and resets the contact totals.
    // `step` is the number of the step they hold, which messages count from;
    // `images` their periodic images (empty: all {0, 0}; else one per particle).
    void setParticles(const std::vector<Particle>& particles, std::uint64_t step = 0,
                      const std::vector<Image>& images = {});
    // Advances the simulation by `steps` steps of world().dt, each split into
    // substeps when world().maxTravel > 0 or the pairwise scheme's grid
    // needs them. Throws Error if a step would need more than kMaxSubsteps
    // substeps, or when the state goes non-finite: stepping stops at the
    // (sub)step that did it (nonFinite() says which), and every later call
    // throws the same until setParticles. Returns early when the stop check
    // asks (setStopCheck); stepNumber() then says the step reached.
    void step(std::uint64_t steps);
    // Asked every kStopCheckInterval or so while step() runs, between steps,
    // and within a step that keeps its start (between substeps and events):
    // true stops step() there, a step cut short returning to its start.
    // Empty: never asked.
    void setStopCheck(std::function<bool()> check) { stopCheck_ = std::move(check); }
    // Where the state went non-finite, once step() found it; empty before.
    const std::optional<NonFiniteState>& nonFinite() const { return nonFinite_; }
    // Copies the current state into `particles` (in id order).
    virtual void readParticles(std::vector<Particle>& particles) = 0;
    // The views of the current state, in the order the backend stores it,
    // into out[0..particleCount()), and their sums (World::readView),
    // measured where the state lives; empty where that is the host, for
    // World to measure its own copy.
    virtual std::optional<ViewSums> readView(ViewValue value, DiskView* out) {
        (void)value;
        (void)out;
        return std::nullopt;
    }
    // The current state where the host holds it between steps, in id order,
    // for World::diskMemory; null where it lives elsewhere (a device, doubles).
    virtual std::shared_ptr<const std::vector<Particle>> sharedState() { return nullptr; }

    // What a backend that keeps an exact state beside its float particles
    // (the event-driven one, in double) adds to them; the defaults are those
    // of the backends whose particles are their whole state.
    // The total energy (kinetic minus sum m g.x) of the exact state; empty
    // here, for World to measure the particles.
    virtual std::optional<double> exactTotalEnergy() const { return std::nullopt; }
    // How often each kind of event happened since setParticles or restoreState; zeros here.
    virtual EventCounts eventCounts() const { return EventCounts{}; }
    // The centres of the exact state, in id order [length]; empty here.
    virtual std::vector<std::array<double, 2>> exactPositions() const { return {}; }
    // The exact state, for a snapshot; empty here.
    virtual std::optional<EventEngineState> saveState() const { return std::nullopt; }
    // Continues exactly where `state`, saved by saveState() of a backend of
    // the same world and particles, left off (call setParticles with those
    // particles first). Throws Error naming the value that does not fit,
    // and changes nothing then; here always: no exact state to restore.
    virtual void restoreState(const EventEngineState& state);
    // Each disk's periodic image (carom/types.h Image), in id order, for the
    // state readParticles gives: setParticles' images plus the wraps since.
    virtual std::vector<Image> images();
    // The disks this process steps, by id, with their ids and images
    // (World::ownDisks): every disk here, a decomposed world's own there.
    virtual void readOwnDisks(std::vector<std::uint32_t>& ids, std::vector<Particle>& particles,
                              std::vector<Image>& images);
    // Whether the whole world reaches this process only when World::gather()
    // asks (Gather::OnRequest); its reads of the whole world are collective.
    virtual bool gathersOnRequest() const { return false; }
    // Collisions, virial and wall impulses since setParticles or the last
    // resetContacts(). Reading them changes nothing: the per-disk tallies are
    // drained into the totals every kTallySubsteps substeps (counted from
    // setParticles), and the totals are the same bits however often and
    // wherever they are read.
    const ContactTotals& contacts();
    void resetContacts();
    // Pairs that received an impulse since setParticles or resetContacts().
    std::uint64_t collisions() { return contacts().collisions; }
    // The largest speed |v| of the current state (a reduction where the
    // state lives); the same on every backend, bit for bit.
    float maxSpeed();

    // Changes dt and gravity between steps (the box stays fixed); throws
    // Error for values out of range.
    void setMotion(float dt, float2 gravity);

    // One process's share of a decomposed world (backends/decomposed.h): its
    // disks and those around them, in the order of their ids in the whole
    // world, with their tallies.
    struct Share {
        std::vector<Particle> particles;
        std::vector<ContactTally> tallies;  // one per particle, carried from substep to substep
        // Out, pairwise: the last round of the substep that changed each disk, 0 for none.
        std::vector<unsigned int> lastRounds;
    };
    // For DecomposedBackend: steps `share` by one substep of dt on this
    // backend, with the grid, radii and world of `whole` (the decomposed
    // world's backend), so that each disk moves as it would among all the
    // disks wherever all its neighbours within reach are in the share.
    // Returns the last round that changed a disk of the share (0 for the
    // simultaneous scheme). Throws Error where this backend cannot.
    unsigned int stepShare(Share& share, const Backend& whole, float dt);

    const WorldDef& world() const { return world_; }
    // The step the state holds: setParticles' `step` plus the steps completed
    // since. After step() threw on a non-finite state, nonFinite() says
    // which step the state stopped at.
    std::uint64_t stepNumber() const { return stepNumber_; }
    std::size_t particleCount() const { return particleCount_; }
    // The grid's cells, as setParticles sized them for the particles and the scheme.
    const GridGeometry& gridGeometry() const { return grid_.geometry; }

protected:
    // The particles setParticles checked, each at time 0 with no last partner.
    virtual void load(const std::vector<Particle>& particles) = 0;
    // Takes `substeps` steps of `dt` with world_'s gravity and boundary, and
    // returns how many it took: fewer only where stopHere() said stop
    // between two of them, or a substep went non-finite.
    virtual std::uint64_t advance(std::uint64_t substeps, float dt) = 0;
    // Keeps the state and the per-particle tallies as they are now, and
    // returns to them: a step that a stop cuts short returns to its start.
    virtual void keepStepStart() = 0;
    virtual void returnToStepStart() = 0;
    // Takes up to `steps` (>= 1) steps of `substeps` substeps of dt each,
    // the first as planned; each later one only while the state it starts
    // from needs the same count (carom_substeps_needed under `rule`), so that
    // the result equals stepping one at a time. Returns the steps taken. This
    // one takes one: a backend that checks the count where its state lives
    // can take more without a wait each. No stop is looked for within.
    virtual std::uint64_t advanceWhileSubstepsHold(std::uint64_t steps, std::uint64_t substeps, float dt,
                                                   const CaromSubstepRule& rule);
    // The largest v.x^2 + v.y^2 of the current state.
    virtual float maxSpeedSquared() = 0;
    // Waits until every step advance() enqueued has finished, for backends
    // that do not wait in advance(); step() returns only after it.
    virtual void awaitSteps() {}
    // Adds the per-particle tallies (kernels/particle.h ContactTally) to
    // `totals` and zeroes them (drainTallyArray). Called every
    // kTallySubsteps substeps and by resetContacts.
    virtual void drainTallies(ContactTotals& totals) = 0;
    // Adds the tallies since the last drain to `totals` as a drain would,
    // leaving them (contacts()); here from readTallies.
    virtual void addUndrained(ContactTotals& totals);
    // setMotion changed world_.dt or world_.gravity (the state is as before).
    virtual void motionChanged() {}
    // The per-particle tallies since the last drain, by id (contacts(),
    // images()); throws Error where the backend keeps none.
    virtual void readTallies(std::vector<ContactTally>& tallies);
    // stepShare's: replaces the per-particle tallies of the state load() took
    // with `tallies` (one per particle); the last round that changed each
    // disk in the last substep (zeros where the scheme has no rounds). These
    // throw Error: this backend takes no shares.
    virtual void writeTallies(const std::vector<ContactTally>& tallies);
    virtual void readLastRounds(std::vector<unsigned int>& rounds);
    // stepShare's: loads a share's disks and tallies (load, writeTallies),
    // and reads them back after its substep (readParticles, readTallies); a
    // backend may take the vectors' contents instead of copying them.
    virtual void loadShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies);
    virtual void readShare(std::vector<Particle>& particles, std::vector<ContactTally>& tallies);
    // stepShare without the copies: takes `whole`'s grid, radii and substep
    // allowance for a share of `count` (> 0) disks, which `load` loads into
    // this backend, and steps it by one substep of dt; returns the last
    // round that changed one of its disks. The result stays here.
    unsigned int stepLoadedShare(std::size_t count, const Backend& whole, float dt, const std::function<void()>& load);
    // Whether the stop check must be asked at every chance (stopHere), not
    // every kStopCheckInterval: a decomposed world's check is collective, and
    // every process must ask it at the same points.
    virtual bool stopCheckCollective() const { return false; }
    // What all the processes that step this world together decide from
    // their stop checks' answers: here the one answer.
    virtual bool agreedStop(bool stop) { return stop; }

    // For implementations: substep number `substep` (counted from 0 since
    // setParticles) left `particle`, the lowest such id, with a position or
    // velocity that is not finite. advance() takes no more substeps after it.
    void recordNonFinite(std::uint64_t substep, std::uint32_t particle);
    // Substeps taken by the advance() calls before the current one, since setParticles.
    std::uint64_t substepsTaken() const { return substepsTaken_; }
    // For implementations, between two substeps of advance() and, in a step
    // that keepStepStart() kept, between events: whether to stop there (the
    // stop check said so, now or earlier in this step() call). False where
    // step() cannot stop: within a step whose start was not kept.
    bool stopHere();
    // Whether a stop check is set: a step that keeps its start can be stopped.
    bool stopCheckSet() const { return static_cast<bool>(stopCheck_); }
    // For implementations: a pairwise (sub)step used this many rounds.
    void recordRounds(unsigned int rounds);
    // What every kernel of a (sub)step of duration dt reads (kernels/params.h).
    CaromStepParams stepParams(float dt) const;
    // How far a disk may move in a substep (gridTravelAllowance of grid_).
    float gridTravel() const { return gridTravel_; }

    WorldDef world_;
    Grid grid_;  // geometry fixed by setParticles, contents rebuilt each step
    // Each disk's image, in id order: set by setParticles before load(), then
    // the implementation's to keep (drainTallyArray adds the tallies' wraps).
    std::vector<Image> images_;
    std::size_t particleCount_ = 0;
    float minRadius_ = 0.0f, maxRadius_ = 0.0f;  // of the particles setParticles took

private:
    // Substeps of one advance() call: the first is substep `firstSubstep`
    // (since setParticles) and belongs to step `firstStep`, which has
    // `substepsPerStep` substeps (1 with a fixed dt).
    struct Batch {
        std::uint64_t firstSubstep = 0, firstStep = 0, substepsPerStep = 1;
    };
    // Advances as advance() does and counts the substeps it took.
    std::uint64_t advanceCounted(const Batch& batch, std::uint64_t substeps, float dt);
    // Takes one step of `substeps` substeps of `substepDt`; a step of at
    // least kStoppableSubsteps keeps its start and can be stopped within.
    void substepped(std::uint64_t substeps, float substepDt);
    void countSubsteps(std::uint64_t substeps);  // after advance() took them
    void drainCounted();                         // drains the tallies into totals_
    // The message for a step that would need more than kMaxSubsteps.
    std::string tooManySubsteps(float speedSquared, const CaromSubstepRule& rule) const;
    // Throws the Error that says where the state went non-finite, once it has.
    void requireFinite() const;
    // The Error of a backend that takes no shares (writeTallies and the rest).
    [[noreturn]] void refuseShares() const;
    // How step() splits a step: the longest move of one substep is
    // maxTravel x the smallest radius, and with the pairwise scheme the
    // grid's allowance over CAROM_PAIRWISE_SPEED_MARGIN; infinite when neither
    // limits it.
    CaromSubstepRule substepRule() const;

    ContactTotals totals_;    // the drained tallies
    ContactTotals reported_;  // contacts()': totals_ and the tallies since
    std::uint64_t substepsSinceDrain_ = 0;
    float gridTravel_ = 0.0f;          // gridTravelAllowance of grid_
    std::uint64_t stepNumber_ = 0;     // the step the current state holds
    std::uint64_t substepsTaken_ = 0;  // since setParticles
    // The current and the previous advance() call's: an implementation that
    // waits for a substep later (the resident pairwise step) may report the
    // previous call's last substep.
    Batch batch_, previousBatch_;
    std::optional<NonFiniteState> nonFinite_;

    std::function<bool()> stopCheck_;
    bool stopAllowed_ = true;  // stopHere() may stop: between steps, or in a step that kept its start
    bool stopped_ = false;     // the stop check said stop during this step() call
    std::chrono::steady_clock::time_point nextStopCheck_;
};

// For implementations: adds `change` to an image count, modulo 2^32 (a
// disk that crosses a box every step for hours wraps around, as it does
// in the int32 of a GSD file, instead of overflowing).
inline void addToImage(std::int32_t& count, std::int32_t change) {
    count = static_cast<std::int32_t>(static_cast<std::uint32_t>(count) + static_cast<std::uint32_t>(change));
}

// The exact sums of per-disk tallies (sumTallies), until addTo rounds them:
// what the processes of a decomposed world add up.
struct TallySums {
    std::uint64_t collisions = 0, lateContacts = 0;
    ExactSum virial;
    std::array<ExactSum, 4> wallImpulse;
    void add(const TallySums& other);
    void addTo(ContactTotals& totals) const;  // each sum rounded once to double
};

// For implementations: the sums of tallies[0..count), on the team of threads.
TallySums sumTallies(const ContactTally* tallies, std::size_t count);
// For implementations: adds the wraps of tallies[0..count) to images[0..count).
void addWraps(Image* images, const ContactTally* tallies, std::size_t count);
// For implementations: addWraps, then zeroes the tallies.
void clearTallies(ContactTally* tallies, std::size_t count, Image* images);
// For implementations: adds tallies[0..count) to `totals` and their wraps
// to images[0..count), and zeroes them. Each drain's sums are exact
// (ExactSum), rounded once to double: the same whatever device produced the
// tallies, in whatever order, and however the disks are shared out.
void drainTallyArray(ContactTally* tallies, std::size_t count, ContactTotals& totals, Image* images);
// For implementations holding the state on the host: the largest
// v.x^2 + v.y^2 (an OpenMP max reduction; max is exact in any order).
float maxSpeedSquaredOf(const Particle* particles, std::size_t count);

}  // namespace carom
