// carom::Random (include/carom/random.h), out of line: every caller draws
// the numbers this library's compilation gives (contraction off).
#include <carom/random.h>

#include <algorithm>
#include <cmath>

#include <carom/types.h>

namespace carom {

double Random::unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

double Random::uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }

float Random::uniformFloat(float lo, float hi) { return lo == hi ? lo : static_cast<float>(uniform(lo, hi)); }

std::size_t Random::below(std::size_t n) { return std::min(n - 1, static_cast<std::size_t>(unit() * double(n))); }

std::pair<double, double> Random::normalPair() {
    const double radius = std::sqrt(-2.0 * std::log(1.0 - unit()));
    const double angle = 2 * kPi * unit();
    return {radius * std::cos(angle), radius * std::sin(angle)};
}

double Random::normal() {
    const double radius = std::sqrt(-2.0 * std::log1p(-unit()));  // drawn first, as in normalPair
    return radius * std::cos(2.0 * kPi * unit());
}

}  // namespace carom
