// Initial conditions, state files and the refusal of bad values.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "engine/constants.h"
#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include "io/state_csv.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

double packingOf(const InitialState& s) {
    double area = 0;
    for (const Particle& p : s.particles) area += kPi * p.radius * p.radius;
    return area / (double(s.width) * s.height);
}

WorldDef worldOf(const InitialState& s) { return box(s.width, s.height); }

std::string errorOf(const SceneDef& scene) {
    try {
        makeInitialState(scene);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::string writeFile(const std::string& name, const std::string& content) {
    std::ofstream(name, std::ios::binary) << content;
    return name;
}

std::string readError(const std::string& path) {
    try {
        readStateCsv(path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("initial conditions: no overlap, inside the box, at the requested packing") {
    struct Case {
        std::uint32_t n;
        float packing, rmin, rmax;
    };
    for (const Case c : {Case{1000, 0.7f, 1, 1}, Case{10000, 0.7f, 1, 1}, Case{2000, 0.45f, 0.5f, 1.0f},
                         Case{3, 0.3f, 1, 1}, Case{1, 0.1f, 1, 1}, Case{50, 0.6f, 1, 1}}) {
        CAPTURE(c.n);
        CAPTURE(c.packing);
        SceneDef scene;
        scene.particles = c.n;
        scene.packing = c.packing;
        scene.radiusMin = c.rmin;
        scene.radiusMax = c.rmax;
        scene.speed = 2.5f;
        const InitialState s = makeInitialState(scene);
        REQUIRE(s.particles.size() == c.n);
        CHECK(packingOf(s) == doctest::Approx(c.packing).epsilon(1e-4));
        CHECK_NOTHROW(validateParticles(s.particles, worldOf(s), "scene"));
        const Diagnostics d = measure(s.particles, worldOf(s));
        CHECK(d.maxOverlap == 0.0);
        for (const Particle& p : s.particles) {
            CHECK(std::hypot(p.velocity.x, p.velocity.y) == doctest::Approx(2.5).epsilon(1e-6));
            CHECK(p.radius >= c.rmin);
            CHECK(p.radius <= c.rmax);
        }
    }
}

TEST_CASE("initial conditions: the seed decides, bit for bit") {
    SceneDef scene;
    scene.massMin = 1;
    scene.massMax = 5;
    const InitialState a = makeInitialState(scene), b = makeInitialState(scene);
    CHECK(std::memcmp(a.particles.data(), b.particles.data(), a.particles.size() * sizeof(Particle)) == 0);
    scene.seed = 2;
    const InitialState c = makeInitialState(scene);
    CHECK(std::memcmp(a.particles.data(), c.particles.data(), a.particles.size() * sizeof(Particle)) != 0);
}

TEST_CASE("initial conditions: a given box is filled evenly") {
    SceneDef scene;
    scene.particles = 100;
    scene.width = 200;
    scene.height = 50;
    const InitialState s = makeInitialState(scene);
    CHECK(s.width == 200.0f);
    CHECK(s.height == 50.0f);
    float minX = 1e9f, maxX = 0;
    for (const Particle& p : s.particles) {
        minX = std::min(minX, p.position.x);
        maxX = std::max(maxX, p.position.x);
    }
    CHECK(minX < 20);
    CHECK(maxX > 180);
}

TEST_CASE("initial conditions: impossible or invalid requests are refused with the value named") {
    SceneDef ok;
    auto with = [&](auto change) {
        SceneDef s = ok;
        change(s);
        return errorOf(s);
    };
    CHECK(with([](SceneDef& s) { s.particles = 0; }).find("particles must be >= 1, got 0") != std::string::npos);
    CHECK(with([](SceneDef& s) { s.packing = 0.75f; }).find("packing must be in (0, 0.7], got 0.75") !=
          std::string::npos);
    CHECK(with([](SceneDef& s) { s.packing = NAN; }).find("packing") != std::string::npos);
    CHECK(with([](SceneDef& s) {
              s.radiusMin = s.radiusMax = -1;
          }).find("radius must be a finite number > 0, got -1") != std::string::npos);
    CHECK(with([](SceneDef& s) { s.massMin = s.massMax = INFINITY; }).find("mass must be") != std::string::npos);
    CHECK(with([](SceneDef& s) { s.radiusMin = 2; }).find("radius-min (2) must not exceed radius-max (1)") !=
          std::string::npos);
    CHECK(with([](SceneDef& s) { s.speed = -1; }).find("speed must be a finite number >= 0, got -1") !=
          std::string::npos);
    CHECK(with([](SceneDef& s) {
              s.width = 1;
              s.height = 10;
          }).find("does not fit") != std::string::npos);
    CHECK(with([](SceneDef& s) {
              s.width = 10;
              s.height = 10;
          }).find("cannot place 1000 disks") != std::string::npos);
    // Polydisperse disks on a lattice cannot reach 0.7: refused, naming what is reachable.
    CHECK(with([](SceneDef& s) {
              s.packing = 0.7f;
              s.radiusMin = 0.5f;
          }).find("reaches packing") != std::string::npos);
}

TEST_CASE("world values are validated") {
    auto errorOfWorld = [](WorldDef w) -> std::string {
        try {
            validate(w);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    CHECK(errorOfWorld(box(10, 10, 0)).find("dt must be a finite number > 0, got 0") != std::string::npos);
    CHECK(errorOfWorld(box(10, NAN)).find("box height") != std::string::npos);
    WorldDef w = box(10, 10);
    w.gravity = float2{0, INFINITY};
    CHECK(errorOfWorld(w).find("gravity must be finite") != std::string::npos);
    CHECK(errorOfWorld(box(10, 10)).empty());
}

TEST_CASE("particles outside the box or with bad values are refused") {
    const WorldDef world = box(10, 10);
    auto errorOfParticles = [&](std::vector<Particle> ps) -> std::string {
        try {
            validateParticles(ps, world, "state.csv");
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    CHECK(errorOfParticles({disk(0.5f, 5, 0, 0)}).find("particle 0: position (0.5, 5) puts the disk outside") !=
          std::string::npos);
    CHECK(errorOfParticles({disk(5, 5, 0, 0), disk(5, 5, 0, 0, -1)}).find("particle 1: mass") != std::string::npos);
    CHECK(errorOfParticles({disk(5, 5, NAN, 0)}).find("velocity must be finite") != std::string::npos);
    CHECK(errorOfParticles({disk(5, 5, 0, 0, 1, 6)}).find("does not fit") != std::string::npos);
    CHECK(errorOfParticles({}).find("no particles") != std::string::npos);
    CHECK(errorOfParticles({disk(1, 1, 0, 0), disk(9, 9, 0, 0)}).empty());  // touching the walls is inside
}

TEST_CASE("state CSV: written and read back bit for bit") {
    SceneDef scene;
    scene.particles = 500;
    scene.radiusMin = 0.3f;
    scene.radiusMax = 1.1f;
    scene.massMin = 0.01f;
    scene.massMax = 100.0f;
    const InitialState s = makeInitialState(scene);
    const std::vector<Disk> disks = disksOf(s.particles);
    writeStateCsv("roundtrip.csv", disks);
    const std::vector<Disk> back = readStateCsv("roundtrip.csv");
    REQUIRE(back.size() == disks.size());
    CHECK(std::memcmp(back.data(), disks.data(), back.size() * sizeof(Disk)) == 0);
    std::remove("roundtrip.csv");
}

TEST_CASE("state CSV: rows in any order, ids 0..N-1") {
    writeFile("shuffled.csv", "id,x,y,vx,vy,mass,radius\n1,3,3,0,0,1,1\n0, 5 ,5,1,0,2,1\r\n\n");
    const auto ps = readStateCsv("shuffled.csv");
    REQUIRE(ps.size() == 2);
    CHECK(ps[0].position.x == 5.0f);
    CHECK(ps[0].mass == 2.0f);
    CHECK(ps[1].position.x == 3.0f);
    std::remove("shuffled.csv");
}

TEST_CASE("state CSV: malformed files are refused with file, line and column") {
    struct Case {
        const char* content;
        const char* message;
    };
    for (const Case c : {
             Case{"", "bad.csv:1: empty file"},
             Case{"id,x,y,vx,vy,mass\n0,1,1,0,0,1\n", "bad.csv:1: header is 'id,x,y,vx,vy,mass'"},
             Case{"id,x,y,vx,vy,mass,radius\n", "no particle rows"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1\n", "bad.csv:2: expected 7 columns"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1,1,9\n", "found 8"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,abc,0,0,1,1\n", "bad.csv:2: column 'y': 'abc' is not a number"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1,\n", "column 'radius': '' is not a number"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1e999,1\n",
                  "column 'mass': '1e999' is too large for a 32-bit float"},
             Case{"id,x,y,vx,vy,mass,radius\n-1,1,1,0,0,1,1\n", "column 'id': '-1' is not a particle id"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1,1\n0,2,2,0,0,1,1\n",
                  "bad.csv:3: duplicate id 0 (first on line 2)"},
             Case{"id,x,y,vx,vy,mass,radius\n0,1,1,0,0,1,1\n5,2,2,0,0,1,1\n", "bad.csv:3: id 5 is out of range"},
         }) {
        CAPTURE(c.content);
        writeFile("bad.csv", c.content);
        CHECK(readError("bad.csv").find(c.message) != std::string::npos);
    }
    std::remove("bad.csv");
    CHECK(readError("does-not-exist.csv").find("cannot read state file 'does-not-exist.csv'") != std::string::npos);
}
