// carom/random.h: the random numbers carom draws, reproducible everywhere.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <utility>

namespace carom {

constexpr double kPi = 3.14159265358979323846;

// The random numbers makeScene draws, for callers that make their own starts
// (`carom validate`'s thermal velocities): a seed gives the same numbers
// with every standard library. std::mt19937_64 is specified bit for bit by
// the C++ standard and the std distributions are not, so every distribution
// here is written out. Changing any of them changes the placement of every
// scene; the bit-for-bit tests and the checkpoints users keep depend on them.
class Random {
public:
    explicit Random(std::uint64_t seed) : engine_(seed) {}

    // Uniform in [0, 1), 53 random bits.
    double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

    // Uniform in [lo, hi).
    double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }

    // A float drawn uniformly in [lo, hi] (a radius or a mass); a fixed
    // value, lo == hi, takes no number from the stream.
    float uniformFloat(float lo, float hi) { return lo == hi ? lo : static_cast<float>(uniform(lo, hi)); }

    // A whole number in [0, n), n >= 1.
    std::size_t below(std::size_t n) { return std::min(n - 1, static_cast<std::size_t>(unit() * double(n))); }

    // Two independent standard normal numbers (Box-Muller): the scene files' velocities.
    std::pair<double, double> normalPair() {
        const double radius = std::sqrt(-2.0 * std::log(1.0 - unit()));
        const double angle = 2 * kPi * unit();
        return {radius * std::cos(angle), radius * std::sin(angle)};
    }

    // One standard normal number (Box-Muller, the second dropped): `carom
    // validate`'s velocities. Not normalPair().first: log1p(-u) and
    // log(1 - u) may differ in the last bit, and each stream stays as it was.
    double normal() {
        const double radius = std::sqrt(-2.0 * std::log1p(-unit()));  // drawn first, as in normalPair
        return radius * std::cos(2.0 * kPi * unit());
    }

private:
    std::mt19937_64 engine_;
};

}  // namespace carom
