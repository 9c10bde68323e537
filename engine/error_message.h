// The refusals of bad input (internal): messages built from their parts, and
// the range checks that several validations share, so that one problem reads
// the same wherever it is found.
#pragma once

#include <cmath>
#include <sstream>
#include <string_view>

#include "engine/scene.h"

namespace carom {

// Throws Error with the parts written one after the other, as `std::ostream`
// writes them (floats with 6 significant digits).
template <class... Parts>
[[noreturn]] void fail(const Parts&... parts) {
    std::ostringstream message;
    (message << ... << parts);
    throw Error(message.str());
}

// "NAME must be a finite number > 0, got VALUE"
inline void requirePositive(std::string_view name, float value) {
    if (!(std::isfinite(value) && value > 0.0f)) fail(name, " must be a finite number > 0, got ", value);
}

// "NAME must be a finite number >= 0, got VALUE"
inline void requireNonNegative(std::string_view name, float value) {
    if (!(std::isfinite(value) && value >= 0.0f)) fail(name, " must be a finite number >= 0, got ", value);
}

}  // namespace carom
