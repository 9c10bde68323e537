// Numbers that several parts of carom share (internal: not part of the public
// API; kPi is public, in carom/types.h).
#pragma once

#include <carom/types.h>

namespace carom {

// The highest packing fraction, sum(pi r^2) / (W H), that the lattice
// placement of a scene is asked for: it reaches no higher for equal disks.
constexpr float kMaxPacking = 0.7f;

}  // namespace carom
