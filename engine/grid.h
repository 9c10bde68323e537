// The shared grid builder: the broad phase that both backends use.
//
// Each step, every particle is hashed to the cell that holds its centre; a
// counting sort groups the particle ids by cell, ascending within a cell
// (which fixes the order in which neighbours are visited and summed). A disk
// can only touch disks in the 3x3 cells around its own, because a cell is at
// least as wide and tall as the largest disk diameter.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/parallel.h"
#include "engine/scene.h"
#include "kernels/physics.h"

namespace carom {

struct Grid {
    GridGeometry geometry{};
    std::vector<GridCell> cells;               // cols * rows, row-major
    std::vector<std::uint32_t> sortedIndices;  // particle ids grouped by cell
    std::vector<std::uint32_t> cellOf;         // the cell of each particle, by id
};

// The cell layout for a box and the largest radius. Cells are as small as the
// largest diameter plus `slack` allows, but never more than about 4 per
// particle, so a dilute system does not allocate a huge empty grid (larger
// cells are still correct, only slower). A periodic box gets at least 3 x 3
// cells, so the 3x3 search around a disk never meets one cell twice; throws
// Error if the box is too small for that. The slack [length] is room for
// the disks to move within a step (the pairwise scheme).
GridGeometry gridGeometryFor(float width, float height, float maxRadius, std::size_t particleCount,
                             Boundary boundary = Boundary::Walls, float slack = 0.0f);

// The pairwise scheme's grid: cells wider than the largest diameter by this
// fraction of it, room for the disks to move within a step.
constexpr float kPairwiseCellSlack = 0.15f;

// The cells a backend uses for `particleCount` disks of at most `maxRadius`
// in `world`: gridGeometryFor with the slack its collision scheme needs.
GridGeometry gridGeometryFor(const WorldDef& world, float maxRadius, std::size_t particleCount);

// The largest radius of particles[0, count) (0 for none), in parallel.
float largestRadius(const Particle* particles, std::size_t count);

// One cell size serves every disk, sized for the largest: among much smaller
// disks, each searches cells far wider than it needs. What that costs.
struct GridCost {
    float largestRadius = 0.0f;
    float typicalRadius = 0.0f;  // the median
    // A step's cost with cells for the largest disk over its cost with cells
    // for the typical one (>= 1, estimated: a disk's cost is the pairs it
    // checks in the 3x3 cells around its own plus a fixed share, calibrated
    // within about 35 % of measured slowdowns: engine/grid.cpp).
    double factor = 1.0;
};
GridCost estimateGridCost(const std::vector<Particle>& particles, const WorldDef& world);

// The cost factor above which gridCostWarning warns.
constexpr double kGridCostWarningFactor = 10.0;
// A warning that names the largest and the typical radius and the factor,
// when the factor is above kGridCostWarningFactor; empty otherwise.
std::string gridCostWarning(const std::vector<Particle>& particles, const WorldDef& world);

// How far every disk may move in a step while the 3x3 cells around the cell
// it started in still hold every disk it can touch: half of what a cell's
// width exceeds the largest diameter by [length]; infinite along an axis
// whose every cell the 3x3 search reaches.
float gridTravelAllowance(const GridGeometry& geometry, float width, float height, float maxRadius, Boundary boundary);

// Fills grid.cells, grid.sortedIndices and grid.cellOf for the particles,
// keeping grid.geometry. Reuses the vectors' storage from step to step.
void buildGrid(const Particle* particles, std::size_t count, Grid& grid);

// buildGrid split into phases for a team of threads: the same cells,
// sortedIndices and cellOf, bit for bit, whatever the number of threads.
// The ids are cut into contiguous blocks; each block counts its disks per
// cell (its own histogram), a scan over the cells (cut into as many parts)
// turns the counts into each block's first slot in each cell (cell by cell,
// block 0 first), and each block scatters its ids in ascending order:
// within a cell, the blocks' ids follow each other in block order, so every
// cell still lists its disks in ascending id. The scratch is blocks x cells
// counters; blocks are at most kMaxGridBlocks, and about one per thread.
class GridBuilder {
public:
    static constexpr int kPhases = 4;  // count, scan totals, scan offsets, scatter
    static constexpr int kMaxGridBlocks = 8;

    // Sizes grid's vectors and the scratch for `count` disks and a team of
    // `threads` threads; call before the phases, outside the team.
    void prepare(std::size_t count, Grid& grid, int threads);
    // The blocks (and parts) of each phase, as prepare chose them.
    int blocks() const { return blocks_; }
    // Block (or part) `block` of phase `phase` (0 .. kPhases-1). The blocks
    // of a phase may run at once, on any threads; every block of phase p
    // must have finished before any of phase p + 1 starts.
    void run(int phase, int block, const Particle* particles, std::size_t count, Grid& grid);

private:
    std::size_t blockBegin(std::size_t count, int block) const { return count * std::size_t(block) / blocks_; }

    int blocks_ = 1;
    std::vector<std::uint32_t> slots_;       // blocks_ x cells: counts, then each block's next slot
    std::vector<std::uint32_t> partTotals_;  // the disks in each part of the cells (blocks_ parts)
};

// buildGrid on a team of `threads` OpenMP threads (one without OpenMP) with
// GridBuilder: the same output as buildGrid.
void buildGridParallel(const Particle* particles, std::size_t count, Grid& grid, GridBuilder& builder, int threads);

// The box as kernels/physics.h sees it.
inline CaromBox caromBoxOf(const WorldDef& world) {
    return carom_box(world.width, world.height, world.boundary == Boundary::Periodic ? 1 : 0);
}

// The disks sorted into square cells at least as wide as the largest
// diameter, however many cells that takes (Grid caps them at about 4 per
// disk, so that a dilute step allocates little): the broad phase of the
// checks of a state, where disks piled into one place must cost what their
// overlaps do, not N^2. Sorted by cell, then centre, then id, so that equal
// centres lie next to each other. Disks whose centre is not finite are left
// out: they overlap nothing.
struct DiskCells {
    struct Entry {
        std::uint64_t cell;  // row * cols + column
        float x, y;          // the centre (-0 read as 0, so that equal centres sort together)
        std::uint32_t id;
        float radius;  // the search reads the entries alone
    };
    UninitialisedVector<Entry> sorted;
    std::uint64_t cols = 1, rows = 1;
    CaromBox box{};
};
// O(N log N).
DiskCells sortIntoCells(const Particle* particles, std::size_t count, CaromBox box);

// Calls visit(i, j) for the pairs i < j whose disks overlap (the collision
// kernel's test, across the edges of a periodic box to the nearest image),
// cell by cell, until visit returns false; returns whether every pair was
// visited. Costs the pairs in neighbouring cells: with disks of similar
// sizes, a constant times N plus the overlapping pairs visited.
template <class Visit>
bool forEachOverlappingPair(const DiskCells& cells, Visit&& visit);
// The same for the disks in sorted[from, to) (each end a cell's first entry,
// or the end) and their partners j > i anywhere.
template <class Visit>
bool forEachOverlappingPairIn(const DiskCells& cells, std::size_t from, std::size_t to, Visit&& visit);
// Runs of whole cells of about `entries` entries each: sorted[runs[r], runs[r + 1]).
std::vector<std::size_t> cellRuns(const DiskCells& cells, std::size_t entries);

}  // namespace carom

#include "engine/grid_search.inl"
