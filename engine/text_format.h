// Text in carom's output files and messages.
#pragma once

#include <algorithm>
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

// The length of the valid UTF-8 sequence `text` starts with (1 to 4
// bytes), or 0 where it starts with an invalid one: a stray continuation
// byte, a truncated or overlong sequence, a surrogate or a code point past
// U+10FFFF.
inline std::size_t utf8SequenceLength(std::string_view text) {
    const auto lead = static_cast<unsigned char>(text[0]);
    std::size_t length = 1;
    std::uint32_t codePoint = lead;
    std::uint32_t smallest = 0;  // below it the sequence is overlong
    if (lead < 0x80) return 1;
    if ((lead & 0xE0) == 0xC0) {
        length = 2, codePoint = lead & 0x1Fu, smallest = 0x80;
    } else if ((lead & 0xF0) == 0xE0) {
        length = 3, codePoint = lead & 0x0Fu, smallest = 0x800;
    } else if ((lead & 0xF8) == 0xF0) {
        length = 4, codePoint = lead & 0x07u, smallest = 0x10000;
    } else {
        return 0;
    }
    if (text.size() < length) return 0;
    for (std::size_t i = 1; i < length; ++i) {
        const auto next = static_cast<unsigned char>(text[i]);
        if ((next & 0xC0) != 0x80) return 0;
        codePoint = codePoint << 6 | (next & 0x3Fu);
    }
    const bool surrogate = codePoint >= 0xD800 && codePoint <= 0xDFFF;
    return codePoint < smallest || codePoint > 0x10FFFF || surrogate ? 0 : length;
}

// A value from an input file as a message shows it: at most 40 characters;
// valid UTF-8 as it is ("café"), control characters (C0, DEL, C1) and
// invalid bytes as \xNN, so a binary or huge file cannot flood or drive the
// terminal.
inline std::string printable(std::string_view text) {
    constexpr std::size_t kLimit = 40;
    std::string out;
    std::size_t i = 0;
    for (std::size_t shown = 0; i < text.size() && shown < kLimit; ++shown) {
        const std::size_t length = utf8SequenceLength(text.substr(i));
        const auto c = static_cast<unsigned char>(text[i]);
        // The C1 controls, U+0080 to U+009F, are C2 80 to C2 9F.
        const bool c1Control = length == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0;
        if (length > 0 && c >= 0x20 && c != 0x7f && !c1Control) {
            out.append(text.substr(i, length));
            i += length;
            continue;
        }
        for (std::size_t end = i + std::max<std::size_t>(length, 1); i < end; ++i) {
            char escaped[5];
            std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned char>(text[i]));
            out += escaped;
        }
    }
    if (i < text.size()) out += "...";
    return out;
}

}  // namespace carom
