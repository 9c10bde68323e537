// A world split among the processes of an MPI communicator
// (carom/decomposition.h): DecomposedBackend steps one process's domain on an
// ordinary backend, its engine.
//
// Each substep, every process hands its neighbours copies of its disks near
// their domains (the halo), steps its own disks and the copies together on
// the whole world's grid (a DomainShare, backends/domain_share.h), keeps
// its own, and hands on those that crossed into another domain. Its own disks then move exactly as
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
#include "backends/domain_share.h"

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
    // same world without the decomposition, holding its disks in `share`
    // (which steps its shares on `engine`).
    DecomposedBackend(const WorldDef& world, std::unique_ptr<Backend> engine, std::unique_ptr<DomainShare> share);

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
    // The next share for a halo of `halo` cells: this process's own disks,
    // those handed to it and copies of the others' within reach, by id.
    void mergeShare(int halo);
    // Hands the own disks whose centres left the domain to their domains'
    // processes, and takes those that entered it.
    void migrate();
    // Refuses processes that were given different worlds or disks.
    void requireSameInput(const std::vector<Particle>& particles) const;

    std::shared_ptr<const Decomposition> decomposition_;
    MPI_Comm comm_;
    std::unique_ptr<Backend> engine_;
    // This process's own disks between substeps, where the last share holds
    // them, and the disks handed to it since (by id), not yet in a share.
    std::unique_ptr<DomainShare> held_;
    DomainDisks arrived_;
    std::unique_ptr<DomainShare> stepStart_;  // keepStepStart's copies
    DomainDisks stepStartArrived_;
    DomainMap map_;
    int domainsY_ = 1;
    // The first cell column (row) of each domain column (row), and one past the last.
    std::vector<int> columnStarts_, rowStarts_;
    int halo_ = 1;  // cells, the next substep's first try

    // The own disks in one run, in any order (for the gathers and sums).
    DomainDisks ownDisks() const;
    // What images() and undrainedSums() gathered, while it holds: until the
    // next substep, drain or load. World takes both after each step() call,
    // on every process, so that a read between steps is each process's own.
    bool imagesCurrent_ = false;  // images_ holds every process's images
    TallySums undrained_;
    bool undrainedCurrent_ = false;
    DecompositionCosts costs_;  // since load()
};

}  // namespace carom
