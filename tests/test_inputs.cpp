// Inputs a person or another program hands carom: numbers on the command
// line, text shown back in messages, and state files and checkpoints whose
// size is not what it seems.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include <carom/io.h>
#include "engine/disk_conversion.h"
#include "io/checkpoint.h"
#include <carom/world.h>
#include "io/state_csv.h"
#include "support.h"

using namespace carom;
using namespace carom::test;

namespace {

constexpr std::uint64_t kU64Max = std::numeric_limits<std::uint64_t>::max();

std::string errorOf(const std::function<void()>& action) {
    try {
        action();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::string stateCsvError(const std::string& text, std::uint64_t availableBytes = 0) {
    return errorOf([&] {
        std::istringstream in(text);
        parseStateCsv(in, "in.csv", availableBytes);
    });
}

const std::string kHeaderLine = "id,x,y,vx,vy,mass,radius\n";

}  // namespace

TEST_CASE("number text: whole numbers never wrap, and an empty text is not 0") {
    CHECK(io::parseWholeNumber("0", 0, kU64Max) == 0);
    CHECK(io::parseWholeNumber("18446744073709551615", 0, kU64Max) == kU64Max);
    CHECK(io::parseWholeNumber("010", 0, kU64Max) == 10);  // decimal, not octal
    CHECK(io::parseWholeNumber("-0", 0, 5) == 0);
    const std::string allowed = "allowed: whole numbers from 0 to 18446744073709551615";
    auto refusal = [](const char* text, std::uint64_t min, std::uint64_t max) {
        return errorOf([&] { io::parseWholeNumber(text, min, max); });
    };
    CHECK(refusal("-1", 0, kU64Max) == "'-1' is out of range; " + allowed);
    CHECK(refusal("18446744073709551616", 0, kU64Max) == "'18446744073709551616' is out of range; " + allowed);
    CHECK(refusal("99999999999999999999999", 0, kU64Max) == "'99999999999999999999999' is out of range; " + allowed);
    CHECK(refusal("", 0, kU64Max) == "'' is not a whole number; " + allowed);
    for (const char* malformed : {"0x10", "+5", " 5", "5 ", "1e3", "1.0", "-", "--1", "five"})
        CHECK_MESSAGE(refusal(malformed, 0, kU64Max).find("is not a whole number") != std::string::npos, malformed);
    CHECK(refusal("0", 1, 1000) == "'0' is out of range; allowed: whole numbers from 1 to 1000");
    CHECK(refusal("1001", 1, 1000) == "'1001' is out of range; allowed: whole numbers from 1 to 1000");
}

TEST_CASE("number text: a real number is the whole text, in decimal") {
    CHECK(io::parseRealNumber("1.5") == 1.5);
    CHECK(io::parseRealNumber("-2e3") == -2000.0);
    CHECK(io::parseRealNumber(".5") == 0.5);
    CHECK(io::parseRealNumber("5.") == 5.0);
    CHECK(io::parseRealNumber("1E+2") == 100.0);
    CHECK(std::isinf(io::parseRealNumber("inf")));  // the options' own checks name the range
    CHECK(std::isinf(io::parseRealNumber("-Infinity")));
    CHECK(std::isnan(io::parseRealNumber("nan")));
    const std::string allowed = "allowed: a decimal number such as 2, -0.5 or 1e-3, or inf or nan";
    // strtod reads hexadecimal, a leading '+' or space: none is a number a person types here.
    for (const char* malformed : {"", " 1", "1 ", "1.5x", "fast", "1,5", "0x10", "0x1p3", "+0.5", "+inf", "-", ".",
                                  "1e", "1e+", "e5", "--1", "nan(1)", "infinit"})
        CHECK_MESSAGE(errorOf([&] { io::parseRealNumber(malformed); }) ==
                          "'" + std::string(malformed) + "' is not a number; " + allowed,
                      malformed);
    for (const char* malformed : {"0x10", "+0.5", " 0.5"})
        CHECK_MESSAGE(errorOf([&] { io::parseFloat(malformed); }).find("is not a number") != std::string::npos,
                      malformed);
}

TEST_CASE("number text: a float that would be another number is refused, naming the text") {
    CHECK(io::parseFloat("0.1") == 0.1f);
    CHECK(io::parseFloat("-0") == 0.0f);
    CHECK(io::parseFloat("0e-999") == 0.0f);  // zero written small is still zero
    CHECK(io::parseFloat("1e-45") > 0.0f);    // the smallest subnormal is a number
    CHECK(io::parseFloat("3.4028235e38") == std::numeric_limits<float>::max());
    CHECK(std::isinf(io::parseFloat("inf")));
    CHECK(std::isnan(io::parseFloat("nan")));
    const std::string small = " is too small for a 32-bit float and would read as 0";
    CHECK(errorOf([] { io::parseFloat("1e-50"); }).find("'1e-50'" + small) == 0);
    CHECK(errorOf([] { io::parseFloat("-0.00000000000000000000000000000000000000000000001"); }).find(small) !=
          std::string::npos);
    CHECK(errorOf([] { io::parseFloat("1e50"); }).find("'1e50' is too large for a 32-bit float") == 0);
    CHECK(io::toFloat(0.1) == 0.1f);
    CHECK(io::toFloat(0.0) == 0.0f);
    CHECK(std::isinf(io::toFloat(HUGE_VAL)));
    CHECK(errorOf([] { io::toFloat(1e-50); }).find("1e-50" + small) == 0);
    CHECK(errorOf([] { io::toFloat(-1e39); }).find("-1e+39 is too large for a 32-bit float") == 0);
}

TEST_CASE("printable: valid UTF-8 as it is; control characters and invalid bytes escaped") {
    CHECK(io::printable("caf\xC3\xA9 \xE6\x97\xA5\xE6\x9C\xAC \xF0\x9F\x8E\xB1") ==
          "caf\xC3\xA9 \xE6\x97\xA5\xE6\x9C\xAC \xF0\x9F\x8E\xB1");
    CHECK(io::printable("a\x1B[31m\x7F") == "a\\x1B[31m\\x7F");
    CHECK(io::printable("\xC2\x9B"
                        "1m") == "\\xC2\\x9B1m");                        // C1 control (CSI)
    CHECK(io::printable("\xC3") == "\\xC3");                             // truncated sequence
    CHECK(io::printable("\xA9x") == "\\xA9x");                           // stray continuation byte
    CHECK(io::printable("\xC0\xAF") == "\\xC0\\xAF");                    // overlong '/'
    CHECK(io::printable("\xED\xA0\x80") == "\\xED\\xA0\\x80");           // surrogate
    CHECK(io::printable("\xF4\x90\x80\x80") == "\\xF4\\x90\\x80\\x80");  // past U+10FFFF
    std::string accents;
    for (int i = 0; i < 50; ++i) accents += "\xC3\xA9";
    CHECK(io::printable(accents) == accents.substr(0, 80) + "...");  // 40 characters, none cut in half
}

TEST_CASE("state CSV: a line longer than 4096 bytes is refused as it is read") {
    CHECK(stateCsvError(std::string(1 << 20, '\0')) ==
          "in.csv:1: line longer than 4096 bytes; in a state file lines are at most 4096 bytes (is it a state file?)");
    CHECK(stateCsvError(kHeaderLine + "0,1,1,0,0,1,1\n" + std::string(5000, '1'))
              .find("in.csv:3: line longer than 4096") == 0);
    // A line of exactly 4096 bytes is read (trailing spaces are trimmed), with or without its newline.
    std::string row = "0,1,1,0,0,1,1";
    row += std::string(4096 - row.size(), ' ');
    for (const char* end : {"\n", ""}) {
        std::istringstream in(kHeaderLine + row + end);
        CHECK(parseStateCsv(in, "in.csv").size() == 1);
    }
}

TEST_CASE("state CSV: a NUL byte is refused, and numbers are decimal floats") {
    CHECK(stateCsvError(kHeaderLine + "0,1,1" + std::string(1, '\0') + ",0,0,1,1\n") ==
          "in.csv:2: a NUL byte, which no text file has (is it a state file?)");
    CHECK(stateCsvError(kHeaderLine + "0,0x10,1,0,0,1,1\n").find("in.csv:2: column 'x': '0x10' is not a number") == 0);
    CHECK(stateCsvError(kHeaderLine + "0,+5,1,0,0,1,1\n").find("in.csv:2: column 'x': '+5' is not a number") == 0);
    CHECK(stateCsvError(kHeaderLine + "0,5,1,1e-50,0,1,1\n")
              .find("in.csv:2: column 'vx': '1e-50' is too small for a 32-bit float") == 0);
}

TEST_CASE("state CSV: rows past the memory available are refused before they are stored") {
    const std::string threeRows = kHeaderLine + "0,1,1,0,0,1,1\n1,4,1,0,0,1,1\n2,7,1,0,0,1,1\n";
    std::istringstream in(threeRows);
    CHECK(parseStateCsv(in, "in.csv", 3 * kHostBytesPerDisk).size() == 3);
    CHECK(stateCsvError(threeRows, 2 * kHostBytesPerDisk).find("in.csv: particle rows: 3 particles need about") == 0);
}

TEST_CASE("checkpoint: the particle count is checked against memory and the checksum before allocating") {
    Snapshot c;
    c.world.width = c.world.height = 100.0f;
    for (int i = 0; i < 10; ++i) c.disks.push_back(diskOf(disk(5.0f + 9.0f * float(i), 50.0f, 1.0f, 0.0f)));
    const std::string bytes = encodeCheckpoint(c);
    { std::ofstream("inputs.ckpt", std::ios::binary) << bytes; }
    CHECK(readCheckpoint("inputs.ckpt", 10 * kHostBytesPerDisk).disks.size() == 10);
    CHECK(errorOf([] {
              readCheckpoint("inputs.ckpt", 9 * kHostBytesPerDisk);
          }).find("checkpoint 'inputs.ckpt': 10 particles need about") == 0);

    // A header forged to claim 10^7 particles, the file grown (sparse) to the
    // size that count needs, and no valid checksum: refused by the checksum.
    std::string forged = bytes.substr(0, 76);
    const std::uint64_t count = 10'000'000;
    for (int i = 0; i < 8; ++i) forged[16 + i] = static_cast<char>(count >> (8 * i));
    { std::ofstream("forged.ckpt", std::ios::binary) << forged; }
    std::filesystem::resize_file("forged.ckpt", 76 + 32 * count + 4);
    CHECK(errorOf([] { readCheckpoint("forged.ckpt"); }).find("checksum mismatch") != std::string::npos);
    std::remove("inputs.ckpt");
    std::remove("forged.ckpt");
}
