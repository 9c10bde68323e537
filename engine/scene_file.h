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

#include "engine/carom.h"

namespace carom {

// An axis-aligned rectangle inside the box [length].
struct Region {
    float xMin = 0.0f;
    float yMin = 0.0f;
    float xMax = 0.0f;
    float yMax = 0.0f;
};

// One [[group]]: `count` disks placed without overlap on a jittered
// hexagonal lattice over their region. Groups that name the same region (or
// none) share one lattice, their disks shuffled over its sites.
struct GroupDef {
    std::string name;         // shown in messages; default "group[K]", K counting from 1
    std::size_t line = 0;     // line of its [[group]] header, for messages
    std::uint32_t count = 0;  // number of disks, >= 1; required
    float radiusMin = 1.0f;   // radius, fixed or uniform in [radiusMin, radiusMax] [length], > 0
    float radiusMax = 1.0f;
    float massMin = 1.0f;  // mass, fixed or uniform in [massMin, massMax] [mass], > 0
    float massMax = 1.0f;
    float speed = 1.0f;            // speed of every disk, random directions [length/time], >= 0
    float temperature = 0.0f;      // > 0: Maxwell-Boltzmann velocities at k_B T = temperature
                                   //   [mass length^2/time^2] instead of `speed`; 0 = off
    std::optional<Region> region;  // where the disks go; default the whole box
};

// One [[disk]]: a single disk, exactly where it is put.
struct DiskDef {
    std::size_t line = 0;   // line of its [[disk]] header, for messages
    float2 position{0, 0};  // centre [length]; required, the disk must lie inside the box
    float2 velocity{0, 0};  // [length/time]; default at rest
    float mass = 1.0f;      // [mass], > 0
    float radius = 1.0f;    // [length], > 0
};

// [output]: the files a run writes. Paths are relative to the working
// directory, like paths on the command line. Empty = not written.
struct OutputDef {
    std::string trajectory;     // extended XYZ frames (engine/trajectory.h)
    std::string stats;          // CSV rows (engine/stats.h)
    std::string checkpoint;     // binary checkpoint (engine/checkpoint.h), also written when the run ends
    std::string state;          // the final state as CSV (engine/state_csv.h)
    std::uint64_t every = 100;  // steps between samples and checkpoints, >= 1
};

struct SceneFile {
    std::string path;            // the file, for messages
    WorldDef world;              // box (0 x 0 when `packing` sizes it), dt, gravity, boundary,
                                 //   collision scheme
    float packing = 0.0f;        // > 0: the box is square, sized so the disks cover this
                                 //   area fraction, in (0, 0.7]; instead of world's box
    std::uint64_t steps = 1000;  // steps `carom run` takes
    std::uint64_t seed = 1;      // random seed of the placement and the velocities
    std::vector<GroupDef> groups;
    std::vector<DiskDef> disks;  // ids follow the groups' disks, in file order
    OutputDef output;
};

// Reads and validates a scene file; throws Error naming file, line, key,
// value and what is allowed.
SceneFile readSceneFile(const std::string& path);

// The same for TOML text; `path` names it in messages.
SceneFile parseSceneFile(std::string_view text, const std::string& path);

// Throws Error unless the scene can be placed: a box or a packing, regions
// and disks inside the box, regions either identical or disjoint.
void validate(const SceneFile& scene);

// The scene's particles and box: the groups' disks in group order (ids
// 0..), then the [[disk]]s. Deterministic in scene.seed; a single group
// filling the box equals makeInitialState(SceneDef) with the same values.
InitialState makeInitialState(const SceneFile& scene);

}  // namespace carom
