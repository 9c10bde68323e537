// The event calendar of the event-driven scheme: the complete binary tree of
// Marin, Risso and Cordero (J. Comput. Phys. 109, 306, 1993). Each disk is
// a leaf holding its one scheduled event time; each inner node holds the
// earlier of its two children, so the root is the next event.
//
// Why this and not Paul's O(1) calendar queue (J. Comput. Phys. 221, 615,
// 2007): an update is one walk of log2 N levels with no tuning parameter
// (the queue needs a bucket width matched to the event rate, and a rebuild
// when it drifts), the cost is the same in any state (dense, dilute, under
// gravity), and the winner of a tie is the lower disk id whatever order the
// events were scheduled in, so a calendar rebuilt from a checkpoint is the
// calendar the run had. At 10^6 disks the walk is 20 levels of 16-byte
// nodes, the upper ones in cache; bench/events.sh measures what it costs.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

namespace carom {

class EventCalendar {
public:
    // `count` leaves, every one at +infinity.
    void reset(std::uint32_t count) {
        leaves_ = 1;
        while (leaves_ < count) leaves_ *= 2;
        nodes_.assign(2 * std::size_t(leaves_), Node{HUGE_VAL, 0});
        for (std::uint32_t i = 0; i < leaves_; ++i) nodes_[leaves_ + i].id = i;
        for (std::size_t k = leaves_ - 1; k >= 1; --k) nodes_[k] = earlier(nodes_[2 * k], nodes_[2 * k + 1]);
    }
    // Sets disk `id`'s event time and walks up to the root.
    void set(std::uint32_t id, double time) {
        std::size_t k = leaves_ + std::size_t(id);
        nodes_[k].time = time;
        for (k /= 2; k >= 1; k /= 2) nodes_[k] = earlier(nodes_[2 * k], nodes_[2 * k + 1]);
    }
    // The disk with the earliest event (the lowest id among equal times), and its time.
    std::uint32_t next() const { return nodes_[1].id; }
    double nextTime() const { return nodes_[1].time; }

private:
    struct Node {
        double time;
        std::uint32_t id;
    };
    static Node earlier(const Node& a, const Node& b) {
        return b.time < a.time || (b.time == a.time && b.id < a.id) ? b : a;
    }
    std::vector<Node> nodes_;  // nodes_[1] is the root; leaves at [leaves_, 2 leaves_)
    std::uint32_t leaves_ = 1;
};

}  // namespace carom
