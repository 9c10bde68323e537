// A process's share of a decomposed world kept on the device of its OpenCL
// resident engine (DomainShare, backends/domain_share.h; kernels/domain_share.cl).
// Each substep the host uploads the disks handed to the process and the halo's
// copies, and reads back only the own disks near another domain and those
// that left it; the merge into the next share, the step, and the maxima and
// minima over the own disks run on the device. The whole share crosses the
// bus only when the host reads the own disks (the gathers and the tallies'
// drains); the copy a stop may return to (clone) stays on the device.
#pragma once

#include <memory>

#include "backends/domain_share.h"
#include "backends/opencl/resident.h"

namespace carom {

class OpenClDomainShare final : public DomainShare {
public:
    explicit OpenClDomainShare(OpenClResidentBackend& engine);

    void load(const DomainDisks& own, const DomainMap& map, int rank) override;
    std::size_t ownCount() const override { return ownCount_; }
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
    std::unique_ptr<DomainShare> clone() const override;

private:
    // A device buffer that grows as needed (never shrinks).
    struct Array {
        opencl::Buffer buffer;
        std::size_t bytes = 0;
        cl_mem get() const { return buffer.get(); }
    };
    // A share in id order (kernels/domain_share.cl): count disks.
    struct Disks {
        Array particles, tallies, images, ids, own;
        std::size_t count = 0;
    };
    struct Kernels;  // the program's kernels, shared by the clones

    // clone()'s: a copy on the device of what `from` holds.
    OpenClDomainShare(const OpenClDomainShare& from, const char* what);

    void fit(Array& array, std::size_t bytes, const char* what) const;
    void fit(Disks& disks, std::size_t count) const;
    template <class T>
    void write(Array& array, const std::vector<T>& values, std::size_t offset, const char* what) const;
    template <class T>
    void read(const Array& array, std::vector<T>& values, std::size_t count, const char* what) const;
    // Lists the held share's slots a kernel picks (list_) and returns their count.
    std::size_t listSlots(cl_kernel kernel);
    // Reads the listed slots' ids and disks, and with tallies their tallies and images.
    void readListed(std::size_t listed, bool tallies, DomainDisks& out);

    OpenClResidentBackend* engine_;
    cl_context context_;
    cl_command_queue queue_;
    std::shared_ptr<const Kernels> kernels_;
    DomainMap map_;
    int rank_ = 0;
    Disks held_, next_;
    std::size_t ownCount_ = 0, nextOwnCount_ = 0;
    // The domains of the cell columns and rows; near()'s marks.
    Array domainOfColumn_, domainOfRow_, nearColumns_, nearRows_;
    // mergeNext's uploads: the arrived disks then the copies (particles,
    // ids), and the arrived disks' tallies and images; its scan of held_.own.
    Array incoming_, incomingIds_, incomingTallies_, incomingImages_, ownRanks_, tileStarts_;
    Array list_, record_;  // a list of slots (count first), and keepNext's and maxSpeedSquared's record
    DomainDisks packed_;   // readListed's scratch
    Array packedIds_, packedParticles_, packedTallies_, packedImages_;
};

}  // namespace carom
