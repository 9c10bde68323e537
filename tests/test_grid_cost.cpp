// estimateGridCost: what one cell size for every disk costs when the largest
// disk is far larger than the typical one.
#include "engine/grid.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

// `count` disks of radius `radius` on a square lattice of spacing 2 filling
// a side x side box from its corner, and one of radius `largest` at the
// far corner when it is > 0.
std::vector<Particle> disks(int count, float radius, float side, float largest) {
    std::vector<Particle> particles;
    const int perRow = static_cast<int>(side / 2.0f);
    for (int i = 0; i < count; ++i)
        particles.push_back(disk(1.0f + 2.0f * float(i % perRow), 1.0f + 2.0f * float(i / perRow), 0, 0, 1, radius));
    if (largest > 0) particles.push_back(disk(side - largest, side - largest, 0, 0, 1, largest));
    return particles;
}

}  // namespace

TEST_CASE("one disk of radius 50 among 20 000 of radius 0.5 makes a step hundreds of times dearer") {
    // The case: measured 239x (simultaneous) and 538x (pairwise) in a 300 x 300 box.
    for (CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Pairwise}) {
        WorldDef world = box(300, 300);
        world.collisions = scheme;
        const GridCost cost = estimateGridCost(disks(20000, 0.5f, 300, 50), world);
        CHECK(cost.largestRadius == 50.0f);
        CHECK(cost.typicalRadius == 0.5f);
        CHECK(cost.factor > 200);
        CHECK(cost.factor < 1000);
        CHECK(gridCostWarning(disks(20000, 0.5f, 300, 50), world).find("about") != std::string::npos);
    }
}

TEST_CASE("equal and mildly mixed radii cost nothing extra and draw no warning") {
    const WorldDef world = box(300, 300);
    const GridCost equal = estimateGridCost(disks(20000, 0.5f, 300, 0), world);
    CHECK(equal.factor == 1.0);
    CHECK(estimateGridCost(disks(20000, 0.5f, 300, 1.0f), world).factor < 2);
    CHECK(gridCostWarning(disks(20000, 0.5f, 300, 1.0f), world).empty());
}
