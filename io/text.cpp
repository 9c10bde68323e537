// The text functions of carom/io.h: numbers read strictly and written
// shortest, values from files shown safely in messages.
#include <carom/io.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <charconv>
#include <cstdio>
#include <cstdlib>

#include "engine/scene.h"
#include "engine/text_format.h"

namespace carom::io {
namespace {

constexpr const char* kRealNumbersAllowed = "allowed: a decimal number such as 2, -0.5 or 1e-3, or inf or nan";

// The length of the valid UTF-8 sequence `text` starts with (1 to 4
// bytes), or 0 where it starts with an invalid one: a stray continuation
// byte, a truncated or overlong sequence, a surrogate or a code point past
// U+10FFFF.
std::size_t utf8SequenceLength(std::string_view text) {
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

// Refuses what strtod reads beyond carom's numbers: hexadecimal ("0x10"),
// a leading '+' or space, an empty text, anything after the number.
void requireDecimal(std::string_view text) {
    std::size_t i = !text.empty() && text[0] == '-' ? 1 : 0;
    std::string word(text.substr(i));
    for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (word == "inf" || word == "infinity" || word == "nan") return;
    const auto digitsFrom = [&text](std::size_t& at) {
        const std::size_t start = at;
        while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at]))) ++at;
        return at - start;
    };
    std::size_t digits = digitsFrom(i);
    if (i < text.size() && text[i] == '.') digits += digitsFrom(++i);
    bool valid = digits > 0;
    if (valid && i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        if (++i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        valid = digitsFrom(i) > 0;
    }
    if (!valid || i != text.size()) throw Error("'" + printable(text) + "' is not a number; " + kRealNumbersAllowed);
}

// Refuses a float that means another number than the one written (`shown`):
// one not 0 that reads as 0, a finite one that reads as infinite.
void requireSameNumber(float value, bool zero, bool infinite, const std::string& shown) {
    if (value == 0.0f && !zero)
        throw Error(shown +
                    " is too small for a 32-bit float and would read as 0 (the smallest above 0 is 1.4e-45); "
                    "write 0 for zero");
    if (std::isinf(value) && !infinite) throw Error(shown + " is too large for a 32-bit float (the largest is 3.4e38)");
}

}  // namespace

std::string wholeNumbersAllowed(std::uint64_t min, std::uint64_t max) {
    return "allowed: whole numbers from " + std::to_string(min) + " to " + std::to_string(max);
}

std::uint64_t parseWholeNumber(std::string_view text, std::uint64_t min, std::uint64_t max) {
    // A minus sign before digits is a number, just below every range.
    const bool negative = text.size() > 1 && text[0] == '-';
    const std::string_view digits = negative ? text.substr(1) : text;
    std::uint64_t value = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error == std::errc::invalid_argument || end != digits.data() + digits.size())
        throw Error("'" + printable(text) + "' is not a whole number; " + wholeNumbersAllowed(min, max));
    if (error == std::errc::result_out_of_range || (negative && value != 0) || value < min || value > max)
        throw Error("'" + printable(text) + "' is out of range; " + wholeNumbersAllowed(min, max));
    return value;
}

double parseRealNumber(std::string_view text) {
    requireDecimal(text);
    const std::string terminated(text);
    // strtod reads the C locale's decimal point: carom never changes the locale.
    return std::strtod(terminated.c_str(), nullptr);
}

float parseFloat(std::string_view text) {
    requireDecimal(text);
    const std::string terminated(text);
    // strtof rounds once, to the nearest float: through a double it could round twice.
    const float value = std::strtof(terminated.c_str(), nullptr);
    const bool zero = text.substr(0, text.find_first_of("eE")).find_first_of("123456789") == std::string::npos;
    const bool infinite = text.find_first_of("iI") != std::string::npos;
    requireSameNumber(value, zero, infinite, "'" + printable(text) + "'");
    return value;
}

float toFloat(double value) {
    const auto single = static_cast<float>(value);
    requireSameNumber(single, value == 0.0, std::isinf(value), shortestText(value));
    return single;
}

std::string shortestText(float value) {
    std::string text;
    appendNumber(text, value);
    return text;
}

std::string shortestText(double value) {
    std::string text;
    appendNumber(text, value);
    return text;
}

std::string printable(std::string_view text) {
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

}  // namespace carom::io
