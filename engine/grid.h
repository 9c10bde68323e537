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
#include <vector>

#include "engine/carom.h"
#include "kernels/physics.h"

namespace carom {

struct Grid {
    GridGeometry geometry{};
    std::vector<GridCell> cells;              // cols * rows, row-major
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

// How far every disk may move in a step while the 3x3 cells around the cell
// it started in still hold every disk it can touch: half of what a cell's
// width exceeds the largest diameter by [length]; infinite along an axis
// whose every cell the 3x3 search reaches.
float gridTravelAllowance(const GridGeometry& geometry, float width, float height, float maxRadius,
                          Boundary boundary);

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
