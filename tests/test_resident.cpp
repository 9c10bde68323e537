// The resident pipeline's grid, built on the OpenCL device, against the
// shared host builder; the resident state across calls; and the all-pairs
// baselines of `carom bench` against the grid search.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <set>
#include <random>

#include "app/bench/all_pairs_cpu.h"
#include "engine/grid.h"
#include "support.h"
#ifdef CAROM_HAVE_OPENCL
#include "backends/opencl/program.h"
#include "backends/opencl/resident.h"
#include "app/bench/all_pairs_opencl.h"
#endif

using namespace carom;
using carom::test::box;
using carom::test::disk;

namespace {

// Random disks in the box: a crowded patch where cells hold many disks
// (overlapping), the rest uniform, and disks touching the walls and lying on
// cell boundaries.
std::vector<Particle> randomDisks(unsigned seed, std::size_t count, const WorldDef& world, float radius) {
    std::mt19937 rng(seed);
    const float w = world.width, h = world.height;
    std::uniform_real_distribution<float> x(radius, w - radius), y(radius, h - radius), v(-1, 1);
    std::uniform_real_distribution<float> patchX(radius, radius + 0.1f * (w - 2 * radius));
    std::vector<Particle> ps;
    for (std::size_t i = 0; i < count; ++i)
        ps.push_back(disk(i % 4 == 0 ? patchX(rng) : x(rng), y(rng), v(rng), v(rng), 1, radius));
    const GridGeometry g = gridGeometryFor(w, h, radius, count + 6);
    const float cellWidth = w / g.cols;
    for (float edgeX : {radius, w - radius, cellWidth, 2 * cellWidth, 3 * cellWidth})
        ps.push_back(disk(edgeX, y(rng), 0, 0, 1, radius));
    ps.push_back(disk(w - radius, h - radius, 0, 0, 1, radius));
    return ps;
}

std::vector<Particle> read(Backend& backend) {
    std::vector<Particle> ps;
    backend.readParticles(ps);
    return ps;
}

}  // namespace

#ifdef CAROM_HAVE_OPENCL

namespace {

// The shared builder's grid of the particles, in the backend's geometry.
Grid hostGrid(const std::vector<Particle>& ps, const GridGeometry& geometry) {
    Grid grid;
    grid.geometry = geometry;
    buildGrid(ps.data(), ps.size(), grid);
    return grid;
}

void checkSameGrid(const Grid& device, const Grid& host) {
    REQUIRE(device.cells.size() == host.cells.size());
    std::size_t differingCells = 0;
    for (std::size_t c = 0; c < host.cells.size(); ++c)
        if (device.cells[c].start != host.cells[c].start || device.cells[c].count != host.cells[c].count)
            ++differingCells;
    CHECK_MESSAGE(differingCells == 0, differingCells << " of " << host.cells.size() << " cells differ");
    CHECK(device.sortedIndices == host.sortedIndices);
}

bool bitwiseEqual(const std::vector<Particle>& a, const std::vector<Particle>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Particle)) == 0;
}

template <class OpenClPipeline>
std::unique_ptr<OpenClPipeline> makeOpenCl(const WorldDef& world) {
    const char* device = std::getenv("CAROM_TEST_DEVICE");
    return std::make_unique<OpenClPipeline>(world, device ? device : "");
}

}  // namespace

TEST_CASE("resident grid: the device builds the shared builder's cells and sortedIndices") {
    struct Case {
        unsigned seed;
        std::size_t count;
        float width, height, radius;
    };
    // From one disk (a single scan tile) to grids whose scan needs two levels;
    // crowded, dilute, and a narrow box.
    for (const Case c : {Case{1, 1, 10, 10, 1.0f}, Case{2, 3000, 80, 60, 0.7f}, Case{3, 20000, 300, 250, 1.0f},
                         Case{4, 50000, 5000, 5000, 0.5f}, Case{5, 2000, 400, 4, 1.0f}}) {
        CAPTURE(c.seed);
        const WorldDef world = box(c.width, c.height);
        const std::vector<Particle> ps = randomDisks(c.seed, c.count, world, c.radius);
        auto backend = makeOpenCl<OpenClResidentBackend>(world);
        backend->setParticles(ps);
        checkSameGrid(backend->readDeviceGrid(), hostGrid(ps, backend->gridGeometry()));
    }
}

// Both scans (keepsWorkGroupsRunning, backends/opencl/grid.h): the one pass
// on this device, and the launches that devices not known to keep a started
// work-group running use instead.
TEST_CASE("resident grid: both scans give the same grid from one tile to thousands") {
    using namespace opencl;
    bool onePass = true;
    SUBCASE("in one pass") { onePass = true; }
    SUBCASE("in launches") { onePass = false; }
    const test::ScopedEnvironment scan("CAROM_GRID_SCAN", onePass ? "one-pass" : "launches");
    const char* selector = std::getenv("CAROM_TEST_DEVICE");
    const DeviceInfo device = selectDevice(selector ? selector : "");
    cl_int status = CL_SUCCESS;
    const Context context(clCreateContext(nullptr, 1, &device.id, nullptr, nullptr, &status));
    check(status, "clCreateContext");
    const Queue queue(clCreateCommandQueue(context.get(), device.id, 0, &status));
    check(status, "clCreateCommandQueue");
    const Program program = buildProgram(context.get(), device, kernelSource(), false);

    const WorldDef world = box(400, 300);
    // Two states of as many disks in the same grid: builds take their counts
    // in turn, so that a scan runs on status words the build before zeroed
    // after a build of other counts used them (a word left over would give a
    // tile a wrong start, where a tile looks back before the one before it
    // publishes: a matter of timing, so each build's zeroing is checked too).
    const std::vector<Particle> states[2] = {randomDisks(11, 20000, world, 1.0f), randomDisks(12, 20000, world, 1.0f)};
    const GridGeometry geometry = gridGeometryFor(world.width, world.height, 1.0f, states[0].size());
    const Grid hosts[2] = {hostGrid(states[0], geometry), hostGrid(states[1], geometry)};
    const auto upload = [&](const void* data, std::size_t bytes) {
        Buffer buffer = createBuffer(context.get(), bytes, "test data");
        check(clEnqueueWriteBuffer(queue.get(), buffer.get(), CL_TRUE, 0, bytes, data, 0, nullptr, nullptr),
              "clEnqueueWriteBuffer");
        return buffer;
    };
    const std::size_t n = states[0].size();
    std::vector<cl_uint> ids(n);
    std::iota(ids.begin(), ids.end(), cl_uint{0});
    const Buffer stateBuffers[2] = {upload(states[0].data(), n * sizeof(Particle)),
                                    upload(states[1].data(), n * sizeof(Particle))};
    const Buffer idBuffer = upload(ids.data(), n * sizeof(cl_uint));
    const Buffer sortedIds = createBuffer(context.get(), n * sizeof(cl_uint), "sorted ids");
    const cl_uint running[2] = {CAROM_RUNNING, 0};  // running, the grid built (kernels/params.h)
    const Buffer halt = upload(running, sizeof running);
    const auto poison = [&](cl_mem buffer, std::size_t bytes) {
        const cl_uint junk = 0xFFFFFFFFu;
        check(clEnqueueFillBuffer(queue.get(), buffer, &junk, sizeof junk, 0, bytes, 0, nullptr, nullptr),
              "clEnqueueFillBuffer");
    };
    const auto copy = [&](cl_mem from, cl_mem to, std::size_t bytes) {
        check(clEnqueueCopyBuffer(queue.get(), from, to, 0, 0, bytes, 0, nullptr, nullptr), "clEnqueueCopyBuffer");
    };
    // Small scan groups make small tiles: ~30 000 cells take up to ~1 900
    // tiles, each adding up the totals of the tiles before it that have not
    // published their prefix yet (how far back depends on how many run at once).
    std::size_t mostTiles = 0;
    for (std::size_t group : {1, 2, 8, 512}) {
        DeviceGrid grid(context.get(), device, program.get(), geometry, n, nullptr, group);
        DeviceGrid counted[2] = {DeviceGrid(context.get(), device, program.get(), geometry, n, nullptr, group),
                                 DeviceGrid(context.get(), device, program.get(), geometry, n, nullptr, group)};
        for (int k = 0; k < 2; ++k) counted[k].count(queue.get(), stateBuffers[k].get());
        grid.count(queue.get(), stateBuffers[0].get());  // zeroes the first status buffer
        CAPTURE(grid.scanTiles());
        for (int build = 0; build < 5; ++build) {
            CAPTURE(build);
            const int k = build / 2 % 2;  // 0 0 1 1 0: each status buffer sees other counts each time
            copy(counted[k].counts(), grid.counts(), grid.cellCount() * sizeof(cl_uint));
            copy(counted[k].cellOf(), grid.cellOf(), n * sizeof(cl_uint));
            copy(counted[k].rankInCell(), grid.rankInCell(), n * sizeof(cl_uint));
            poison(grid.cells(), grid.cellCount() * sizeof(GridCell));
            poison(sortedIds.get(), n * sizeof(cl_uint));
            grid.build(queue.get(), idBuffer.get(), sortedIds.get(), halt.get());
            checkSameGrid(grid.read(queue.get(), sortedIds.get()), hosts[k]);
            std::vector<cl_uint> next(1 + grid.scanTiles());
            check(clEnqueueReadBuffer(queue.get(), grid.scanStatus(), CL_TRUE, 0, next.size() * sizeof(cl_uint),
                                      next.data(), 0, nullptr, nullptr),
                  "clEnqueueReadBuffer(scan status)");
            if (onePass) CHECK(std::count(next.begin(), next.end(), 0u) == std::ptrdiff_t(next.size()));
        }
        mostTiles = std::max(mostTiles, grid.scanTiles());
    }
    CHECK(mostTiles >= 1000);
}

namespace {

// The box of a scene's start, under `scheme`.
WorldDef boxUnder(CollisionScheme scheme, const InitialState& s) {
    WorldDef world = box(s.width, s.height);
    world.collisions = scheme;
    return world;
}

}  // namespace

// Both schemes, below and above the size whose steps run in one work-group
// (kSmallSystemParticles = 2048, backends/opencl/small_system.h).
TEST_CASE("resident grid: stays the shared builder's as the state evolves") {
    for (const CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Pairwise})
        for (const std::uint32_t particles : {2000u, 5000u}) {
            CAPTURE(scheme);
            CAPTURE(particles);
            SceneDef scene;
            scene.particles = particles;
            scene.packing = 0.45f;
            scene.radiusMin = 0.4f;
            scene.radiusMax = 1.0f;
            scene.speed = 3.0f;
            const InitialState s = makeInitialState(scene);
            const WorldDef world = boxUnder(scheme, s);
            auto backend = makeOpenCl<OpenClResidentBackend>(world);
            backend->setParticles(s.particles);
            for (int round = 0; round < 4; ++round) {
                CAPTURE(round);
                backend->step(37);
                checkSameGrid(backend->readDeviceGrid(), hostGrid(read(*backend), backend->gridGeometry()));
            }
        }
}

TEST_CASE("resident pipeline: steps in several calls, with reads between, equal the CPU bitwise") {
    for (const CollisionScheme scheme : {CollisionScheme::Simultaneous, CollisionScheme::Pairwise})
        for (const std::uint32_t particles : {2000u, 4000u}) {
            CAPTURE(scheme);
            CAPTURE(particles);
            SceneDef scene;
            scene.particles = particles;
            scene.packing = 0.5f;
            const InitialState s = makeInitialState(scene);
            const WorldDef world = boxUnder(scheme, s);
            auto resident = makeOpenCl<OpenClResidentBackend>(world);
            if (!resident->exactArithmetic()) {
                MESSAGE("the device lacks correctly rounded divide/sqrt: no bitwise comparison");
                return;
            }
            auto cpu = makeBackend(EngineDef{}, world);
            resident->setParticles(s.particles);
            cpu->setParticles(s.particles);
            // Around the backend's sync interval (64) and the small system's steps per launch (16).
            for (std::uint64_t steps : {1, 63, 64, 65, 7, 16, 17, 15}) {
                CAPTURE(steps);
                resident->step(steps);
                cpu->step(steps);
                CHECK(bitwiseEqual(read(*resident), read(*cpu)));
                CHECK(resident->collisions() == cpu->collisions());
            }
            // A new state replaces the old one entirely.
            resident->setParticles(s.particles);
            cpu->setParticles(s.particles);
            resident->step(10);
            cpu->step(10);
            CHECK(bitwiseEqual(read(*resident), read(*cpu)));
            CHECK(resident->collisions() == cpu->collisions());
        }
}

// The pairwise steps of one call run in chunks without a wait, and the
// device stops a chunk where a step needs another substep count
// (startPairwiseStep, or within stepSmallPairwise). Falling disks speed up,
// so the count changes: one call equals a call per step, and the CPU
// backend, bit for bit, below and above the small-system size.
TEST_CASE("resident pipeline: pairwise chunks stop where the substep count changes, as single steps do") {
    for (const std::uint32_t particles : {1000u, 4000u}) {
        CAPTURE(particles);
        SceneDef scene;
        scene.particles = particles;
        const InitialState s = makeInitialState(scene);
        WorldDef world = boxUnder(CollisionScheme::Pairwise, s);
        world.dt = 0.05f;
        world.gravity = float2{0.0f, -10.0f};
        auto chunked = makeOpenCl<OpenClResidentBackend>(world);
        if (!chunked->exactArithmetic()) {
            MESSAGE("the device lacks correctly rounded divide/sqrt: no bitwise comparison");
            return;
        }
        auto single = makeOpenCl<OpenClResidentBackend>(world);
        auto cpu = makeBackend(EngineDef{}, world);
        for (Backend* b : {static_cast<Backend*>(chunked.get()), static_cast<Backend*>(single.get()), cpu.get()})
            b->setParticles(s.particles);
        const std::uint64_t steps = 200;
        chunked->step(steps);
        std::set<std::uint64_t> counts;  // the substeps each step took
        for (std::uint64_t k = 0, before = 0; k < steps; ++k) {
            single->step(1);
            counts.insert(single->contacts().substeps - before);
            before = single->contacts().substeps;
        }
        CHECK(counts.size() >= 3);
        cpu->step(steps);
        const std::uint64_t substeps = cpu->contacts().substeps;
        CHECK(chunked->contacts().substeps == substeps);
        CHECK(single->contacts().substeps == substeps);
        CHECK(bitwiseEqual(read(*chunked), read(*cpu)));
        CHECK(bitwiseEqual(read(*single), read(*cpu)));
        CHECK(chunked->collisions() == cpu->collisions());
        CHECK(chunked->contacts().maxRounds == cpu->contacts().maxRounds);
    }
}

// Pairwise steps that search neighbour lists (forced on, as for large
// systems) skip the grid's build while the lists hold, and rebuild them as
// the disks move: the grid's bits, and the CPU's, in walled and periodic
// boxes, with gravity and mixed radii. One large disk among small ones
// widens the grid's cells, and so the lists' skin: the small disks' lists
// then outgrow their first room.
TEST_CASE("resident pipeline: pairwise neighbour lists reuse their build with the grid's bits") {
    for (const Boundary boundary : {Boundary::Walls, Boundary::Periodic})
        for (const float radiusMax : {0.5f, 2.5f, 5.0f}) {
            CAPTURE(boundary);
            CAPTURE(radiusMax);
            SceneDef scene;
            scene.particles = 4000;
            scene.packing = radiusMax == 5.0f ? 0.5f : 0.35f;
            scene.radiusMin = 0.5f;
            scene.radiusMax = radiusMax == 5.0f ? 0.5f : radiusMax;
            InitialState s = makeInitialState(scene);
            if (radiusMax == 5.0f) {  // the large disk in the middle, without the disks it would overlap
                const float x = s.width / 2, y = s.height / 2;
                s.particles.erase(std::remove_if(s.particles.begin(), s.particles.end(),
                                                 [&](const Particle& p) {
                                                     return std::hypot(p.position.x - x, p.position.y - y) <
                                                            radiusMax + 0.6f;
                                                 }),
                                  s.particles.end());
                s.particles.push_back(disk(x, y, 0, 0, 1, radiusMax));
            }
            WorldDef world = boxUnder(CollisionScheme::Pairwise, s);
            world.boundary = boundary;
            world.gravity = float2{0.0f, -1.0f};
            std::unique_ptr<OpenClResidentBackend> listed, grid;
            {
                const test::ScopedEnvironment on("CAROM_PAIRWISE_LISTS", "on");
                listed = makeOpenCl<OpenClResidentBackend>(world);
                listed->setParticles(s.particles);
            }
            {
                const test::ScopedEnvironment off("CAROM_PAIRWISE_LISTS", "off");
                grid = makeOpenCl<OpenClResidentBackend>(world);
                grid->setParticles(s.particles);
            }
            REQUIRE(listed->searchesNeighbourLists());
            CHECK_FALSE(grid->searchesNeighbourLists());
            auto cpu = makeBackend(EngineDef{}, world);
            cpu->setParticles(s.particles);
            for (std::uint64_t steps : {1, 40, 100, 60}) {
                CAPTURE(steps);
                listed->step(steps);
                grid->step(steps);
                cpu->step(steps);
                CHECK(bitwiseEqual(read(*listed), read(*grid)));
                if (listed->exactArithmetic()) CHECK(bitwiseEqual(read(*listed), read(*cpu)));
                CHECK(listed->collisions() == grid->collisions());
            }
            CHECK(listed->collisions() > 0);
            // Built, rebuilt as the disks moved (within the skin of small cells), and reused between builds.
            CHECK(listed->neighbourListBuilds() >= 1);
            if (radiusMax == 0.5f) CHECK(listed->neighbourListBuilds() > 1);
            CHECK(listed->neighbourListUses() > 2 * listed->neighbourListBuilds());
            if (radiusMax == 5.0f) CHECK(listed->neighbourListRoom() > 6 * s.particles.size());
            MESSAGE("builds " << listed->neighbourListBuilds() << ", substeps searching them "
                              << listed->neighbourListUses() << " of " << listed->contacts().substeps << ", room "
                              << listed->neighbourListRoom());
            // A state loaded without the lists builds its grid each step again.
            const test::ScopedEnvironment off("CAROM_PAIRWISE_LISTS", "off");
            listed->setParticles(s.particles);
            cpu->setParticles(s.particles);
            CHECK_FALSE(listed->searchesNeighbourLists());
            listed->step(20);
            cpu->step(20);
            if (listed->exactArithmetic()) CHECK(bitwiseEqual(read(*listed), read(*cpu)));
        }
}

TEST_CASE("pipelines: a value that is not a ComputeEngine is refused") {
    const WorldDef world = box(10, 10);
    CHECK_THROWS_WITH_AS(makeBackend(EngineDef{static_cast<ComputeEngine>(7), ""}, world),
                         "WorldDef::engine 7 is not a ComputeEngine; allowed: Cpu, OpenClHostGrid, OpenClResident",
                         Error);
}

#endif  // CAROM_HAVE_OPENCL

// One step from overlapping disks: every method must find the same pairs
// (equal collision counts); all pairs sums them in another order, so the
// positions agree to rounding only.
TEST_CASE("all pairs: the naive baselines find the grid search's collisions") {
    WorldDef world = box(60, 50);
    world.collisions = CollisionScheme::Simultaneous;  // the baselines' scheme
    const std::vector<Particle> ps = randomDisks(9, 2500, world, 0.8f);
    std::vector<std::unique_ptr<Backend>> naive;
    naive.push_back(std::make_unique<bench::AllPairsCpuBackend>(world));
#ifdef CAROM_HAVE_OPENCL
    naive.push_back(makeOpenCl<bench::AllPairsOpenClBackend>(world));
#endif
    auto grid = makeBackend(EngineDef{}, world);
    grid->setParticles(ps);
    grid->step(1);
    const std::vector<Particle> expected = read(*grid);
    REQUIRE(grid->collisions() > 500);
    for (auto& backend : naive) {
        CAPTURE(backend->device());
        backend->setParticles(ps);
        backend->step(1);
        CHECK(backend->collisions() == grid->collisions());
        const std::vector<Particle> got = read(*backend);
        REQUIRE(got.size() == expected.size());
        for (std::size_t i = 0; i < got.size(); ++i) {
            CHECK(std::abs(got[i].position.x - expected[i].position.x) < 1e-4f);
            CHECK(std::abs(got[i].velocity.y - expected[i].velocity.y) < 1e-4f);
        }
    }
}
