#include "engine/grid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/physics.h"

namespace carom {

GridGeometry gridGeometryFor(float width, float height, float maxRadius, std::size_t particleCount, Boundary boundary,
                             float slack) {
    // A hair more than the diameter: float rounding of position * cellsPerLength
    // must never put two touching disks two cells apart.
    const double diameter = 2.0 * maxRadius * (1.0 + 1e-5);
    // Up to 4 cells a disk, and no more than an int counts (from 5 * 10^8 disks).
    const double maxCells = std::min(4.0 * double(particleCount), 2e9) + 1024.0;
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

GridGeometry gridGeometryFor(const WorldDef& world, float maxRadius, std::size_t particleCount) {
    const float slack = world.collisions == CollisionScheme::Pairwise ? kPairwiseCellSlack * 2.0f * maxRadius : 0.0f;
    return gridGeometryFor(world.width, world.height, maxRadius, particleCount, world.boundary, slack);
}

namespace {

// A disk's share of a step besides the pairs it checks (its cells, its
// integration, its place in the grid build), in pair checks, by scheme (a
// pairwise check solves for a contact time, so it weighs more). Calibrated
// on an AMD EPYC with 2 cores under other load, one run each: one disk of radius
// 50 among 20 000 of radius 0.5 in a 300 x 300 box made a step 239 times
// (simultaneous) and 538 times (pairwise) dearer, estimated 322 and 723; one
// of radius 20 beside 1 500 of radius 0.5 (tests/data/large_radius.toml) 34
// and 68 times, estimated 25 and 56.
constexpr double kSimultaneousDiskCost = 60.0;
constexpr double kPairwiseDiskCost = 25.0;

// The pairs a disk checks in a step: the disks in the 3x3 cells around its
// own (fewer cells where the grid is narrower than 3 in a walled box).
double pairChecksPerDisk(const GridGeometry& g, std::size_t count, Boundary boundary) {
    const int reach = 3;
    const double cols = boundary == Boundary::Periodic ? reach : std::min(reach, g.cols);
    const double rows = boundary == Boundary::Periodic ? reach : std::min(reach, g.rows);
    return cols * rows * double(count) / (double(g.cols) * double(g.rows));
}

}  // namespace

float largestRadius(const Particle* particles, std::size_t count) {
    const auto n = static_cast<std::int64_t>(count);
    float largest = 0.0f;
#pragma omp parallel for reduction(max : largest) schedule(static) if (n >= kParallelLength)
    for (std::int64_t i = 0; i < n; ++i) largest = std::max(largest, particles[i].radius);
    return largest;
}

GridCost estimateGridCost(const std::vector<Particle>& particles, const WorldDef& world) {
    GridCost cost;
    if (particles.empty()) return cost;
    const std::size_t n = particles.size();
    cost.typicalRadius = kthSmallest(n, n / 2, [&](std::size_t i) { return particles[i].radius; });
    cost.largestRadius = largestRadius(particles.data(), n);
    const double largest = pairChecksPerDisk(gridGeometryFor(world, cost.largestRadius, n), n, world.boundary);
    const double typical = pairChecksPerDisk(gridGeometryFor(world, cost.typicalRadius, n), n, world.boundary);
    const double disk = world.collisions == CollisionScheme::Pairwise ? kPairwiseDiskCost : kSimultaneousDiskCost;
    cost.factor = std::max(1.0, (disk + largest) / (disk + typical));
    return cost;
}

std::string gridCostWarning(const std::vector<Particle>& particles, const WorldDef& world) {
    const GridCost cost = estimateGridCost(particles, world);
    if (!(cost.factor > kGridCostWarningFactor)) return "";
    std::ostringstream message;
    message << "the largest disk (radius " << cost.largestRadius << ") sizes the grid's cells for all "
            << particles.size() << " disks, whose typical (median) radius is " << cost.typicalRadius
            << ": each step costs about " << std::lround(cost.factor)
            << " times what it would among disks of the typical size (carom's grid has one cell size)";
    return message.str();
}

float gridTravelAllowance(const GridGeometry& geometry, float width, float height, float maxRadius, Boundary boundary) {
    const int reachesAll = boundary == Boundary::Periodic ? 3 : 2;  // cells a 3x3 search always covers
    const double diameter = 2.0 * maxRadius * (1.0 + 1e-5);
    double allowance = HUGE_VAL;
    if (geometry.cols > reachesAll) allowance = std::min(allowance, 0.5 * (double(width) / geometry.cols - diameter));
    if (geometry.rows > reachesAll) allowance = std::min(allowance, 0.5 * (double(height) / geometry.rows - diameter));
    return static_cast<float>(std::max(0.0, allowance));
}

DiskCells sortIntoCells(const Particle* particles, std::size_t count, CaromBox box) {
    DiskCells cells;
    cells.box = box;
    const float maxRadius = largestRadius(particles, count);
    // A hair more than the diameter, as in gridGeometryFor; at most 2^20 cells
    // a side, so that the cell's number fits (wider cells are still correct).
    const double diameter = 2.0 * maxRadius * (1.0 + 1e-5);
    const auto cellsAlong = [&](float extent) {
        return diameter > 0.0 ? std::clamp(std::floor(extent / diameter), 1.0, 1048576.0) : 1.0;
    };
    const double cols = cellsAlong(box.width), rows = cellsAlong(box.height);
    cells.cols = std::uint64_t(cols);
    cells.rows = std::uint64_t(rows);
    // Clamped into the box: a disk outside it stays next to its neighbours.
    const auto coord = [](float x, float extent, double n) {
        return std::uint64_t(std::clamp(std::floor(double(x) * n / extent), 0.0, n - 1.0));
    };
    // Non-finite centres get the last cell and the centre 0 (NaN would not
    // sort), sort to the end, and are cut off.
    constexpr std::uint64_t kLeftOut = ~std::uint64_t{0};
    cells.sorted.resize(count);
    const auto n = static_cast<std::int64_t>(count);
    std::int64_t finite = 0;
#pragma omp parallel for reduction(+ : finite) schedule(static) if (n >= kParallelLength)
    for (std::int64_t i = 0; i < n; ++i) {
        const float x = particles[i].position.x + 0.0f, y = particles[i].position.y + 0.0f;
        const bool kept = std::isfinite(x) && std::isfinite(y);
        finite += kept;
        const std::uint64_t cell =
            kept ? coord(y, box.height, rows) * cells.cols + coord(x, box.width, cols) : kLeftOut;
        cells.sorted[std::size_t(i)] = {cell, kept ? x : 0.0f, kept ? y : 0.0f, static_cast<std::uint32_t>(i),
                                        particles[i].radius};
    }
    sortInParallel(cells.sorted, [](const DiskCells::Entry& a, const DiskCells::Entry& b) {
        if (a.cell != b.cell) return a.cell < b.cell;
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        return a.id < b.id;
    });
    cells.sorted.resize(std::size_t(finite));
    return cells;
}

std::vector<std::size_t> cellRuns(const DiskCells& cells, std::size_t entries) {
    const auto& sorted = cells.sorted;
    std::vector<std::size_t> runs{0};
    while (runs.back() < sorted.size()) {
        std::size_t end = std::min(sorted.size(), runs.back() + std::max<std::size_t>(entries, 1));
        while (end < sorted.size() && sorted[end].cell == sorted[end - 1].cell) ++end;
        runs.push_back(end);
    }
    return runs;
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

void GridBuilder::prepare(std::size_t count, Grid& grid, int threads) {
    const GridGeometry& g = grid.geometry;
    const std::size_t cells = std::size_t(g.cols) * g.rows;
    // A block of fewer than ~1 000 disks costs more in its histogram than it saves.
    const std::size_t usefulBlocks = std::max<std::size_t>(1, count / 1024);
    blocks_ = static_cast<int>(
        std::min<std::size_t>({std::size_t(std::max(threads, 1)), std::size_t(kMaxGridBlocks), usefulBlocks}));
    grid.cells.resize(cells);
    grid.sortedIndices.resize(count);
    grid.cellOf.resize(count);
    slots_.resize(std::size_t(blocks_) * cells);
    partTotals_.resize(std::size_t(blocks_));
}

void GridBuilder::run(int phase, int b, const Particle* particles, std::size_t count, Grid& grid) {
    const GridGeometry& g = grid.geometry;
    const std::size_t cells = grid.cells.size();
    std::uint32_t* cellOf = grid.cellOf.data();
    std::uint32_t* slots = slots_.data() + std::size_t(b) * cells;
    const std::size_t begin = blockBegin(count, b), end = blockBegin(count, b + 1);
    // Part b of the cells, for the scan.
    const std::size_t firstCell = cells * std::size_t(b) / blocks_, lastCell = cells * std::size_t(b + 1) / blocks_;
    switch (phase) {
        case 0:  // each disk's cell; the block's count per cell
            std::fill(slots, slots + cells, 0u);
            for (std::size_t i = begin; i < end; ++i) {
                const auto cell = static_cast<std::uint32_t>(carom_cell_index(particles[i].position, g));
                cellOf[i] = cell;
                ++slots[cell];
            }
            break;
        case 1: {  // the disks in part b of the cells
            std::uint32_t total = 0;
            for (int k = 0; k < blocks_; ++k) {
                const std::uint32_t* counts = slots_.data() + std::size_t(k) * cells;
                for (std::size_t c = firstCell; c < lastCell; ++c) total += counts[c];
            }
            partTotals_[b] = total;
            break;
        }
        case 2: {  // each cell's start, and each block's first slot in it
            std::uint32_t next = 0;
            for (int p = 0; p < b; ++p) next += partTotals_[p];
            for (std::size_t c = firstCell; c < lastCell; ++c) {
                const std::uint32_t start = next;
                for (int k = 0; k < blocks_; ++k) {
                    std::uint32_t& slot = slots_[std::size_t(k) * cells + c];
                    const std::uint32_t n = slot;
                    slot = next;
                    next += n;
                }
                grid.cells[c] = GridCell{start, next - start};
            }
            break;
        }
        case 3:  // the block's ids, ascending, into their cells
            for (std::size_t i = begin; i < end; ++i)
                grid.sortedIndices[slots[cellOf[i]]++] = static_cast<std::uint32_t>(i);
            break;
        default: break;
    }
}

void buildGridParallel(const Particle* particles, std::size_t count, Grid& grid, GridBuilder& builder, int threads) {
    threads = std::max(threads, 1);
    builder.prepare(count, grid, threads);
    const int blocks = builder.blocks();
#pragma omp parallel num_threads(threads) if (threads > 1)
    for (int phase = 0; phase < GridBuilder::kPhases; ++phase) {
#pragma omp for schedule(static, 1)
        for (int b = 0; b < blocks; ++b) builder.run(phase, b, particles, count, grid);
    }
}

}  // namespace carom
