// One number in printf's notation ("%.2f", "%.4g"), for the reports of
// `carom validate` and `carom bench`, which people read. (carom's files hold
// numbers as io::shortestText writes them, which read back bit for bit.)
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace carom::app {

// A value that is not finite (a run gone non-finite) reads "—", never "nan" or "inf".
inline std::string format(const char* pattern, double value) {
    if (!std::isfinite(value)) return "—";
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

}  // namespace carom::app
