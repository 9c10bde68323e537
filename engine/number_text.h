// Numbers as a person types them (command-line options), read strictly: the
// whole text must be the number, and a whole number must lie in its range.
// Nothing wraps around ("-1" is not 2^64 - 1), nothing is octal or
// hexadecimal, and an empty text is not 0.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace carom {

// "allowed: whole numbers from 1 to 1000": the range in a refusal.
std::string wholeNumbersAllowed(std::uint64_t min, std::uint64_t max);

// The number `text` spells in decimal digits. Throws Error naming the text
// and the range when it is not one ("'' is not a whole number; allowed:
// ...") or lies outside [min, max] ("'-1' is out of range; allowed: ...").
std::uint64_t parseWholeNumber(std::string_view text, std::uint64_t min, std::uint64_t max);

// The number `text` spells as strtod reads it (decimal, exponent, inf, nan):
// throws Error "'1.5x' is not a number" for an empty text, leading spaces or
// anything after the number. Ranges are the caller's to check.
double parseRealNumber(std::string_view text);

}  // namespace carom
