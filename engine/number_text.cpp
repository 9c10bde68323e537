#include "engine/number_text.h"

#include <cctype>
#include <charconv>
#include <cstdlib>

#include "engine/carom.h"
#include "engine/text_format.h"

namespace carom {

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
    const std::string terminated(text);
    char* end = nullptr;
    // strtod reads the C locale's decimal point: carom never changes the locale.
    const double value = std::strtod(terminated.c_str(), &end);
    const bool leadingSpace = !text.empty() && std::isspace(static_cast<unsigned char>(text[0]));
    if (text.empty() || leadingSpace || end != terminated.c_str() + terminated.size())
        throw Error("'" + printable(text) + "' is not a number");
    return value;
}

}  // namespace carom
