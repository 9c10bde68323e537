// The regions of a scene file's groups (internal): what its checks
// (scene_file_validate.cpp) and its placement (scene_placement.cpp) share.
#pragma once

#include "engine/scene.h"

namespace carom {

// The region of a group that names none.
inline Region wholeBox(const SceneFileDef& scene) { return Region{0, 0, scene.world.width, scene.world.height}; }

inline bool sameRegion(const Region& a, const Region& b) {
    return a.xMin == b.xMin && a.yMin == b.yMin && a.xMax == b.xMax && a.yMax == b.yMax;
}

inline bool regionsOverlap(const Region& a, const Region& b) {
    return a.xMin < b.xMax && b.xMin < a.xMax && a.yMin < b.yMax && b.yMin < a.yMax;
}

}  // namespace carom
