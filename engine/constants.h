// Numbers that several parts of carom share (internal: not part of the public API).
#pragma once

namespace carom {

constexpr double kPi = 3.14159265358979323846;

// The highest packing fraction, sum(pi r^2) / (W H), that the lattice
// placement of a scene is asked for: it reaches no higher for equal disks.
constexpr float kMaxPacking = 0.7f;

}  // namespace carom
