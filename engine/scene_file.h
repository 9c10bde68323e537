// Scene files: a whole simulation in TOML (read with toml++). The README's
// "Scene files" section is the user's reference; in short:
//
//   box = [100, 60]          # or packing = 0.3 for a square box (one group, no regions, no disks)
//   boundary = "walls"       # reflective walls, or "periodic"
//   collisions = "pairwise"  # or "simultaneous"; default WorldDef's
//   dt = 0.01                # or "auto": substeps of at most max_travel = 0.2 radii
//                            # steps = 1000, gravity = [0, 0], seed = 1 are the other defaults
//   [[group]]                # disks placed on a jittered lattice, without overlap
//   count = 500
//   radius = 1.0             # or [min, max]; mass likewise
//   temperature = 1.0        # or speed = 1.0
//   region = [0, 0, 50, 60]  # x_min, y_min, x_max, y_max; default the whole box
//   [[disk]]                 # one disk, exactly where it is put
//   position = [80, 30]
//   velocity = [-2, 0]
//   [output]
//   trajectory = "run.xyz"   # also stats, checkpoint, state; every = 100
//
// Every value is checked for type, range and finiteness, and unknown keys are
// errors: the message names the file, the line, the key, the bad value and
// what is allowed.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <carom/io.h>

#include "engine/carom.h"

namespace carom {

// Throws Error unless the scene can be placed: a box or a packing, regions
// and disks inside the box, regions either identical or disjoint.
void validate(const SceneFileDef& scene);

// The scene's particles and box: the groups' disks in group order (ids
// 0..), then the [[disk]]s. Deterministic in scene.seed; a single group
// filling the box equals makeInitialState(SceneDef) with the same values.
InitialState makeInitialState(const SceneFileDef& scene);

}  // namespace carom
