// Numbers in carom's output files (the public forms are in carom/io.h).
#pragma once

#include <charconv>
#include <string>

namespace carom {

// Appends the shortest decimal that reads back to the same bits
// (std::to_chars), whatever the C locale says the decimal point is: 0.1f is
// written "0.1", never "0.100000001" or "0,1".
template <class Number>
void appendNumber(std::string& out, Number value) {
    char text[32];  // the longest double, "-2.2250738585072014e-308", has 24 characters
    const std::to_chars_result written = std::to_chars(text, text + sizeof text, value);
    out.append(text, written.ptr);
}

}  // namespace carom
