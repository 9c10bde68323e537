// carom's internal definitions: the particles a scene starts from and the
// checks of a run's start. The public definitions (WorldDef, SceneDef,
// EngineDef, the limits, the checks of a world and a scene) are in
// include/carom/types.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <carom/types.h>

#include "kernels/particle.h"

namespace carom {

// The particles a scene starts from and the box they fill.
struct InitialState {
    float width = 0.0f;
    float height = 0.0f;
    std::vector<Particle> particles;
};

// Builds the initial particles of a scene. Deterministic in scene.seed.
InitialState makeInitialState(const SceneDef& scene);

// Throws Error unless a scene file's scene can be placed: a box or a
// packing, regions and disks inside the box, regions either identical or
// disjoint.
void validate(const SceneFileDef& scene);

// A scene file's particles and box: the groups' disks in group order (ids
// 0..), then the [[disk]]s. Deterministic in scene.seed; a single group
// filling the box equals makeInitialState(SceneDef) with the same values.
InitialState makeInitialState(const SceneFileDef& scene);

// Throws Error unless every particle has finite values, mass and radius in
// their ranges (kMinMass.., kMinLength..), fits in the box and lies inside
// it. `what` names the source in messages (for example the file the
// particles came from).
void validateParticles(const std::vector<Particle>& particles, const WorldDef& world, const std::string& what);

// The motion checks of validateStart alone (the world's dt and gravity with
// the particles' speeds), for a change of dt or gravity on a running world.
void requireValidMotion(const std::vector<Particle>& particles, const WorldDef& world, const std::string& what);

// The checks of a run's start, beyond validateParticles (which it calls):
// throws Error where the motion leaves the ranges in which float32 results
// are valid (box diagonal x the largest reachable speed within
// kMaxLengthTimesSpeed; a step that moves a typical disk by at least
// kMinStepSpacings float spacings and, without max-travel substeps, the
// fastest by at most the smaller box side) or two disks share a centre.
// Returns warnings where results are less accurate than usual: a step of
// fewer than kWarnStepSpacings spacings, and overlaps deeper than a step
// closes (a checkpoint holds the small ones a step leaves; a scene file
// refuses any), with the pair and the overlap. O(N log N) however the disks
// lie (findOverlaps).
// Not part of validateParticles, so that the viewer can upload a flicked or
// dropped disk without being refused.
// With DeepOverlaps::Refuse, such an overlap is refused rather than warned of.
std::vector<std::string> validateStart(const std::vector<Particle>& particles, const WorldDef& world,
                                       const std::string& what, DeepOverlaps deepOverlaps = DeepOverlaps::Warn);

}  // namespace carom
