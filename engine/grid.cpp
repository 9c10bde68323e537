#include "engine/grid.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/physics.h"

namespace carom {

GridGeometry gridGeometryFor(float width, float height, float maxRadius, std::size_t particleCount,
                             Boundary boundary, float slack) {
    // A hair more than the diameter: float rounding of position * cellsPerLength
    // must never put two touching disks two cells apart.
    const double diameter = 2.0 * maxRadius * (1.0 + 1e-5);
    const double maxCells = 4.0 * double(particleCount) + 1024.0;
    const double cellSize = std::max(diameter + slack, std::sqrt(double(width) * height / maxCells));
    GridGeometry g;
    g.cols = static_cast<int>(std::clamp(std::floor(width / cellSize), 1.0, maxCells));
    g.rows = static_cast<int>(std::clamp(std::floor(height / cellSize), 1.0, maxCells));
    if (boundary == Boundary::Periodic) {
        if (width < 3.0 * diameter || height < 3.0 * diameter)
            throw Error("a periodic box must be at least 3 largest diameters (3 x " + std::to_string(2.0 * maxRadius) +
                        ") wide and high, got " + std::to_string(width) + " x " + std::to_string(height));
        g.cols = std::max(g.cols, 3);
        g.rows = std::max(g.rows, 3);
    }
    g.cellsPerLengthX = static_cast<float>(g.cols / double(width));
    g.cellsPerLengthY = static_cast<float>(g.rows / double(height));
    return g;
}

float gridTravelAllowance(const GridGeometry& geometry, float width, float height, float maxRadius,
                          Boundary boundary) {
    const int reachesAll = boundary == Boundary::Periodic ? 3 : 2;  // cells a 3x3 search always covers
    const double diameter = 2.0 * maxRadius * (1.0 + 1e-5);
    double allowance = HUGE_VAL;
    if (geometry.cols > reachesAll) allowance = std::min(allowance, 0.5 * (double(width) / geometry.cols - diameter));
    if (geometry.rows > reachesAll) allowance = std::min(allowance, 0.5 * (double(height) / geometry.rows - diameter));
    return static_cast<float>(std::max(0.0, allowance));
}

void buildGrid(const Particle* particles, std::size_t count, Grid& grid) {
    const GridGeometry& g = grid.geometry;
    grid.cells.assign(std::size_t(g.cols) * g.rows, GridCell{0, 0});
    grid.sortedIndices.resize(count);
    grid.cellOf.resize(count);

    for (std::size_t i = 0; i < count; ++i) {
        const auto cell = static_cast<std::uint32_t>(carom_cell_index(particles[i].position, g));
        grid.cellOf[i] = cell;
        ++grid.cells[cell].count;
    }
    std::uint32_t start = 0;
    for (GridCell& cell : grid.cells) {
        cell.start = start;
        start += cell.count;
    }
    // Scatter in ascending id, so each cell lists its particles in id order.
    // `count` doubles as the fill cursor and ends where it began.
    for (GridCell& cell : grid.cells) cell.count = 0;
    for (std::size_t i = 0; i < count; ++i) {
        GridCell& cell = grid.cells[grid.cellOf[i]];
        grid.sortedIndices[cell.start + cell.count++] = static_cast<std::uint32_t>(i);
    }
}

}  // namespace carom
