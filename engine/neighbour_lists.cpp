#include "engine/neighbour_lists.h"

#include <algorithm>
#include <limits>

#include "kernels/physics.h"

namespace carom {

namespace {

// Calls visit(j) for every disk j != i whose centre lies within contact
// plus `skin` of disk i's (to the nearest image in a periodic box), from the
// grid's 3 x 3 cells around disk i's, which are at least that wide.
template <class Visit>
void forEachWithin(std::size_t i, const Particle* particles, const Grid& grid, CaromBox box, float skin,
                   Visit&& visit) {
    const Particle& self = particles[i];
    const GridGeometry& g = grid.geometry;
    const int cellX = carom_cell_coord(self.position.x, g.cellsPerLengthX, g.cols);
    const int cellY = carom_cell_coord(self.position.y, g.cellsPerLengthY, g.rows);
    for (int run = 0; run < 6; ++run) {
        unsigned int begin, end;
        if (!carom_neighbour_run(run, cellX, cellY, grid.cells.data(), g, box, &begin, &end)) continue;
        for (unsigned int q = begin; q < end; ++q) {
            const std::uint32_t j = grid.sortedIndices[q];
            if (j == i) continue;
            if (carom_within_reach(self, particles[j], skin, box)) visit(j);
        }
    }
}

}  // namespace

float NeighbourLists::skinFor(float asked, float maxRadius, float travel) {
    if (asked > 0.0f) return asked;
    // Half a diameter leaves the disks 0.3 radii to move between builds at
    // the pairwise scheme's usual allowance (0.15 radii a substep); a larger
    // one (cells widened in a dilute box) widens it.
    return std::max(maxRadius, 4.0f * travel);
}

std::optional<GridGeometry> NeighbourLists::gridFor(CaromBox box, float maxRadius, std::size_t count, float skin) {
    const Boundary boundary = box.periodic ? Boundary::Periodic : Boundary::Walls;
    const GridGeometry geometry = gridGeometryFor(box.width, box.height, maxRadius, count, boundary, skin);
    const double reach = 2.0 * maxRadius * (1.0 + 1e-5) + skin;
    if (double(box.width) / geometry.cols < reach || double(box.height) / geometry.rows < reach) return std::nullopt;
    return geometry;
}

bool NeighbourLists::begin(const Particle* particles, std::size_t count, float maxRadius, float skin, CaromBox box,
                           int threads, std::size_t chunk) {
    built_ = false;
    const std::optional<GridGeometry> geometry = gridFor(box, maxRadius, count, skin);
    if (!geometry) return false;
    grid_.geometry = *geometry;
    builder_.prepare(count, grid_, threads);
    particles_ = particles;
    count_ = count;
    chunk_ = std::max<std::size_t>(chunk, 1);
    skin_ = skin;
    box_ = box;
    starts_.resize(count + 1);
    origins_.resize(count);
    chunkLists_.resize((count + chunk_ - 1) / chunk_);
    return true;
}

bool NeighbourLists::build(const Particle* particles, std::size_t count, float maxRadius, float skin, CaromBox box,
                           int threads) {
    threads = std::max(threads, 1);
    const std::size_t chunk = std::max<std::size_t>(256, (count + 4 * std::size_t(threads) - 1) / (4 * threads));
    if (!begin(particles, count, maxRadius, skin, box, threads, chunk)) return false;
    buildGridParallel(particles, count, grid_, builder_, threads);
    const auto chunks = static_cast<std::int64_t>(chunkLists_.size());
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
#pragma omp for schedule(dynamic, 1)
        for (std::int64_t c = 0; c < chunks; ++c)
            for (std::size_t i = std::size_t(c) * chunk_; i < std::min(count, std::size_t(c + 1) * chunk_); ++i)
                collect(i);
#pragma omp single
        sum();
#pragma omp for schedule(static)
        for (std::int64_t c = 0; c < chunks; ++c) place(std::size_t(c));
    }
    return built_;
}

void NeighbourLists::collect(std::size_t i) {
    std::vector<std::uint32_t>& mine = chunkLists_[i / chunk_];
    if (i % chunk_ == 0) mine.clear();
    const std::size_t first = mine.size();
    forEachWithin(i, particles_, grid_, box_, skin_, [&](std::uint32_t j) { mine.push_back(j); });
    std::sort(mine.begin() + std::ptrdiff_t(first), mine.end());
    starts_[i + 1] = std::uint32_t(mine.size() - first);
    origins_[i] = particles_[i].position;
}

void NeighbourLists::sum() {
    starts_[0] = 0;
    std::uint64_t total = 0;
    for (std::size_t i = 1; i <= count_; ++i) {
        total += starts_[i];
        starts_[i] = std::uint32_t(total);
    }
    // Past 32-bit offsets (more than 64 neighbours a disk on average) no
    // lists are placed, and the substep searches the grid.
    fits_ = total <= std::numeric_limits<std::uint32_t>::max();
    if (fits_) list_.resize(std::size_t(total));
}

void NeighbourLists::place(std::size_t c) {
    if (!fits_) return;
    const std::vector<std::uint32_t>& mine = chunkLists_[c];
    std::copy(mine.begin(), mine.end(), list_.begin() + std::ptrdiff_t(starts_[c * chunk_]));
    if (c + 1 == chunkLists_.size()) built_ = true;
}

}  // namespace carom
