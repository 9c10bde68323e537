// Text in carom's output files and messages.
#pragma once

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

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

// A value from an input file as a message shows it: at most 40 characters,
// control and non-ASCII bytes as \xNN, so a binary or huge file cannot flood
// the terminal.
inline std::string printable(std::string_view text) {
    constexpr std::size_t kLimit = 40;
    std::string out;
    for (std::size_t i = 0; i < text.size() && i < kLimit; ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            char escaped[5];
            std::snprintf(escaped, sizeof escaped, "\\x%02X", c);
            out += escaped;
        }
    }
    if (text.size() > kLimit) out += "...";
    return out;
}

}  // namespace carom
