// Output files: extended XYZ trajectories, statistics CSV and the atomic
// writer under them; the hardened state CSV reader; resource limits.
// (tests/outputs_test.py reads the files back with ASE and drives `carom run`.)
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <locale>
#include <sstream>

#ifdef __linux__
#include <sys/resource.h>
#endif

#include <carom/files.h>
#include "engine/diagnostics.h"
#include "engine/disk_conversion.h"
#include <carom/world.h>
#include "io/state_csv.h"
#include "io/stats.h"
#include "engine/text_format.h"
#include "io/trajectory.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

std::string contents(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

bool exists(const std::string& path) { return std::ifstream(path).good(); }

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> result;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) result.push_back(line);
    return result;
}

std::vector<std::string> fields(const std::string& line, char separator) {
    std::vector<std::string> result;
    std::istringstream in(line);
    for (std::string field; std::getline(in, field, separator);) result.push_back(field);
    return result;
}

float parseFloat(const std::string& text) { return std::strtof(text.c_str(), nullptr); }

// A locale whose decimal point is a comma, as in much of Europe.
struct CommaDecimal : std::numpunct<char> {
    char do_decimal_point() const override { return ','; }
};

}  // namespace

TEST_CASE("numbers: shortest text that reads back to the same bits") {
    for (float v : {0.1f, 1.0f / 3.0f, -0.0f, 1e-45f, std::numeric_limits<float>::max(), 123456.789f}) {
        std::string text;
        appendNumber(text, v);
        CAPTURE(text);
        const float back = parseFloat(text);
        CHECK(std::memcmp(&back, &v, sizeof v) == 0);
    }
    std::string text;
    appendNumber(text, 0.1f);
    CHECK(text == "0.1");
}

TEST_CASE("trajectory: extended XYZ frames with the cell, the step and every particle field") {
    const WorldDef world = box(40, 25.5f);
    std::vector<Disk> disks = disksOf({disk(1.5f, 2.25f, 0.1f, -3, 2, 1.5f), disk(30, 20, 1.0f / 3, 0, 0.5f, 0.25f)});
    {
        TrajectoryWriter writer("t.xyz");
        writer.write(disks, world, 0, 0.0);
        disks[0].position.x = 2.0f;
        writer.write(disks, world, 10, 0.1);
        CHECK(writer.frames() == 2);
        CHECK_FALSE(exists("t.xyz"));  // not in place before commit
        writer.commit();
    }
    const std::vector<std::string> text = lines(contents("t.xyz"));
    REQUIRE(text.size() == 8);
    CHECK(text[0] == "2");
    CHECK(text[1] ==
          "Lattice=\"40 0 0 0 25.5 0 0 0 3\" Origin=\"0 0 -1.5\" pbc=\"F F F\" "
          "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:id:I:1 step=0 time=0");
    CHECK(text[2] == "X 1.5 2.25 0 0.1 -3 0 1.5 2 0");
    const std::vector<std::string> second = fields(text[3], ' ');
    REQUIRE(second.size() == 10);
    CHECK(parseFloat(second[4]) == 1.0f / 3);  // exactly
    CHECK(second[9] == "1");
    CHECK(text[5].find("step=10 time=0.1") != std::string::npos);
    CHECK(text[6].rfind("X 2 2.25 0", 0) == 0);
    std::remove("t.xyz");
}

TEST_CASE("trajectory and statistics: numbers ignore the locale") {
    const std::locale previous = std::locale::global(std::locale(std::locale::classic(), new CommaDecimal));
    {
        TrajectoryWriter trajectory("locale.xyz");
        trajectory.write(disksOf({disk(1.5f, 2.5f, 0.25f, 0)}), box(10, 10), 3, 0.03);
        trajectory.commit();
        StatsWriter stats("locale.csv");
        stats.write(3, 0.03, measure({disk(1.5f, 2.5f, 0.25f, 0)}, box(10, 10)), 0);
        stats.commit();
    }
    std::locale::global(previous);
    CHECK(contents("locale.xyz").find("X 1.5 2.5 0 0.25 0 0 1 1 0") != std::string::npos);
    CHECK(contents("locale.csv").find("3,0.03,0.03125,0.25,0,0,0,0") != std::string::npos);
    std::remove("locale.xyz");
    std::remove("locale.csv");
}

TEST_CASE("statistics: a header and one row per sample") {
    const std::vector<Particle> particles = {disk(2, 2, 1, 0, 2), disk(5, 5, 0, -2)};
    const Diagnostics d = measure(particles, box(10, 10));
    {
        StatsWriter stats("s.csv");
        stats.write(0, 0.0, d, 0);
        stats.write(100, 1.0, d, 42);
        CHECK(stats.rows() == 2);
        stats.commit();
    }
    const std::vector<std::string> text = lines(contents("s.csv"));
    REQUIRE(text.size() == 3);
    CHECK(text[0] == "step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped");
    CHECK(text[1] == "0,0,3,2,-2,0,0,0");
    CHECK(text[2] == "100,1,3,2,-2,42,0,0");
    std::remove("s.csv");
}

TEST_CASE("atomic files: complete or absent, never half-written") {
    std::ofstream("target.txt") << "old";
    std::string temporary;
    {
        io::AtomicFile file("target.txt");
        file.append("half of the new");
        temporary = file.temporaryPath();
        CHECK(exists(temporary));
    }  // destroyed without commit: an error happened
    CHECK(contents("target.txt") == "old");
    CHECK_FALSE(exists(temporary));
    {
        io::AtomicFile file("target.txt");
        file.append("new");
        temporary = file.temporaryPath();
        file.commit();
        file.commit();  // harmless
    }
    CHECK(contents("target.txt") == "new");
    CHECK_FALSE(exists(temporary));
    std::remove("target.txt");

    CHECK_THROWS_WITH_AS(io::AtomicFile("no-such-dir/x"), doctest::Contains("cannot write 'no-such-dir/x'"), Error);
    CHECK_THROWS_WITH_AS(io::AtomicFile("."), doctest::Contains("cannot write '.': it is a directory"), Error);
    CHECK_THROWS_WITH_AS(io::AtomicFile(""), doctest::Contains("empty"), Error);
}

#ifdef __linux__
TEST_CASE("atomic files: a failed write keeps the previous file") {
    // Past a file size limit every write fails (EFBIG, SIGXFSZ ignored), as on a full disk.
    std::ofstream("limited.txt") << "old";
    struct rlimit saved {};
    getrlimit(RLIMIT_FSIZE, &saved);
    const auto previousHandler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limited = saved;
    limited.rlim_cur = 4096;
    setrlimit(RLIMIT_FSIZE, &limited);
    std::string temporary;
    {
        io::AtomicFile file("limited.txt");
        temporary = file.temporaryPath();
        CHECK_THROWS_WITH_AS(
            [&] {
                file.append(std::string(1 << 20, 'x'));
                file.commit();
            }(),
            doctest::Contains("writing 'limited.txt' failed: File too large; the previous file, if any, is unchanged"),
            Error);
    }
    setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previousHandler);
    CHECK(contents("limited.txt") == "old");
    CHECK_FALSE(std::filesystem::exists(temporary));
    std::remove("limited.txt");
}
#endif

TEST_CASE("state CSV: shortest numbers, a byte order mark, long and binary values") {
    writeStateCsv("short.csv", disksOf({disk(1.5f, 2, 0.1f, 0)}));
    CHECK(contents("short.csv") == "id,x,y,vx,vy,mass,radius\n0,1.5,2,0.1,0,1,1\n");
    std::remove("short.csv");

    std::istringstream bom("\xEF\xBB\xBFid,x,y,vx,vy,mass,radius\n0,1,1,0,0,1,1\n");
    CHECK(parseStateCsv(bom, "bom.csv").size() == 1);

    auto errorOf = [](const std::string& text) -> std::string {
        std::istringstream in(text);
        try {
            parseStateCsv(in, "bad.csv");
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    const std::string longValue = errorOf("id,x,y,vx,vy,mass,radius\n0," + std::string(3000, '7') + "x,1,0,0,1,1\n");
    CHECK(longValue.find("bad.csv:2: column 'x': '777") != std::string::npos);
    CHECK(longValue.size() < 200);
    CHECK(errorOf(std::string("id,x,y,vx,vy,mass,radius\n0,1,\x01\xff,0,0,1,1\n"))
              .find("column 'y': '\\x01\\xFF' is not a number") != std::string::npos);
    CHECK(errorOf(std::string("\x01\x02\x7F", 3)).find("bad.csv:1: header is '\\x01\\x02\\x7F'") != std::string::npos);
    CHECK(errorOf(std::string("\x00\x01\x02", 3)) ==
          "bad.csv:1: a NUL byte, which no text file has (is it a state file?)");
    CHECK_THROWS_WITH_AS(readStateCsv("."), doctest::Contains("it is a directory"), Error);
}

TEST_CASE("resources: requests that cannot fit are refused before allocating") {
    CHECK_NOTHROW(requireRoomFor(1000, "--particles", 0));
    CHECK_NOTHROW(requireRoomFor(kMaxParticles, "--particles", 0));
    CHECK_THROWS_WITH_AS(requireRoomFor(kMaxParticles + 1, "--particles", 0),
                         doctest::Contains("--particles: 1000000001 particles; allowed: 1 to 1000000000"), Error);
    const std::uint64_t oneGiB = std::uint64_t{1} << 30;
    CHECK_NOTHROW(requireRoomFor(1000000, "--particles", oneGiB));
    CHECK_THROWS_WITH_AS(requireRoomFor(100000000, "--particles", oneGiB),
                         doctest::Contains("100000000 particles need about 30517 MiB of memory, more than the "
                                           "1024 MiB available"),
                         Error);
    // An OpenCL engine keeps its state on the device: less a disk on the host.
    CHECK_NOTHROW(requireRoomFor(5000000, "--particles", oneGiB, kOpenClHostBytesPerDisk));
    CHECK_THROWS_WITH_AS(requireRoomFor(10000000, "--particles", oneGiB, kOpenClHostBytesPerDisk),
                         doctest::Contains("10000000 particles need about 1220 MiB of memory"), Error);
}
