// What a process of a decomposed world (backends/decomposed.h) holds
// between substeps: its own disks, where the share of the last substep holds
// them beside the copies of other processes' disks it was stepped with.
// Each substep merges them with the disks handed to the process and the new
// copies into the next share, in id order, and steps it on the engine.
//   - HostDomainShare keeps the share on the host and steps it on any engine
//     (Backend::stepShare);
//   - OpenClDomainShare (backends/opencl/domain_share.h) keeps it on the
//     device of an OpenCL resident engine, so that only the halo's copies
//     and the disks handed on cross the bus.
// Both give the same bits: the same share, in the same order, on engines
// that agree bit for bit.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "backends/backend.h"

namespace carom {

// Disks with their ids, tallies and images.
struct DomainDisks {
    std::vector<std::uint32_t> ids;
    std::vector<Particle> particles;
    std::vector<ContactTally> tallies;
    std::vector<Image> images;
    void resize(std::size_t n);
};

// Which process's domain holds a position: the domain of each cell column
// and row of the whole world's grid.
struct DomainMap {
    GridGeometry grid{};
    int domainsX = 1;
    std::vector<int> domainOfColumn, domainOfRow;
    int ownerOf(float2 position) const;
};

class DomainShare {
public:
    virtual ~DomainShare() = default;

    // Starts from `own`, this process's disks (`rank` in `map`) by id, with
    // zero tallies.
    virtual void load(const DomainDisks& own, const DomainMap& map, int rank) = 0;
    // The own disks held (those handed on since the last substep not among them).
    virtual std::size_t ownCount() const = 0;
    // The ids and disks of the own disks whose cell's column or row is
    // marked (by cell column and row), in any order.
    virtual void near(const std::vector<unsigned char>& nearColumns, const std::vector<unsigned char>& nearRows,
                      std::vector<std::uint32_t>& ids, std::vector<Particle>& particles) = 0;
    // The next share: the own disks, `arrived` (handed to this process, by
    // id) and the copies (by id), merged by id. The held disks stay as they
    // are until keepNext, so the next share can be merged again.
    virtual void mergeNext(const DomainDisks& arrived, const std::vector<std::uint32_t>& copyIds,
                           const std::vector<Particle>& copies) = 0;
    // Steps the next share by one substep of dt with the grid of `whole`
    // (Backend::stepShare); returns the last round that changed one of its disks.
    virtual unsigned int stepNext(const Backend& whole, float dt) = 0;
    struct Kept {
        unsigned int lastRound = 0;                                           // the last round that changed an own disk
        std::uint32_t nonFinite = std::numeric_limits<std::uint32_t>::max();  // the lowest id of one left non-finite
    };
    // The stepped share is held from now on, with the arrived disks among its own.
    virtual Kept keepNext() = 0;
    // Removes the own disks whose centres left the domain and returns them, in any order.
    virtual void takeLeavers(DomainDisks& leavers) = 0;
    // The own disks, by id.
    virtual DomainDisks own() const = 0;
    // The largest v.x^2 + v.y^2 of the own disks (0 for none).
    virtual float maxSpeedSquared() = 0;
    // Adds the own disks' wraps to their images and zeroes the tallies.
    virtual void clearTallies() = 0;
    // A copy of what it holds, to return to (Backend::keepStepStart).
    virtual std::unique_ptr<DomainShare> clone() const = 0;
};

class HostDomainShare final : public DomainShare {
public:
    explicit HostDomainShare(Backend& engine) : engine_(&engine) {}

    void load(const DomainDisks& own, const DomainMap& map, int rank) override;
    std::size_t ownCount() const override { return stayed_.size(); }
    void near(const std::vector<unsigned char>& nearColumns, const std::vector<unsigned char>& nearRows,
              std::vector<std::uint32_t>& ids, std::vector<Particle>& particles) override;
    void mergeNext(const DomainDisks& arrived, const std::vector<std::uint32_t>& copyIds,
                   const std::vector<Particle>& copies) override;
    unsigned int stepNext(const Backend& whole, float dt) override;
    Kept keepNext() override;
    void takeLeavers(DomainDisks& leavers) override;
    DomainDisks own() const override;
    float maxSpeedSquared() override;
    void clearTallies() override;
    std::unique_ptr<DomainShare> clone() const override { return std::make_unique<HostDomainShare>(*this); }

private:
    Backend* engine_;
    DomainMap map_;
    int rank_ = 0;
    // The own disks are not copied out of the share and back: the next share
    // is merged from where they are.
    Backend::Share share_;                // by id: the own disks and the copies of the last substep
    std::vector<std::uint32_t> ids_;      // the id in each slot of share_
    std::vector<std::size_t> stayed_;     // the own disks' slots, in id order
    std::vector<Image> stayedImages_;     // by stayed_ index
    Backend::Share next_;                 // mergeNext's, stepped by stepNext
    std::vector<std::uint32_t> nextIds_;  // the id in each slot of next_
    std::vector<std::size_t> nextOwn_;    // the own disks' slots in next_, in id order
    std::vector<Image> nextImages_;       // by nextOwn_ index
    std::vector<unsigned char> scratch_;  // near's (whether an own disk is near), kept between substeps
    std::vector<int> owners_;             // takeLeavers' (each own disk's domain), kept between substeps
};

}  // namespace carom
