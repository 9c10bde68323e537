// One number in printf's notation ("%.2f", "%.4g"), for the reports of
// `carom validate` and `carom bench`.
#pragma once

#include <cstdio>
#include <string>

namespace carom::app {

inline std::string format(const char* pattern, double value) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

}  // namespace carom::app
