// The checks of a snapshot's (a checkpoint's) counts, which World::restore
// and the checkpoint reader share.
#pragma once

#include <cstdint>
#include <string>

#include <carom/types.h>

namespace carom {

// The most collisions a snapshot may hold: far more than any run reaches
// (2^63 at 10^9 a second take three centuries), and with as many again to
// spare, so that a run continued from one never takes the count past 2^64.
constexpr std::uint64_t kMaxSnapshotCollisions = std::uint64_t(1) << 63;

// What is wrong with `snapshot`'s step, time and collision count: a time
// that is not finite, or that `step` steps of a dt in [kMinDt, kMaxDt]
// cannot add up to (0 at step 0), or more than kMaxSnapshotCollisions
// collisions. Empty when nothing is.
std::string snapshotCountsProblem(const Snapshot& snapshot);

}  // namespace carom
