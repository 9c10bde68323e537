#include "engine/scene_file.h"

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <toml++/toml.h>

#include "engine/constants.h"
#include "engine/error_message.h"
#include "engine/grid.h"
#include "engine/random.h"
#include "engine/text_format.h"

namespace carom {
namespace {

constexpr std::uintmax_t kMaxSceneFileBytes = 64u << 20;
constexpr std::size_t kMaxGroups = 10000;  // regions are compared pairwise

// ---------------------------------------------------------------------------
// Parsing: every value checked where it is read, with its line.

enum class Bound { Any, NonNegative, Positive };

const char* describe(Bound bound) {
    switch (bound) {
        case Bound::Any: return "a finite number";
        case Bound::NonNegative: return "a finite number >= 0";
        case Bound::Positive: return "a finite number > 0";
    }
    return "";
}

class Parser {
public:
    explicit Parser(std::string path) : path_(std::move(path)) {}

    SceneFile parse(const toml::table& root) const {
        SceneFile scene;
        scene.path = path_;
        requireKnownKeys(root, "", {"boundary", "box", "collisions", "disk", "dt", "gravity", "group", "max_travel",
                                    "output", "packing", "seed", "steps"});
        const toml::node* box = root.get("box");
        const toml::node* packing = root.get("packing");
        if (box && packing) fail(*packing, "packing", "give box or packing, not both");
        if (!box && !packing)
            failAt(line(root), "the scene needs box = [W, H] (the world is [0,W]x[0,H]) or packing = ETA "
                               "(a square box that the disks cover to this area fraction)");
        if (box) {
            const float2 size = pair(*box, "box", Bound::Positive);
            scene.world.width = size.x;
            scene.world.height = size.y;
        } else {
            scene.packing = real(*packing, "packing", Bound::Positive);
            if (scene.packing > kMaxPacking)
                fail(*packing, "packing", "must be in (0, 0.7]: the lattice placement reaches no higher");
        }
        if (const toml::node* boundary = root.get("boundary")) {
            const std::string name = text(*boundary, "boundary");
            if (name == "walls") scene.world.boundary = Boundary::Walls;
            else if (name == "periodic") scene.world.boundary = Boundary::Periodic;
            else fail(*boundary, "boundary", "allowed: \"walls\" (reflective) or \"periodic\"");
        }
        if (const toml::node* collisions = root.get("collisions")) {
            const std::string name = text(*collisions, "collisions");
            try {
                scene.world.collisions = parseCollisionScheme(name);
            } catch (const Error&) {
                // Its message repeats the name in full, where the file's shows it cut short.
                fail(*collisions, "collisions", "allowed: \"pairwise\", \"simultaneous\" or \"events\"");
            }
        }
        if (const toml::node* dt = root.get("dt")) {
            if (dt->is_string()) {
                if (text(*dt, "dt") != "auto") fail(*dt, "dt", "must be a finite number > 0 or \"auto\"");
                if (scene.world.maxTravel == 0.0f) scene.world.maxTravel = kDefaultMaxTravel;
            } else {
                scene.world.dt = real(*dt, "dt", Bound::Positive);
            }
        }
        if (const toml::node* maxTravel = root.get("max_travel"))
            scene.world.maxTravel = real(*maxTravel, "max_travel", Bound::Positive);
        if (const toml::node* gravity = root.get("gravity"))
            scene.world.gravity = pair(*gravity, "gravity", Bound::Any);
        if (const toml::node* steps = root.get("steps")) scene.steps = integer(*steps, "steps", 0, INT64_MAX);
        if (const toml::node* seed = root.get("seed")) scene.seed = integer(*seed, "seed", 0, INT64_MAX);

        if (const toml::array* groups = root.get_as<toml::array>("group"); groups && groups->size() > kMaxGroups)
            failAt(line(*groups), std::to_string(groups->size()) + " [[group]] tables; allowed: at most " +
                                      std::to_string(kMaxGroups) + " (for more, write a state CSV for --input-state)");
        forEachTable(root, "group", [&](const toml::table& t, const std::string& key) {
            scene.groups.push_back(group(t, key));
        });
        forEachTable(root, "disk", [&](const toml::table& t, const std::string& key) {
            scene.disks.push_back(disk(t, key));
        });
        if (const toml::node* output = root.get("output")) scene.output = outputs(*output);
        return scene;
    }

private:
    static std::size_t line(const toml::node& node) { return node.source().begin.line; }

    [[noreturn]] void failAt(std::size_t line, const std::string& message) const {
        throw Error(path_ + ":" + std::to_string(line) + ": " + message);
    }

    // A value as the user wrote it: numbers in their shortest form, strings quoted.
    static std::string shown(const toml::node& node) {
        if (const auto* f = node.as_floating_point()) {
            std::string text;
            appendNumber(text, f->get());
            // TOML's 2.0 is a float: do not show it as the integer 2.
            if (text.find_first_of(".eEna") == std::string::npos) text += ".0";
            return text;
        }
        if (const auto* s = node.as_string()) return "\"" + s->get() + "\"";
        if (const auto* a = node.as_array()) {
            std::string text;
            for (const toml::node& element : *a) text += (text.empty() ? "" : ", ") + shown(element);
            return "[" + text + "]";
        }
        if (node.is_table()) return "a table";
        std::ostringstream text;  // integers, booleans, dates and times
        node.visit([&text](const auto& v) { text << v; });
        return text.str();
    }

    // "scene.toml:7: dt = -0.01: must be a finite number > 0"
    [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& problem) const {
        failAt(line(node), key + " = " + printable(shown(node)) + ": " + problem);
    }

    void requireKnownKeys(const toml::table& table, const std::string& prefix,
                          std::initializer_list<const char*> allowed) const {
        for (const auto& [key, node] : table) {
            const std::string_view name = key.str();
            const bool known =
                std::any_of(allowed.begin(), allowed.end(), [name](const char* allowedName) { return name == allowedName; });
            if (known) continue;
            std::string list;
            for (const char* allowedName : allowed) list += (list.empty() ? "" : ", ") + std::string(allowedName);
            failAt(line(node), "unknown key '" + prefix + printable(name) + "'; allowed" +
                                   (prefix.empty() ? "" : " in " + prefix.substr(0, prefix.size() - 1)) + ": " +
                                   list);
        }
    }

    float real(const toml::node& node, const std::string& key, Bound bound) const {
        double value = 0.0;
        if (const auto* f = node.as_floating_point()) {
            value = f->get();
        } else if (const auto* i = node.as_integer()) {
            value = static_cast<double>(i->get());
        } else {
            fail(node, key, std::string("must be ") + describe(bound));
        }
        const bool inBound = bound == Bound::Any        ? std::isfinite(value)
                             : bound == Bound::Positive ? std::isfinite(value) && value > 0
                                                        : std::isfinite(value) && value >= 0;
        if (!inBound) fail(node, key, std::string("must be ") + describe(bound));
        if (std::fabs(value) > FLT_MAX) fail(node, key, "is out of range: carom computes in 32-bit floats (|x| < 3.4e38)");
        const auto single = static_cast<float>(value);
        if (bound == Bound::Positive && !(single > 0.0f))
            fail(node, key, "is too small for a 32-bit float (at least 1.2e-38)");
        return single;
    }

    std::int64_t integer(const toml::node& node, const std::string& key, std::int64_t min, std::int64_t max) const {
        const auto* i = node.as_integer();
        const std::string allowed = "must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
        if (!i || i->get() < min || i->get() > max) fail(node, key, allowed);
        return i->get();
    }

    std::string text(const toml::node& node, const std::string& key) const {
        const auto* s = node.as_string();
        if (!s || s->get().empty()) fail(node, key, "must be a non-empty string");
        return s->get();
    }

    const toml::array& numbers(const toml::node& node, const std::string& key, std::size_t count,
                               const std::string& shape) const {
        const auto* array = node.as_array();
        if (!array || array->size() != count) fail(node, key, "must be " + shape);
        return *array;
    }

    float2 pair(const toml::node& node, const std::string& key, Bound bound) const {
        const toml::array& a = numbers(node, key, 2, std::string("[x, y], two numbers, each ") + describe(bound));
        return float2{real(a[0], key + "[0]", bound), real(a[1], key + "[1]", bound)};
    }

    // `radius = 1.5` or `radius = [1, 2]`: a fixed value or a uniform range, both > 0.
    void range(const toml::node& node, const std::string& key, float& min, float& max) const {
        if (!node.is_array()) {
            min = max = real(node, key, Bound::Positive);
            return;
        }
        const toml::array& a = numbers(node, key, 2, "a number > 0 or a range [min, max] of numbers > 0");
        min = real(a[0], key + "[0]", Bound::Positive);
        max = real(a[1], key + "[1]", Bound::Positive);
        if (min > max) fail(node, key, "the range [min, max] must have min <= max");
    }

    Region region(const toml::node& node, const std::string& key) const {
        const toml::array& a = numbers(node, key, 4, "[x_min, y_min, x_max, y_max], four numbers >= 0");
        const Region r{real(a[0], key + "[0]", Bound::NonNegative), real(a[1], key + "[1]", Bound::NonNegative),
                       real(a[2], key + "[2]", Bound::NonNegative), real(a[3], key + "[3]", Bound::NonNegative)};
        if (!(r.xMin < r.xMax && r.yMin < r.yMax)) fail(node, key, "needs x_min < x_max and y_min < y_max");
        return r;
    }

    // [[name]]: an array of tables; calls each(table, "name[K]") for each.
    template <class Each>
    void forEachTable(const toml::table& root, const char* name, Each&& each) const {
        const toml::node* node = root.get(name);
        if (!node) return;
        const toml::array* array = node->as_array();
        if (!array || !array->is_array_of_tables())
            fail(*node, name, std::string("must be tables: write each as [[") + name + "]] followed by its keys");
        for (std::size_t k = 0; k < array->size(); ++k)
            each(*array->get(k)->as_table(), std::string(name) + "[" + std::to_string(k + 1) + "]");
    }

    const toml::node& required(const toml::table& t, const std::string& key, const char* name,
                               const char* meaning) const {
        const toml::node* node = t.get(name);
        if (!node) failAt(line(t), key + " needs '" + name + "' (" + meaning + ")");
        return *node;
    }

    GroupDef group(const toml::table& t, const std::string& key) const {
        requireKnownKeys(t, key + ".", {"count", "mass", "name", "radius", "region", "speed", "temperature"});
        GroupDef g;
        g.line = line(t);
        g.name = key;
        if (const toml::node* name = t.get("name")) g.name = key + " '" + printable(text(*name, key + ".name")) + "'";
        g.count = static_cast<std::uint32_t>(integer(required(t, key, "count", "the number of disks, an integer >= 1"),
                                                     key + ".count", 1, kMaxParticles));
        if (const toml::node* radius = t.get("radius")) range(*radius, key + ".radius", g.radiusMin, g.radiusMax);
        if (const toml::node* mass = t.get("mass")) range(*mass, key + ".mass", g.massMin, g.massMax);
        const toml::node* speed = t.get("speed");
        const toml::node* temperature = t.get("temperature");
        if (speed && temperature) fail(*temperature, key + ".temperature", "give speed or temperature, not both");
        if (speed) g.speed = real(*speed, key + ".speed", Bound::NonNegative);
        if (temperature) g.temperature = real(*temperature, key + ".temperature", Bound::Positive);
        if (const toml::node* r = t.get("region")) g.region = region(*r, key + ".region");
        return g;
    }

    DiskDef disk(const toml::table& t, const std::string& key) const {
        requireKnownKeys(t, key + ".", {"mass", "position", "radius", "velocity"});
        DiskDef d;
        d.line = line(t);
        d.position = pair(required(t, key, "position", "the centre [x, y]"), key + ".position", Bound::Any);
        if (const toml::node* v = t.get("velocity")) d.velocity = pair(*v, key + ".velocity", Bound::Any);
        if (const toml::node* m = t.get("mass")) d.mass = real(*m, key + ".mass", Bound::Positive);
        if (const toml::node* r = t.get("radius")) d.radius = real(*r, key + ".radius", Bound::Positive);
        return d;
    }

    OutputDef outputs(const toml::node& node) const {
        const toml::table* t = node.as_table();
        if (!t) fail(node, "output", "must be a table: write [output] followed by its keys");
        requireKnownKeys(*t, "output.", {"checkpoint", "every", "state", "stats", "trajectory"});
        OutputDef o;
        if (const toml::node* n = t->get("trajectory")) o.trajectory = text(*n, "output.trajectory");
        if (const toml::node* n = t->get("stats")) o.stats = text(*n, "output.stats");
        if (const toml::node* n = t->get("checkpoint")) o.checkpoint = text(*n, "output.checkpoint");
        if (const toml::node* n = t->get("state")) o.state = text(*n, "output.state");
        if (const toml::node* n = t->get("every")) o.every = integer(*n, "output.every", 1, INT64_MAX);
        return o;
    }

    std::string path_;
};

// ---------------------------------------------------------------------------
// Validation of the whole scene, after command-line overrides.

// "[x_min, y_min, x_max, y_max]", for messages.
std::string regionText(const Region& r) {
    std::ostringstream text;
    text << '[' << r.xMin << ", " << r.yMin << ", " << r.xMax << ", " << r.yMax << ']';
    return text.str();
}

Region wholeBox(const SceneFile& scene) { return Region{0, 0, scene.world.width, scene.world.height}; }

bool sameRegion(const Region& a, const Region& b) {
    return a.xMin == b.xMin && a.yMin == b.yMin && a.xMax == b.xMax && a.yMax == b.yMax;
}

bool regionsOverlap(const Region& a, const Region& b) {
    return a.xMin < b.xMax && b.xMin < a.xMax && a.yMin < b.yMax && b.yMin < a.yMax;
}

void requireRange(const std::string& where, const char* name, float min, float max) {
    if (!(std::isfinite(min) && min > 0.0f && std::isfinite(max) && max >= min))
        fail(where, ": ", name, " must be > 0 and finite, a range with min <= max; got [", min, ", ", max, "]");
}

void validateGroup(const SceneFile& scene, const GroupDef& g) {
    std::ostringstream whereText;
    whereText << scene.path << ':' << g.line << ": " << g.name;
    const std::string where = whereText.str();
    if (g.count < 1) fail(where, ": count must be >= 1");
    requireRange(where, "radius", g.radiusMin, g.radiusMax);
    requireRange(where, "mass", g.massMin, g.massMax);
    requireNonNegative(where + ": speed", g.speed);
    if (!(std::isfinite(g.temperature) && g.temperature >= 0.0f))
        fail(where, ": temperature must be a finite number > 0, got ", g.temperature);
    if (!g.region) return;
    if (scene.packing > 0)
        fail(where, ": a region needs a known box: give box = [W, H] instead of packing");
    const Region& r = *g.region;
    if (r.xMax > scene.world.width || r.yMax > scene.world.height)
        fail(where, ": region ", regionText(r), " extends past the ", scene.world.width, " x ", scene.world.height, " box");
}

void validateDisk(const SceneFile& scene, const DiskDef& d, std::size_t index) {
    std::ostringstream whereText;
    whereText << scene.path << ':' << d.line << ": disk[" << index + 1 << ']';
    const std::string where = whereText.str();
    if (scene.packing > 0) fail(where, ": a disk needs a known box: give box = [W, H] instead of packing");
    const float r = d.radius, w = scene.world.width, h = scene.world.height;
    const float2 x = d.position;
    // The same bounds as validateParticles, so a placed disk is accepted there.
    if (!(x.x >= r && x.x <= w - r && x.y >= r && x.y <= h - r))
        fail(where, ": position (", x.x, ", ", x.y, ") with radius ", r, " puts the disk outside the ", w, " x ", h,
             " box; the centre must lie in [", r, ", ", w - r, "] x [", r, ", ", h - r, "]");
}

// Regions shared by several groups hold one mixed lattice; regions of
// different groups must not cut into each other, or their disks could overlap.
void validateRegions(const SceneFile& scene) {
    for (std::size_t a = 0; a < scene.groups.size(); ++a) {
        for (std::size_t b = a + 1; b < scene.groups.size(); ++b) {
            const GroupDef& ga = scene.groups[a];
            const GroupDef& gb = scene.groups[b];
            const Region ra = ga.region.value_or(wholeBox(scene));
            const Region rb = gb.region.value_or(wholeBox(scene));
            if (!sameRegion(ra, rb) && regionsOverlap(ra, rb))
                fail(scene.path, ':', gb.line, ": ", gb.name, ": region ", regionText(rb), " overlaps region ", regionText(ra), " of ", ga.name,
                     " (line ", ga.line, "); give groups the same region to mix them, or disjoint regions");
        }
    }
}

// ---------------------------------------------------------------------------
// Placement.

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
        p.velocity = float2{static_cast<float>(g.speed * std::cos(angle)), static_cast<float>(g.speed * std::sin(angle))};
    }
}

struct Placed {
    float width = 0.0f;  // the region's size: the box's when sized by packing
    float height = 0.0f;
    std::vector<Particle> particles;  // in group order, positions relative to the region
};

// Rethrows a placement error with the file and the group it concerns.
template <class Place>
Placed placing(const SceneFile& scene, const GroupDef& g, Place&& place) {
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

// Throws if a [[disk]] overlaps any other disk (the groups' lattices never
// overlap by construction).
void requireNoOverlap(const SceneFile& scene, const std::vector<Particle>& particles, std::size_t firstDisk,
                      float width, float height) {
    float maxRadius = 0.0f;
    for (const Particle& p : particles) maxRadius = std::max(maxRadius, p.radius);
    Grid grid;
    grid.geometry = gridGeometryFor(width, height, maxRadius, particles.size());
    buildGrid(particles.data(), particles.size(), grid);
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
    forEachOverlappingPair(particles.data(), particles.size(), grid, carom_box(width, height, 0),
                           [&](std::uint32_t i, std::uint32_t j) {
        const DiskDef& d = scene.disks[j - firstDisk];  // j > i, so j is a [[disk]]
        fail(scene.path, ':', d.line, ": ", name(j), " at (", d.position.x, ", ", d.position.y, ") overlaps ",
             name(i), " at (", particles[i].position.x, ", ", particles[i].position.y,
             "); disks may touch but not overlap");
    });
}

}  // namespace

SceneFile parseSceneFile(std::string_view text, const std::string& path) {
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        throw Error(path + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
                    ": not valid TOML: " + std::string(e.description()));
    }
    return Parser(path).parse(root);
}

SceneFile readSceneFile(const std::string& path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
        throw Error("cannot read scene file '" + path + "': " +
                    (std::filesystem::exists(path, error) ? "not a regular file" : "no such file"));
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error("cannot read scene file '" + path + "': " + std::strerror(errno));
    const std::streamoff size = in.tellg();
    if (static_cast<std::uintmax_t>(size) > kMaxSceneFileBytes)
        throw Error("scene file '" + path + "' has " + std::to_string(size) + " bytes; a scene file is at most " +
                    std::to_string(kMaxSceneFileBytes >> 20) + " MiB (use a state CSV for many explicit disks)");
    in.seekg(0);
    std::string text(static_cast<std::size_t>(size), '\0');
    if (!in.read(text.data(), size)) throw Error("reading scene file '" + path + "' failed");
    return parseSceneFile(text, path);
}

void validate(const SceneFile& scene) {
    const std::string& where = scene.path;
    if (scene.packing > 0) {
        if (!(std::isfinite(scene.packing) && scene.packing <= kMaxPacking))
            fail(where, ": packing must be in (0, ", kMaxPacking, "], got ", scene.packing);
    } else if (!(std::isfinite(scene.world.width) && scene.world.width > 0 && std::isfinite(scene.world.height) &&
                 scene.world.height > 0)) {
        fail(where, ": the box must be two finite numbers > 0, got ", scene.world.width, " x ", scene.world.height);
    }
    WorldDef motion = scene.world;
    motion.width = motion.height = 1.0f;  // the box was checked above, or comes from packing
    try {
        validate(motion);
    } catch (const Error& e) {
        fail(where, ": ", e.what());
    }
    if (scene.groups.empty() && scene.disks.empty())
        fail(where, ": the scene has no particles: add a [[group]] (count = N) or a [[disk]]");
    std::uint64_t total = scene.disks.size();
    for (const GroupDef& g : scene.groups) {
        validateGroup(scene, g);
        total += g.count;
    }
    if (total > kMaxParticles) fail(where, ": ", total, " particles; allowed: at most ", kMaxParticles);
    validateRegions(scene);
    for (std::size_t i = 0; i < scene.disks.size(); ++i) validateDisk(scene, scene.disks[i], i);
    if (scene.output.every < 1) fail(where, ": output every must be >= 1");
}

InitialState makeInitialState(const SceneFile& scene) {
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
