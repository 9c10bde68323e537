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
#include <string>
#include <vector>

#include "engine/carom.h"
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

// The box as kernels/physics.h sees it.
inline CaromBox caromBoxOf(const WorldDef& world) {
    return carom_box(world.width, world.height, world.boundary == Boundary::Periodic ? 1 : 0);
}

// Calls visit(i, j) for every pair i < j whose disks overlap, found with the
// same 3x3 search the collision kernel uses (across the edges of a periodic
// box, to the nearest image).
template <class Visit>
void forEachOverlappingPair(const Particle* particles, std::size_t count, const Grid& grid, CaromBox box,
                            Visit&& visit);

}  // namespace carom

#include "engine/grid_search.inl"
