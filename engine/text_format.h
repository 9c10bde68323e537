// Numbers in carom's output files (the public forms are in carom/io.h).
#pragma once

#include <charconv>
#include <string>
#if defined(_LIBCPP_VERSION) && _LIBCPP_VERSION < 14000
#include <cstdio>
#include <cstdlib>
#include <type_traits>
#endif

namespace carom {

// Appends the shortest decimal that reads back to the same bits
// (std::to_chars), whatever the C locale says the decimal point is: 0.1f is
// written "0.1", never "0.100000001" or "0,1".
template <class Number>
void appendNumber(std::string& out, Number value) {
    char text[32];  // the longest double, "-2.2250738585072014e-308", has 24 characters
#if defined(_LIBCPP_VERSION) && _LIBCPP_VERSION < 14000
    // libc++ before 14 (emscripten 3.1.6's) has no floating-point to_chars:
    // the fewest significant digits that read back to the same bits. Its C
    // locale is fixed, so the point is a point.
    if constexpr (std::is_floating_point_v<Number>) {
        for (int digits = 1; digits <= 17; ++digits) {
            std::snprintf(text, sizeof text, "%.*g", digits, double(value));
            if (Number(std::strtod(text, nullptr)) == value || value != value) break;
        }
        out.append(text);
    } else
#endif
    {
        const std::to_chars_result written = std::to_chars(text, text + sizeof text, value);
        out.append(text, written.ptr);
    }
}

}  // namespace carom
