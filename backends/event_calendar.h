// The event calendar of the event-driven scheme: the complete binary tree of
// Marin, Risso and Cordero (J. Comput. Phys. 109, 306, 1993). Each disk is
// a leaf holding its one scheduled event time; each inner node holds the
// earlier of its two children, so the root is the next event.
//
// Why this and not Paul's O(1) calendar queue (J. Comput. Phys. 221, 615,
// 2007): an update is one walk of log2 N levels with no tuning parameter
// (the queue needs a bucket width matched to the event rate, and a rebuild
// when it drifts), the cost is the same in any state (dense, dilute, under
// gravity), and the winner of a tie is the lower particle id whatever order the
// events were scheduled in, so a calendar rebuilt from a checkpoint is the
// calendar the run had. At 10^6 disks the walk is 20 levels of 16-byte
// nodes, the upper ones in cache (at 10^5 the walks took 31 % of the time:
// README, "Event-driven speed").
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

namespace carom {

class EventCalendar {
public:
    // One leaf per disk: leaf i holds times[i], and ties between equal
    // times go to the lower keys[i] (the particle id).
    void reset(const std::vector<double>& times, const std::vector<std::uint32_t>& keys) {
        leaves_ = 1;
        while (leaves_ < times.size()) leaves_ *= 2;
        nodes_.assign(2 * std::size_t(leaves_), Node{HUGE_VAL, 0, 0});
        for (std::size_t i = 0; i < leaves_; ++i)
            nodes_[leaves_ + i] =
                i < times.size() ? Node{times[i], std::uint32_t(i), keys[i]} : Node{HUGE_VAL, std::uint32_t(i), ~0u};
        for (std::size_t k = leaves_ - 1; k >= 1; --k) nodes_[k] = earlierChild(k);
    }
    // Sets leaf `leaf`'s time and walks up towards the root, as far as the
    // winners change.
    void set(std::uint32_t leaf, double time) {
        std::size_t k = leaves_ + std::size_t(leaf);
        nodes_[k].time = time;
        for (k /= 2; k >= 1; k /= 2) {
            const Node winner = earlierChild(k);
            if (winner.leaf == nodes_[k].leaf && winner.time == nodes_[k].time) break;
            nodes_[k] = winner;
        }
    }
    // The leaf with the earliest time (the lowest key among equal times), and its time.
    std::uint32_t next() const { return nodes_[1].leaf; }
    double nextTime() const { return nodes_[1].time; }

private:
    struct Node {
        double time;
        std::uint32_t leaf, key;
    };
    // The earlier child of node k, chosen by index rather than by a branch:
    // which child wins is a coin toss the processor cannot predict.
    Node earlierChild(std::size_t k) const {
        const Node* child = &nodes_[2 * k];
        const bool right =
            (child[1].time < child[0].time) | ((child[1].time == child[0].time) & (child[1].key < child[0].key));
        return child[right];
    }
    std::vector<Node> nodes_;  // nodes_[1] is the root; leaves at [leaves_, 2 leaves_)
    std::size_t leaves_ = 1;
};

}  // namespace carom
