// Initial conditions: the disks of a SceneDef on a jittered hexagonal
// lattice, and a scene file's groups (one lattice per region, groups sharing
// a region shuffled over it) and [[disk]]s.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

#include <carom/random.h>

#include "engine/scene.h"
#include "engine/constants.h"
#include "engine/error_message.h"
#include "engine/grid.h"
#include "engine/scene_region.h"

namespace carom {
namespace {

// A hexagonal lattice of cols x rows sites spread over the part of the box
// where a disk of the largest radius fits; odd rows are shifted by half a
// spacing.
struct Lattice {
    int cols = 1;
    int rows = 1;
    double spacingX = 0.0;  // 0 when there is a single column
    double spacingY = 0.0;  // 0 when there is a single row
    double minDistance = 0.0;

    static Lattice make(int cols, int rows, double innerWidth, double innerHeight) {
        constexpr double inf = std::numeric_limits<double>::infinity();
        Lattice l;
        l.cols = cols;
        l.rows = rows;
        const bool shifted = cols > 1 && rows > 1;
        if (cols > 1) l.spacingX = innerWidth / (shifted ? cols - 0.5 : cols - 1);
        if (rows > 1) l.spacingY = innerHeight / (rows - 1);
        const double dx = cols > 1 ? l.spacingX : inf;
        const double dy = rows > 1 ? l.spacingY : inf;
        // Shifted rows: the nearest sites are in the same row, the next row
        // (half a spacing across) or two rows away (straight above).
        l.minDistance = shifted ? std::min({dx, std::hypot(dx / 2, dy), 2 * dy}) : std::min(dx, dy);
        return l;
    }

    // The densest lattice for n sites: the one whose closest sites are farthest apart.
    static Lattice best(std::uint32_t n, double innerWidth, double innerHeight) {
        const double ideal = std::sqrt(n * (innerWidth + 1e-12) / ((innerHeight + 1e-12) * 0.866));
        const int lastCols = static_cast<int>(std::min<double>(n, 2 * ideal + 2));
        Lattice best = make(1, static_cast<int>(n), innerWidth, innerHeight);
        for (int cols = 2; cols <= lastCols; ++cols) {
            const int rows = static_cast<int>((n + cols - 1) / cols);
            const Lattice l = make(cols, rows, innerWidth, innerHeight);
            if (l.minDistance > best.minDistance) best = l;
        }
        return best;
    }

    double siteX(int col, int row, double width, double margin) const {
        if (cols == 1) return width / 2;
        return margin + (col + (rows > 1 && row % 2 ? 0.5 : 0.0)) * spacingX;
    }
    double siteY(int row, double height, double margin) const {
        return rows == 1 ? height / 2 : margin + row * spacingY;
    }
};

// Each region gets its own stream of random numbers; the first uses the
// scene's seed itself, so a one-group scene matches makeInitialState(SceneDef).
std::uint64_t regionSeed(std::uint64_t seed, std::size_t region) { return seed + region * 0x9E3779B97F4A7C15ull; }

void setVelocity(Particle& p, const GroupDef& g, Random& random) {
    if (g.temperature > 0.0f) {
        // Maxwell-Boltzmann in 2D: each component normal with variance k_B T / m.
        const double sigma = std::sqrt(double(g.temperature) / p.mass);
        const auto [a, b] = random.normalPair();
        p.velocity = float2{static_cast<float>(sigma * a), static_cast<float>(sigma * b)};
    } else {
        const double angle = 2 * kPi * random.unit();
        p.velocity =
            float2{static_cast<float>(g.speed * std::cos(angle)), static_cast<float>(g.speed * std::sin(angle))};
    }
}

struct Placed {
    float width = 0.0f;  // the region's size: the box's when sized by packing
    float height = 0.0f;
    std::vector<Particle> particles;  // in group order, positions relative to the region
};

// Rethrows a placement error with the file and the group it concerns.
template <class Place>
Placed placing(const SceneFileDef& scene, const GroupDef& g, Place&& place) {
    try {
        return place();
    } catch (const Error& e) {
        fail(scene.path, ':', g.line, ": ", g.name, ": ", e.what());
    }
}

SceneDef latticeDef(std::uint32_t count, float radiusMin, float radiusMax, float width, float height, float packing,
                    std::uint64_t seed) {
    SceneDef def;
    def.particles = count;
    def.radiusMin = radiusMin;
    def.radiusMax = radiusMax;
    def.width = width;
    def.height = height;
    if (packing > 0) def.packing = packing;
    def.seed = seed;
    return def;
}

// One group alone in its region: makeInitialState(SceneDef) places it.
Placed placeAlone(const GroupDef& g, float width, float height, float packing, std::uint64_t seed) {
    SceneDef def = latticeDef(g.count, g.radiusMin, g.radiusMax, width, height, packing, seed);
    def.massMin = g.massMin;
    def.massMax = g.massMax;
    def.speed = g.speed;
    InitialState s = makeInitialState(def);
    if (g.temperature > 0.0f) {
        Random random(seed ^ 0x5DEECE66Dull);  // the lattice's stream is used up
        for (Particle& p : s.particles) setVelocity(p, g, random);
    }
    return Placed{s.width, s.height, std::move(s.particles)};
}

// Several groups sharing a region: draw every disk's radius and mass, lay one
// lattice spaced for the largest radius, and shuffle the disks over its
// sites so the species start mixed.
Placed placeMixed(const std::vector<const GroupDef*>& groups, float width, float height, float packing,
                  std::uint64_t seed) {
    Random random(seed);
    Placed placed;
    float maxRadius = 0.0f;
    double diskArea = 0.0;
    for (const GroupDef* g : groups) {
        for (std::uint32_t k = 0; k < g->count; ++k) {
            Particle p{};
            p.radius = random.uniformFloat(g->radiusMin, g->radiusMax);
            p.mass = random.uniformFloat(g->massMin, g->massMax);
            setVelocity(p, *g, random);
            maxRadius = std::max(maxRadius, p.radius);
            diskArea += kPi * double(p.radius) * p.radius;
            placed.particles.push_back(p);
        }
    }
    if (packing > 0) width = height = static_cast<float>(std::sqrt(diskArea / packing));
    const auto count = static_cast<std::uint32_t>(placed.particles.size());
    const InitialState sites = makeInitialState(latticeDef(count, maxRadius, maxRadius, width, height, 0, seed));
    std::vector<std::size_t> site(count);
    for (std::size_t i = 0; i < count; ++i) site[i] = i;
    for (std::size_t i = count - 1; i > 0; --i) std::swap(site[i], site[random.below(i + 1)]);  // Fisher-Yates
    for (std::size_t i = 0; i < count; ++i) placed.particles[i].position = sites.particles[site[i]].position;
    placed.width = sites.width;
    placed.height = sites.height;
    return placed;
}

// Throws if a [[disk]] overlaps any other disk. The groups' disks lie in
// their regions, which are the same or apart: two groups' disks may touch
// across their regions' common edge, which rounding can make a hair of
// overlap, and are not checked.
void requireNoOverlap(const SceneFileDef& scene, const std::vector<Particle>& particles, std::size_t firstDisk,
                      float width, float height) {
    auto name = [&](std::uint32_t id) {
        std::ostringstream text;
        if (id >= firstDisk) {
            text << "disk[" << id - firstDisk + 1 << "] (line " << scene.disks[id - firstDisk].line << ")";
        } else {
            text << "particle " << id << " of the groups";
        }
        return text.str();
    };
    // Disks are placed inside the box, so an overlap across a periodic edge is
    // not possible: the walled search finds every one.
    const DiskCells cells = sortIntoCells(particles.data(), particles.size(), carom_box(width, height, 0));
    forEachOverlappingPair(cells, [&](std::uint32_t i, std::uint32_t j) -> bool {
        if (j < firstDisk) return true;  // i < j: two groups' disks
        const DiskDef& d = scene.disks[j - firstDisk];
        fail(scene.path, ':', d.line, ": ", name(j), " at (", d.position.x, ", ", d.position.y, ") overlaps ", name(i),
             " at (", particles[i].position.x, ", ", particles[i].position.y, "); disks may touch but not overlap");
    });
}

}  // namespace

namespace {

// Calls place(k, u) for every disk k < count, where u holds the disk's
// `perDisk` numbers from `random` (Random::unit), drawn in the order a loop
// over the disks draws them: block by block, the draws in stream order on
// one thread, the disks (their trigonometry) in parallel. The same numbers,
// so the same placement, as one loop; many times faster at 10^8 disks.
template <class Place>
void inBlocks(Random& random, std::uint32_t count, std::uint32_t perDisk, Place&& place) {
    constexpr std::uint32_t kBlock = 1 << 16;
    std::vector<double> draws(std::size_t(kBlock) * perDisk);
    for (std::uint32_t first = 0; first < count; first += kBlock) {
        const std::uint32_t disks = std::min(kBlock, count - first);
        for (std::size_t d = 0; d < std::size_t(disks) * perDisk; ++d) draws[d] = random.unit();
        const auto n = static_cast<std::int64_t>(disks);
#pragma omp parallel for schedule(static) if (n >= 4096)
        for (std::int64_t j = 0; j < n; ++j) place(first + std::uint32_t(j), draws.data() + j * perDisk);
    }
}

}  // namespace

InitialState makeInitialState(const SceneDef& scene) {
    validate(scene);
    Random random(scene.seed);
    InitialState state;
    state.particles.resize(scene.particles);

    // Each disk's radius, then its mass, as Random::uniformFloat draws them
    // (a fixed one takes no number from the stream).
    const bool radiusDrawn = scene.radiusMin != scene.radiusMax, massDrawn = scene.massMin != scene.massMax;
    const auto uniformFloat = [](float lo, float hi, double u) {
        return static_cast<float>(double(lo) + (double(hi) - double(lo)) * u);
    };
    inBlocks(random, scene.particles, radiusDrawn + massDrawn, [&](std::uint32_t k, const double* u) {
        Particle& p = state.particles[k];
        p.radius = radiusDrawn ? uniformFloat(scene.radiusMin, scene.radiusMax, u[0]) : scene.radiusMin;
        p.mass = massDrawn ? uniformFloat(scene.massMin, scene.massMax, u[radiusDrawn]) : scene.massMin;
    });
    double diskArea = 0.0;
    for (const Particle& p : state.particles) diskArea += kPi * double(p.radius) * p.radius;
    const bool boxGiven = scene.width > 0.0f;
    state.width = boxGiven ? scene.width : static_cast<float>(std::sqrt(diskArea / scene.packing));
    state.height = boxGiven ? scene.height : state.width;
    if (!boxGiven && !(state.width <= kMaxLength))
        fail("packing ", scene.packing, " makes a ", state.width, " x ", state.height, " box; boxes up to ", kMaxLength,
             " are valid (README, Limits): raise the packing");
    const double packing = diskArea / (double(state.width) * state.height);

    const double rmax = scene.radiusMax;
    const double innerWidth = state.width - 2 * rmax;
    const double innerHeight = state.height - 2 * rmax;
    if (innerWidth < 0 || innerHeight < 0)
        fail("a disk of radius ", scene.radiusMax, " does not fit in the ", state.width, " x ", state.height, " box");

    // Keep a gap of a few float ulps between neighbours so that rounding the
    // positions to float cannot create an overlap.
    const double gap = 1e-6 * std::max(state.width, state.height);
    const Lattice lattice = Lattice::best(scene.particles, innerWidth, innerHeight);
    const double freeSpace = lattice.minDistance - 2 * rmax - gap;
    if (freeSpace < 0) {
        const double reachable = packing * std::pow(std::min(1.0, lattice.minDistance / (2 * rmax + gap)), 2);
        fail("cannot place ", scene.particles, " disks of radius up to ", scene.radiusMax, " without overlap in a ",
             state.width, " x ", state.height, " box (packing ", packing,
             "); with these radii the lattice placement reaches packing ", reachable,
             " at most: lower the packing or the number of disks, or enlarge the box");
    }

    // Spread the N disks evenly over the lattice sites and jitter each inside
    // the free space around its site (a lone site has infinite free space).
    const double jitter = std::min(freeSpace, std::min(innerWidth, innerHeight)) / 2;
    const std::uint64_t sites = std::uint64_t(lattice.cols) * lattice.rows;
    inBlocks(random, scene.particles, 2, [&](std::uint32_t k, const double* u) {
        Particle& p = state.particles[k];
        const std::uint64_t site = std::uint64_t(k) * sites / scene.particles;
        const int col = static_cast<int>(site % lattice.cols);
        const int row = static_cast<int>(site / lattice.cols);
        const double angle = 2 * kPi * u[0];
        const double distance = jitter * std::sqrt(u[1]);
        const double x = lattice.siteX(col, row, state.width, rmax) + distance * std::cos(angle);
        const double y = lattice.siteY(row, state.height, rmax) + distance * std::sin(angle);
        p.position.x = static_cast<float>(std::clamp(x, double(p.radius), state.width - double(p.radius)));
        p.position.y = static_cast<float>(std::clamp(y, double(p.radius), state.height - double(p.radius)));
    });
    inBlocks(random, scene.particles, 1, [&](std::uint32_t k, const double* u) {
        Particle& p = state.particles[k];
        const double angle = 2 * kPi * u[0];
        p.velocity.x = static_cast<float>(scene.speed * std::cos(angle));
        p.velocity.y = static_cast<float>(scene.speed * std::sin(angle));
    });
    return state;
}

InitialState makeInitialState(const SceneFileDef& scene) {
    validate(scene);
    InitialState state;
    state.width = scene.world.width;
    state.height = scene.world.height;

    // Group the groups by region, in the order regions first appear.
    std::vector<Region> regions;
    std::vector<std::vector<std::size_t>> members;
    for (std::size_t g = 0; g < scene.groups.size(); ++g) {
        const Region r = scene.groups[g].region.value_or(wholeBox(scene));
        auto found = std::find_if(regions.begin(), regions.end(), [&](const Region& x) { return sameRegion(x, r); });
        if (found == regions.end()) {
            regions.push_back(r);
            members.emplace_back();
            found = regions.end() - 1;
        }
        members[std::size_t(found - regions.begin())].push_back(g);
    }

    std::vector<std::size_t> firstId(scene.groups.size() + 1, 0);
    for (std::size_t g = 0; g < scene.groups.size(); ++g) firstId[g + 1] = firstId[g] + scene.groups[g].count;
    state.particles.resize(firstId.back() + scene.disks.size());

    for (std::size_t r = 0; r < regions.size(); ++r) {
        const Region& region = regions[r];
        const std::vector<std::size_t>& in = members[r];
        const float width = region.xMax - region.xMin, height = region.yMax - region.yMin;
        const std::uint64_t seed = regionSeed(scene.seed, r);
        const GroupDef& first = scene.groups[in.front()];
        const Placed placed = placing(scene, first, [&] {
            if (in.size() == 1) return placeAlone(first, width, height, scene.packing, seed);
            std::vector<const GroupDef*> groups;
            for (std::size_t g : in) groups.push_back(&scene.groups[g]);
            return placeMixed(groups, width, height, scene.packing, seed);
        });
        if (scene.packing > 0) {  // a single region: the whole box, sized now
            state.width = placed.width;
            state.height = placed.height;
        }
        std::size_t next = 0;
        for (std::size_t g : in) {
            for (std::size_t id = firstId[g]; id < firstId[g + 1]; ++id) {
                Particle p = placed.particles[next++];
                // Clamped as validateParticles checks, in case the shift rounds up.
                p.position.x = std::min(p.position.x + region.xMin, state.width - p.radius);
                p.position.y = std::min(p.position.y + region.yMin, state.height - p.radius);
                state.particles[id] = p;
            }
        }
    }

    const std::size_t firstDisk = firstId.back();
    for (std::size_t i = 0; i < scene.disks.size(); ++i) {
        const DiskDef& d = scene.disks[i];
        Particle& p = state.particles[firstDisk + i];
        p = Particle{};
        p.position = d.position;
        p.velocity = d.velocity;
        p.mass = d.mass;
        p.radius = d.radius;
    }
    if (!scene.disks.empty()) requireNoOverlap(scene, state.particles, firstDisk, state.width, state.height);
    // A box sized by packing can overflow a float for absurd radii: never hand out such a state.
    WorldDef world = scene.world;
    world.width = state.width;
    world.height = state.height;
    try {
        validateParticles(state.particles, world, "particles");
    } catch (const Error& e) {
        fail(scene.path, ": ", e.what());
    }
    return state;
}

}  // namespace carom
