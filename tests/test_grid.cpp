// The shared grid builder and the 3x3 neighbour search, against brute force.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "engine/diagnostics.h"
#include "engine/grid.h"
#include "support.h"

using namespace carom;
using carom::test::disk;

namespace {

using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

// With a periodic `box`, the separation is to the nearest image.
PairSet bruteForcePairs(const std::vector<Particle>& ps, CaromBox box) {
    PairSet pairs;
    for (std::uint32_t i = 0; i < ps.size(); ++i)
        for (std::uint32_t j = i + 1; j < ps.size(); ++j) {
            const float2 d = carom_offset(ps[i].position, ps[j].position, box);
            const float contact = ps[i].radius + ps[j].radius;
            if (d.x * d.x + d.y * d.y < contact * contact) pairs.insert({i, j});
        }
    return pairs;
}

Grid gridFor(const std::vector<Particle>& ps, float width, float height, Boundary boundary = Boundary::Walls) {
    float maxRadius = 0;
    for (const Particle& p : ps) maxRadius = std::max(maxRadius, p.radius);
    Grid grid;
    grid.geometry = gridGeometryFor(width, height, maxRadius, ps.size(), boundary);
    buildGrid(ps.data(), ps.size(), grid);
    return grid;
}

// Random polydisperse disks, overlaps allowed, plus disks exactly on the box
// edges, on cell boundaries and slightly outside the box.
std::vector<Particle> randomConfiguration(unsigned seed, float width, float height, float rmin, float rmax) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> x(0, width), y(0, height), r(rmin, rmax);
    std::vector<Particle> ps;
    for (int i = 0; i < 3000; ++i) ps.push_back(disk(x(rng), y(rng), 0, 0, 1, r(rng)));
    const GridGeometry g = gridGeometryFor(width, height, rmax, ps.size() + 8);
    const float cellWidth = width / g.cols;
    for (float edgeX : {0.0f, width, cellWidth, 2 * cellWidth, -0.5f, width + 0.5f})
        ps.push_back(disk(edgeX, y(rng), 0, 0, 1, rmax));
    ps.push_back(disk(width, height, 0, 0, 1, rmax));
    ps.push_back(disk(0, 0, 0, 0, 1, rmax));
    return ps;
}

}  // namespace

TEST_CASE("grid: cells are at least one largest diameter and cover the box") {
    const GridGeometry g = gridGeometryFor(100.0f, 50.0f, 1.5f, 1000);
    CHECK(100.0 / g.cols >= 3.0);
    CHECK(50.0 / g.rows >= 3.0);
    CHECK(g.cols == 33);
    CHECK(g.rows == 16);

    SUBCASE("a dilute system gets at most about 4 cells per particle") {
        const GridGeometry dilute = gridGeometryFor(1e6f, 1e6f, 0.5f, 100);
        CHECK(double(dilute.cols) * dilute.rows <= 4.0 * 100 + 1024);
    }
    SUBCASE("a box narrower than a disk has one cell across") {
        const GridGeometry narrow = gridGeometryFor(1.0f, 10.0f, 1.0f, 10);
        CHECK(narrow.cols == 1);
        CHECK(narrow.rows == 4);
    }
}

TEST_CASE("grid: every particle appears once, in its own cell, ascending by id") {
    const float width = 80.0f, height = 60.0f;
    const std::vector<Particle> ps = randomConfiguration(7, width, height, 0.1f, 1.3f);
    const Grid grid = gridFor(ps, width, height);
    const GridGeometry& g = grid.geometry;

    REQUIRE(grid.sortedIndices.size() == ps.size());
    std::vector<int> seen(ps.size(), 0);
    std::uint32_t expectedStart = 0;
    for (std::size_t c = 0; c < grid.cells.size(); ++c) {
        const GridCell cell = grid.cells[c];
        CHECK(cell.start == expectedStart);
        expectedStart += cell.count;
        for (std::uint32_t k = cell.start; k < cell.start + cell.count; ++k) {
            const std::uint32_t id = grid.sortedIndices[k];
            ++seen[id];
            CHECK(carom_cell_index(ps[id].position, g) == int(c));
            if (k > cell.start) CHECK(grid.sortedIndices[k - 1] < id);
        }
    }
    CHECK(expectedStart == ps.size());
    CHECK(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
}

TEST_CASE("grid: the overlap search finds exactly the overlapping pairs of brute force, with walls and periodic") {
    struct Case {
        unsigned seed;
        float width, height, rmin, rmax;
    };
    for (const Case c : {Case{1, 80, 60, 0.1f, 1.3f}, Case{2, 50, 50, 0.5f, 0.5f}, Case{3, 200, 20, 0.05f, 2.0f},
                         Case{4, 30, 120, 1.0f, 1.0f}, Case{5, 5, 130, 1.0f, 1.0f}}) {
        CAPTURE(c.seed);
        const std::vector<Particle> configuration = randomConfiguration(c.seed, c.width, c.height, c.rmin, c.rmax);
        for (const Boundary boundary : {Boundary::Walls, Boundary::Periodic}) {
            CAPTURE(std::string(boundaryName(boundary)));
            const CaromBox box = carom_box(c.width, c.height, boundary == Boundary::Periodic);
            // A periodic box keeps every centre in [0, W) x [0, H) (integrate wraps them).
            std::vector<Particle> ps = configuration;
            if (box.periodic)
                for (Particle& p : ps) {
                    int image[2] = {0, 0};
                    p = carom_wrap_position(p, box, image);
                }
            PairSet found;
            CHECK(
                forEachOverlappingPair(sortIntoCells(ps.data(), ps.size(), box), [&](std::uint32_t i, std::uint32_t j) {
                    CHECK(found.insert({i, j}).second);  // each pair once
                    return true;
                }));
            const PairSet expected = bruteForcePairs(ps, box);
            CHECK(expected.size() > 100);  // the configurations do overlap
            CHECK(found == expected);
        }
    }
}

TEST_CASE("grid: NaN positions land in a valid cell") {
    std::vector<Particle> ps = {disk(NAN, NAN, 0, 0), disk(5, 5, 0, 0)};
    const Grid grid = gridFor(ps, 10, 10);
    CHECK(carom_cell_index(ps[0].position, grid.geometry) == 0);
}

// NaN and infinite centres among finite ones: left out of the cells (NaN
// centres cannot be ordered, and a sort given them may run past its range).
TEST_CASE("grid: disks whose centre is not finite are left out of the overlap search") {
    const float odd[] = {NAN, INFINITY, -INFINITY};
    std::vector<Particle> ps, finite;
    for (int k = 0; k < 300; ++k) {
        const Particle p = disk(0.5f * float(k % 20), 0.5f * float(k / 20), 0, 0, 1, 0.3f);
        ps.push_back(k % 3 == 0 ? disk(odd[k % 9 / 3], odd[(k / 9) % 3], 0, 0, 1, 0.3f) : p);
        if (k % 3 != 0) finite.push_back(p);
    }
    const CaromBox box = carom_box(10, 10, 0);
    const DiskCells cells = sortIntoCells(ps.data(), ps.size(), box);
    CHECK(cells.sorted.size() == finite.size());
    std::size_t pairs = 0;
    CHECK(forEachOverlappingPair(cells, [&](std::uint32_t i, std::uint32_t j) {
        CHECK((i % 3 != 0 && j % 3 != 0));
        ++pairs;
        return true;
    }));
    CHECK(pairs == bruteForcePairs(finite, box).size());
}

TEST_CASE("grid: the parallel build equals the serial one for any number of threads") {
    struct Case {
        unsigned seed;
        float width, height, rmin, rmax;
        std::size_t copies;  // repeats of the 3 008 disks (more blocks), shifted
    };
    for (const Case c : {Case{1, 80, 60, 0.1f, 1.3f, 1}, Case{2, 50, 50, 0.5f, 0.5f, 4},
                         Case{3, 200, 20, 0.05f, 2.0f, 3}, Case{4, 30, 120, 1.0f, 1.0f, 2}}) {
        CAPTURE(c.seed);
        const std::vector<Particle> one = randomConfiguration(c.seed, c.width, c.height, c.rmin, c.rmax);
        std::vector<Particle> ps;
        for (std::size_t k = 0; k < c.copies; ++k)
            for (Particle p : one) {
                p.position.x = std::fmod(p.position.x + 0.37f * float(k), c.width);
                ps.push_back(p);
            }
        for (const std::size_t n : {std::size_t(1), std::size_t(7), std::size_t(1500), ps.size()}) {
            CAPTURE(n);
            const Grid serial = gridFor(std::vector<Particle>(ps.begin(), ps.begin() + n), c.width, c.height);
            GridBuilder builder;
            Grid parallel;  // reused across thread counts, as a backend reuses its grid
            parallel.geometry = serial.geometry;
            for (const int threads : {1, 2, 3, 4, 5, 8, 16}) {
                CAPTURE(threads);
                buildGridParallel(ps.data(), n, parallel, builder, threads);
                CHECK(parallel.sortedIndices == serial.sortedIndices);
                CHECK(parallel.cellOf == serial.cellOf);
                REQUIRE(parallel.cells.size() == serial.cells.size());
                CHECK(std::equal(parallel.cells.begin(), parallel.cells.end(), serial.cells.begin(),
                                 [](GridCell a, GridCell b) { return a.start == b.start && a.count == b.count; }));
            }
            // The blocks of each phase in any order (as the threads of a team may run them).
            for (const int threads : {2, 3, 6, 8}) {
                CAPTURE(threads);
                Grid split;
                split.geometry = serial.geometry;
                builder.prepare(n, split, threads);
                for (int phase = 0; phase < GridBuilder::kPhases; ++phase)
                    for (int block = builder.blocks() - 1; block >= 0; --block)
                        builder.run(phase, block, ps.data(), n, split);
                CHECK(split.sortedIndices == serial.sortedIndices);
                CHECK(split.cellOf == serial.cellOf);
            }
        }
    }
}

// findOverlaps and sortIntoCells share runs of cells among threads: the
// pairs counted and the deepest pair must be those of one pass in cell
// order, on any number of threads, also where counting stops part-way.
TEST_CASE("grid: the overlap search in parallel finds what one pass finds, for any number of threads") {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float width = 1200, height = 1200;
    std::vector<Particle> ps;
    for (int k = 0; k < 300'000; ++k) ps.push_back(disk(width * unit(random), height * unit(random), 0, 0, 1, 0.5f));
    const WorldDef w = test::box(width, height);
    // What the search finds in one pass over the cells, counting as findOverlaps does.
    const auto onePass = [&](const std::vector<Particle>& disks) {
        Overlaps found;
        const std::size_t counted = kOverlapsCountedPerDisk * disks.size();
        const DiskCells cells = sortIntoCells(disks.data(), disks.size(), caromBoxOf(w));
        REQUIRE(std::is_sorted(cells.sorted.begin(), cells.sorted.end(),
                               [](const DiskCells::Entry& a, const DiskCells::Entry& b) { return a.cell < b.cell; }));
        found.allCounted = forEachOverlappingPair(cells, [&](std::uint32_t i, std::uint32_t j) {
            return countOverlap(found, counted, {i, j}, overlapOf(disks[i], disks[j], w));
        });
        return found;
    };
    std::vector<Particle> heaped = ps;  // a heap of 3 000 disks in the middle: more pairs than are counted
    for (int k = 0; k < 3000; ++k)
        heaped[std::size_t(k) * 97].position = {600.0f + 0.01f * float(k % 40), 600.0f + 0.01f * float(k / 40)};
    for (const std::vector<Particle>* disks : {&ps, &heaped}) {
        const Overlaps expected = onePass(*disks);
        CHECK(expected.pairs > 1000);
        CHECK(expected.allCounted == (disks == &ps));
#ifdef _OPENMP
        const int threads = omp_get_max_threads();
        for (const int t : {1, 2, 3, 8}) {
            CAPTURE(t);
            omp_set_num_threads(t);
#endif
            const Overlaps found = findOverlaps(*disks, w);
            CHECK(found.pairs == expected.pairs);
            CHECK(found.allCounted == expected.allCounted);
            CHECK(found.deepest == expected.deepest);
            CHECK(found.deepestPair == expected.deepestPair);
#ifdef _OPENMP
        }
        omp_set_num_threads(threads);
#endif
    }
}
