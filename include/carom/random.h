// carom/random.h: the random numbers carom draws, reproducible everywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <utility>

namespace carom {

/// The random numbers makeScene draws, for callers that make their own starts
/// (`carom validate`'s thermal velocities): a seed gives the same numbers
/// with every standard library. std::mt19937_64 is specified bit for bit by
/// the C++ standard and the std distributions are not, so every distribution
/// here is written out, and compiled inside the library (engine/random.cpp)
/// so that no caller's compiler fuses its arithmetic differently. Changing
/// any of them changes the placement of every scene; the bit-for-bit tests
/// and the checkpoints users keep depend on them.
class Random {
public:
    explicit Random(std::uint64_t seed) : engine_(seed) {}

    /// Uniform in [0, 1), 53 random bits.
    double unit();

    /// Uniform in [lo, hi).
    double uniform(double lo, double hi);

    /// A float drawn uniformly in [lo, hi] (a radius or a mass); a fixed
    /// value, lo == hi, takes no number from the stream.
    float uniformFloat(float lo, float hi);

    /// A whole number in [0, n), n >= 1.
    std::size_t below(std::size_t n);

    /// Two independent standard normal numbers (Box-Muller): the scene files' velocities.
    std::pair<double, double> normalPair();

    /// One standard normal number (Box-Muller, the second dropped): `carom
    /// validate`'s velocities. Not normalPair().first: log1p(-u) and
    /// log(1 - u) may differ in the last bit, and each stream stays as it was.
    double normal();

private:
    std::mt19937_64 engine_;
};

}  // namespace carom
