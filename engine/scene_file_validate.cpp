// Scene files, checked as a whole, after command-line overrides: a box or a
// packing, groups and disks in range and inside the box, regions identical
// or disjoint.
#include <cmath>
#include <sstream>
#include <string>

#include "engine/constants.h"
#include "engine/error_message.h"
#include "engine/scene.h"
#include "engine/scene_region.h"

namespace carom {
namespace {

// "[x_min, y_min, x_max, y_max]", for messages.
std::string regionText(const Region& r) {
    std::ostringstream text;
    text << '[' << r.xMin << ", " << r.yMin << ", " << r.xMax << ", " << r.yMax << ']';
    return text.str();
}

void requireRange(const std::string& where, const char* name, float min, float max) {
    if (!(std::isfinite(min) && min > 0.0f && std::isfinite(max) && max >= min))
        fail(where, ": ", name, " must be > 0 and finite, a range with min <= max; got [", min, ", ", max, "]");
}

void validateGroup(const SceneFileDef& scene, const GroupDef& g) {
    std::ostringstream whereText;
    whereText << scene.path << ':' << g.line << ": " << g.name;
    const std::string where = whereText.str();
    if (g.count < 1) fail(where, ": count must be >= 1");
    requireRange(where, "radius", g.radiusMin, g.radiusMax);
    requireRange(where, "mass", g.massMin, g.massMax);
    requireNonNegative(where + ": speed", g.speed);
    if (!(std::isfinite(g.temperature) && g.temperature >= 0.0f))
        fail(where, ": temperature must be a finite number > 0, got ", g.temperature);
    if (!g.region) return;
    if (scene.packing > 0) fail(where, ": a region needs a known box: give box = [W, H] instead of packing");
    const Region& r = *g.region;
    if (r.xMax > scene.world.width || r.yMax > scene.world.height)
        fail(where, ": region ", regionText(r), " extends past the ", scene.world.width, " x ", scene.world.height,
             " box");
}

void validateDisk(const SceneFileDef& scene, const DiskDef& d, std::size_t index) {
    std::ostringstream whereText;
    whereText << scene.path << ':' << d.line << ": disk[" << index + 1 << ']';
    const std::string where = whereText.str();
    if (scene.packing > 0) fail(where, ": a disk needs a known box: give box = [W, H] instead of packing");
    const float r = d.radius, w = scene.world.width, h = scene.world.height;
    const float2 x = d.position;
    // The same bounds as validateParticles, so a placed disk is accepted there.
    if (!(x.x >= r && x.x <= w - r && x.y >= r && x.y <= h - r))
        fail(where, ": position (", x.x, ", ", x.y, ") with radius ", r, " puts the disk outside the ", w, " x ", h,
             " box; the centre must lie in [", r, ", ", w - r, "] x [", r, ", ", h - r, "]");
}

// Regions shared by several groups hold one mixed lattice; regions of
// different groups must not cut into each other, or their disks could overlap.
void validateRegions(const SceneFileDef& scene) {
    for (std::size_t a = 0; a < scene.groups.size(); ++a) {
        for (std::size_t b = a + 1; b < scene.groups.size(); ++b) {
            const GroupDef& ga = scene.groups[a];
            const GroupDef& gb = scene.groups[b];
            const Region ra = ga.region.value_or(wholeBox(scene));
            const Region rb = gb.region.value_or(wholeBox(scene));
            if (!sameRegion(ra, rb) && regionsOverlap(ra, rb))
                fail(scene.path, ':', gb.line, ": ", gb.name, ": region ", regionText(rb), " overlaps region ",
                     regionText(ra), " of ", ga.name, " (line ", ga.line,
                     "); give groups the same region to mix them, or disjoint regions");
        }
    }
}

}  // namespace

void validate(const SceneFileDef& scene) {
    const std::string& where = scene.path;
    if (scene.packing > 0) {
        if (!(std::isfinite(scene.packing) && scene.packing <= kMaxPacking))
            fail(where, ": packing must be in (0, ", kMaxPacking, "], got ", scene.packing);
    } else if (!(std::isfinite(scene.world.width) && scene.world.width > 0 && std::isfinite(scene.world.height) &&
                 scene.world.height > 0)) {
        fail(where, ": the box must be two finite numbers > 0, got ", scene.world.width, " x ", scene.world.height);
    }
    WorldDef motion = scene.world;
    motion.width = motion.height = 1.0f;  // the box was checked above, or comes from packing
    try {
        validate(motion);
    } catch (const Error& e) {
        fail(where, ": ", e.what());
    }
    if (scene.groups.empty() && scene.disks.empty())
        fail(where, ": the scene has no particles: add a [[group]] (count = N) or a [[disk]]");
    std::uint64_t total = scene.disks.size();
    for (const GroupDef& g : scene.groups) {
        validateGroup(scene, g);
        total += g.count;
    }
    if (total > kMaxParticles) fail(where, ": ", total, " particles; allowed: at most ", kMaxParticles);
    validateRegions(scene);
    for (std::size_t i = 0; i < scene.disks.size(); ++i) validateDisk(scene, scene.disks[i], i);
    if (scene.output.every < 1) fail(where, ": output every must be >= 1");
}

}  // namespace carom
