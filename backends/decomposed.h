// A world split among the processes of an MPI communicator
// (carom/decomposition.h): DecomposedBackend steps one process's domain on an
// ordinary backend, its engine.
//
// Each substep, every process hands its neighbours copies of its disks near
// their domains (the halo), steps its own disks and the copies together on
// the whole world's grid (Backend::stepShare), keeps its own, and hands on
// those that crossed into another domain. Its own disks then move exactly as
// among all the disks, bit for bit:
//   - the share is in the order of the disks' ids, and every choice of both
//     schemes (neighbour order, ties, sums) follows the ids;
//   - a disk's step reads only the disks within one grid cell. The
//     simultaneous step does so once, so a halo of one cell suffices. A
//     pairwise round can carry a wrong event from the halo's outer edge two
//     cells further in (a changed disk's neighbours search again, and a
//     resolve reads the partner's event), so a substep of R rounds that
//     changed disks is exact with a halo of 2R + 3 cells: the processes agree
//     on R after the substep and take it again with a deeper halo where it
//     was not deep enough;
//   - totals are exact sums (TallySums) added up across the processes, and
//     maxima and minima are exact in any order.
// The substeps, drains and stops are Backend's, as in one process: every
// decision they take is agreed across the processes (the largest speed, a
// non-finite disk, a stop).
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <carom/decomposition.h>

#include "backends/backend.h"

namespace carom {

class Decomposition {
public:
    explicit Decomposition(const DecompositionDef& def);  // duplicates def.communicator
    ~Decomposition();
    Decomposition(const Decomposition&) = delete;
    Decomposition& operator=(const Decomposition&) = delete;

    MPI_Comm communicator() const { return communicator_; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    // This process's rank among the processes of its node (shared memory),
    // which choose their GPUs by it.
    int nodeRank() const { return nodeRank_; }
    Gather gather() const { return gather_; }

    // The domains across and up for a box of width x height: as given, or
    // the factors of size() nearest the box's aspect.
    std::array<int, 2> domainsFor(float width, float height) const;

private:
    MPI_Comm communicator_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1, nodeRank_ = 0;
    int domainsX_ = 0, domainsY_ = 0;
    Gather gather_ = Gather::EachStep;
};

class DecomposedBackend : public Backend {
public:
    // Steps this process's domain of `world` on `engine`, a backend of the
    // same world without the decomposition.
    DecomposedBackend(const WorldDef& world, std::unique_ptr<Backend> engine);

    std::string device() const override;
    bool exactArithmetic() const override { return engine_->exactArithmetic(); }
    DeviceMemoryUse deviceMemory() const override { return engine_->deviceMemory(); }  // this process's
    DecompositionCosts decompositionCosts() const override { return costs_; }
    // The whole world, gathered from every process: collective.
    void readParticles(std::vector<Particle>& particles) override;
    std::vector<Image> images() override;
    void readOwnDisks(std::vector<std::uint32_t>& ids, std::vector<Particle>& particles,
                      std::vector<Image>& images) override;
    bool gathersOnRequest() const override { return decomposition_->gather() == Gather::OnRequest; }

private:
    void load(const std::vector<Particle>& particles) override;
    std::uint64_t advance(std::uint64_t substeps, float dt) override;
    void keepStepStart() override;
    void returnToStepStart() override;
    float maxSpeedSquared() override;
    void drainTallies(ContactTotals& totals) override;
    void addUndrained(ContactTotals& totals) override;
    // The sums of every process's tallies since the last drain (collective
    // unless they are known: between two substeps, once taken).
    TallySums undrainedSums();
    void motionChanged() override { engine_->setMotion(world_.dt, world_.gravity); }
    bool stopCheckCollective() const override { return true; }
    bool agreedStop(bool stop) override;

    // Substep number `substep` (since setParticles), of dt; returns false
    // where it left one of the whole world's disks non-finite (recorded), and
    // then hands no disks on.
    bool substep(std::uint64_t substep, float dt);
    // next_ for a halo of `halo` cells: this process's own disks and copies
    // of the others' within reach, by id.
    void gatherShare(int halo);
    // Hands the own disks whose centres left the domain to their domains'
    // processes, and takes those that entered it.
    void migrate();
    // The process whose domain holds `position`.
    int ownerOf(float2 position) const;
    // Refuses processes that were given different worlds or disks.
    void requireSameInput(const std::vector<Particle>& particles) const;

    std::shared_ptr<const Decomposition> decomposition_;
    MPI_Comm comm_;
    std::unique_ptr<Backend> engine_;
    int domainsX_ = 1, domainsY_ = 1;
    // The first cell column (row) of each domain column (row), and one past the last.
    std::vector<int> columnStarts_, rowStarts_;
    std::vector<int> domainColumn_, domainRow_;  // by cell column (row)
    int halo_ = 1;                               // cells, the next substep's first try

    // Disks with their ids, tallies and images.
    struct Own {
        std::vector<std::uint32_t> ids;
        std::vector<Particle> particles;
        std::vector<ContactTally> tallies;
        std::vector<Image> images;
        void resize(std::size_t n);
    };
    // This process's own disks between substeps: those of the last share
    // that stayed in the domain, where the share holds them, and those handed
    // on to it since. They are not copied out of the share and back: the
    // next share is merged from them and the new copies.
    struct Held {
        Share share;                      // by id: the own disks and the copies of the last substep
        std::vector<std::uint32_t> ids;   // the id in each slot of share
        std::vector<std::size_t> stayed;  // the own disks' slots, in id order
        std::vector<Image> stayedImages;  // by stayed index
        Own arrived;                      // by id
    };
    Held held_, stepStart_;
    // The own disks in one run, in any order (for the gathers and sums).
    Own ownDisks() const;
    // What images() and undrainedSums() gathered, while it holds: until the
    // next substep, drain or load. World takes both after each step() call,
    // on every process, so that a read between steps is each process's own.
    bool imagesCurrent_ = false;  // images_ holds every process's images
    TallySums undrained_;
    bool undrainedCurrent_ = false;
    // gatherShare's: the next share, its ids, the own disks' slots (in id
    // order) and their images; held_ until the substep is kept.
    Share next_;
    std::vector<std::uint32_t> nextIds_;
    std::vector<std::size_t> nextOwn_;
    std::vector<Image> nextImages_;
    // Scratch of gatherShare (whether an own disk is near another domain)
    // and migrate (each one's domain), kept so that no substep allocates them.
    std::vector<unsigned char> near_;
    std::vector<int> owners_;
    DecompositionCosts costs_;  // since load()
};

}  // namespace carom
