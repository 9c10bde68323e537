// The numeric options of every subcommand go through these CLI11 validators
// instead of CLI11's own conversion, which turns "-1" into 2^64 - 1, a value
// past 2^64 into 2^64 - 1, "010" into 8 and "" into 0 (CLI11 2.1).
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include <CLI/CLI.hpp>

namespace carom::app {

// A whole number in [min, max] (io::parseWholeNumber, carom/io.h), handed on to CLI11
// as plain decimal digits; its refusal names the value and the range.
CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max = std::numeric_limits<std::uint64_t>::max());

// A number of disks in [min, max], whole, written in digits or with an
// exponent ("1000", "1e6", "1.6e7"); throws Error naming the text and the range.
std::uint64_t parseParticleCount(const std::string& text, std::uint64_t min, std::uint64_t max);
// The same, handed on to CLI11 as plain decimal digits.
CLI::Validator particleCount(std::uint64_t min, std::uint64_t max);

// A real number, all of the text, as the 32-bit float carom computes with
// (io::parseFloat, carom/io.h); the option's own checks judge its range.
CLI::Validator realNumber();

}  // namespace carom::app
