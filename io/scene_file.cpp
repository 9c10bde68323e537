// Scene files, read (io::readSceneFile): a whole simulation in TOML. The
// README's "Scene files" section is the user's reference; in short:
//
//   box = [100, 60]          # or packing = 0.3 for a square box (one group, no regions, no disks)
//   boundary = "walls"       # reflective walls, or "periodic"
//   collisions = "pairwise"  # or "simultaneous"; default WorldDef's
//   dt = 0.01                # or "auto": substeps of at most max_travel = 0.2 radii
//                            # steps = 1000, gravity = [0, 0], seed = 1 are the other defaults
//   [[group]]                # disks placed on a jittered lattice, without overlap
//   count = 500
//   radius = 1.0             # or [min, max]; mass likewise
//   temperature = 1.0        # or speed = 1.0
//   region = [0, 0, 50, 60]  # x_min, y_min, x_max, y_max; default the whole box
//   [[disk]]                 # one disk, exactly where it is put
//   position = [80, 30]
//   velocity = [-2, 0]
//   [output]
//   trajectory = "run.xyz"   # also stats, checkpoint, state; every = 100
//
// Every value is checked for type, range and finiteness, and unknown keys are
// errors: the message names the file, the line, the key, the bad value and
// what is allowed.
// Each value is checked where it is read, with its line. The only file that
// sees toml++; the checks of
// the whole scene are in scene_file_validate.cpp, its placement in
// scene_placement.cpp.
#include <carom/io.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <sstream>
#include <utility>

#include <toml++/toml.h>

#include "engine/scene.h"
#include "engine/constants.h"
#include "engine/text_format.h"

namespace carom {
namespace {

constexpr std::size_t kMaxSceneFileBytes = 64u << 20;  // for many explicit disks, a state CSV
constexpr std::size_t kMaxGroups = 10000;              // regions are compared pairwise

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

    SceneFileDef parse(const toml::table& root) const {
        SceneFileDef scene;
        scene.path = path_;
        requireKnownKeys(root, "",
                         {"boundary", "box", "collisions", "disk", "dt", "gravity", "group", "max_travel", "output",
                          "packing", "seed", "steps"});
        const toml::node* box = root.get("box");
        const toml::node* packing = root.get("packing");
        if (box && packing) fail(*packing, "packing", "give box or packing, not both");
        if (!box && !packing)
            failAt(line(root),
                   "the scene needs box = [W, H] (the world is [0,W]x[0,H]) or packing = ETA "
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
            if (name == "walls")
                scene.world.boundary = Boundary::Walls;
            else if (name == "periodic")
                scene.world.boundary = Boundary::Periodic;
            else
                fail(*boundary, "boundary", "allowed: \"walls\" (reflective) or \"periodic\"");
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
        const toml::node* maxTravel = root.get("max_travel");
        if (maxTravel) scene.world.maxTravel = real(*maxTravel, "max_travel", Bound::NonNegative);  // 0: off
        if (const toml::node* dt = root.get("dt")) {
            if (dt->is_string()) {
                if (text(*dt, "dt") != "auto") fail(*dt, "dt", "must be a finite number > 0 or \"auto\"");
                if (maxTravel && scene.world.maxTravel == 0.0f)
                    fail(*maxTravel, "max_travel",
                         "dt = \"auto\" splits each step so that no disk moves more than max_travel radii, and 0 "
                         "turns that off: give max_travel > 0 (without it, " +
                             io::shortestText(kDefaultMaxTravel) + ") or a fixed dt");
                if (!maxTravel) scene.world.maxTravel = kDefaultMaxTravel;
            } else {
                scene.world.dt = real(*dt, "dt", Bound::Positive);
            }
        }
        if (const toml::node* gravity = root.get("gravity"))
            scene.world.gravity = pair(*gravity, "gravity", Bound::Any);
        if (const toml::node* steps = root.get("steps")) scene.steps = integer(*steps, "steps", 0, INT64_MAX);
        if (const toml::node* seed = root.get("seed")) scene.seed = integer(*seed, "seed", 0, INT64_MAX);

        if (const toml::array* groups = root.get_as<toml::array>("group"); groups && groups->size() > kMaxGroups)
            failAt(line(*groups), std::to_string(groups->size()) + " [[group]] tables; allowed: at most " +
                                      std::to_string(kMaxGroups) + " (for more, write a state CSV for --input-state)");
        forEachTable(root, "group",
                     [&](const toml::table& t, const std::string& key) { scene.groups.push_back(group(t, key)); });
        forEachTable(root, "disk",
                     [&](const toml::table& t, const std::string& key) { scene.disks.push_back(disk(t, key)); });
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
        failAt(line(node), key + " = " + io::printable(shown(node)) + ": " + problem);
    }

    void requireKnownKeys(const toml::table& table, const std::string& prefix,
                          std::initializer_list<const char*> allowed) const {
        for (const auto& [key, node] : table) {
            const std::string_view name = key.str();
            const bool known = std::any_of(allowed.begin(), allowed.end(),
                                           [name](const char* allowedName) { return name == allowedName; });
            if (known) continue;
            std::string list;
            for (const char* allowedName : allowed) list += (list.empty() ? "" : ", ") + std::string(allowedName);
            failAt(line(node), "unknown key '" + prefix + io::printable(name) + "'; allowed" +
                                   (prefix.empty() ? "" : " in " + prefix.substr(0, prefix.size() - 1)) + ": " + list);
        }
    }

    // The node's integer, refused where written in hexadecimal, octal or
    // binary, as every other number carom reads is (io::parseRealNumber).
    const toml::value<std::int64_t>* decimalInteger(const toml::node& node, const std::string& key) const {
        const auto* i = node.as_integer();
        constexpr auto kOtherBases = toml::value_flags::format_as_binary | toml::value_flags::format_as_octal |
                                     toml::value_flags::format_as_hexadecimal;
        if (i && (i->flags() & kOtherBases) != toml::value_flags::none)
            fail(node, key, "must be written in decimal (0x, 0o and 0b numbers are not read)");
        return i;
    }

    float real(const toml::node& node, const std::string& key, Bound bound) const {
        double value = 0.0;
        if (const auto* f = node.as_floating_point()) {
            value = f->get();
        } else if (const auto* i = decimalInteger(node, key)) {
            value = static_cast<double>(i->get());
        } else {
            fail(node, key, std::string("must be ") + describe(bound));
        }
        const bool inBound = bound == Bound::Any        ? std::isfinite(value)
                             : bound == Bound::Positive ? std::isfinite(value) && value > 0
                                                        : std::isfinite(value) && value >= 0;
        if (!inBound) fail(node, key, std::string("must be ") + describe(bound));
        try {
            return io::toFloat(value);  // carom computes in 32-bit floats
        } catch (const Error& e) {
            failAt(line(node), key + " = " + e.what());
        }
    }

    std::int64_t integer(const toml::node& node, const std::string& key, std::int64_t min, std::int64_t max) const {
        const auto* i = decimalInteger(node, key);
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
        if (const toml::node* name = t.get("name"))
            g.name = key + " '" + io::printable(text(*name, key + ".name")) + "'";
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

}  // namespace

namespace io {

SceneFileDef parseSceneFile(std::string_view text, const std::string& path) {
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        throw Error(path + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
                    ": not valid TOML: " + std::string(e.description()));
    }
    return Parser(path).parse(root);
}

SceneFileDef readSceneFile(const std::string& path) {
    return parseSceneFile(TextFile(path, "scene file").readAll(kMaxSceneFileBytes), path);
}

}  // namespace io

}  // namespace carom
