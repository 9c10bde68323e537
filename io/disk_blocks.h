// Disks in id order, read a block at a time, so that a writer holds one
// block of them rather than a copy of them all: a world's (World::getDisks
// of a range, from the state the world holds) or a vector's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include <carom/types.h>
#include <carom/world.h>

namespace carom {

class DiskBlocks {
public:
    static constexpr std::size_t kBlock = std::size_t(1) << 16;  // disks a block: 1.5 MB

    // Implicit, for a writer's argument: the vector outlives the call.
    DiskBlocks(const std::vector<Disk>& disks) : vector_(&disks), count_(disks.size()) {}
    explicit DiskBlocks(const World& world) : world_(&world), count_(world.diskCount()) {}

    std::size_t size() const { return count_; }
    bool empty() const { return count_ == 0; }

    // visit(i, disk) for every disk, in id order.
    template <class Visit>
    void forEach(Visit&& visit) const {
        for (std::size_t first = 0; first < count_; first += kBlock) {
            const std::size_t n = std::min(kBlock, count_ - first);
            const Disk* block = vector_ ? vector_->data() + first : read(first, n);
            for (std::size_t j = 0; j < n; ++j) visit(first + j, block[j]);
        }
    }

private:
    const Disk* read(std::size_t first, std::size_t n) const {
        buffer_.resize(n);
        world_->getDisks(first, n, buffer_.data());
        return buffer_.data();
    }

    const std::vector<Disk>* vector_ = nullptr;
    const World* world_ = nullptr;
    std::size_t count_ = 0;
    mutable std::vector<Disk> buffer_;
};

}  // namespace carom
