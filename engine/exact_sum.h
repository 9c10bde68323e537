// An exact sum of floats. Every finite float is a whole multiple of 2^-149
// below 2^128, so a 320-bit two's-complement integer counting 2^-149 holds
// the sum of up to 2^42 of them without rounding. Being exact, the sum is
// the same in any order and any grouping: threads (and processes) add up
// their shares and combine them with add(const ExactSum&). value() rounds
// it once, to the nearest double.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace carom {

class ExactSum {
public:
    void add(float x) {
        std::uint32_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        const std::uint32_t exponent = (bits >> 23) & 0xffu;
        if (exponent == 0xffu) {  // inf or NaN: summed apart, in double (any order gives the same)
            nonFinite_ += double(x);
            return;
        }
        // A normal float is (2^23 + fraction) 2^(exponent - 150); a subnormal one fraction 2^-149.
        const std::uint64_t mantissa = (bits & 0x7fffffu) | (exponent ? 0x800000u : 0u);
        if (mantissa == 0) return;
        const unsigned shift = exponent ? exponent - 1 : 0;
        std::array<std::uint64_t, kWords> term{};
        term[shift / 64] = mantissa << (shift % 64);
        if (shift % 64 > 40) term[shift / 64 + 1] = mantissa >> (64 - shift % 64);
        if (bits >> 31) negate(term);
        addWords(term);
    }

    void add(const ExactSum& other) {
        addWords(other.words_);
        nonFinite_ += other.nonFinite_;
    }

    // The sum, rounded to the nearest double (ties to even); inf or NaN
    // where a term was.
    double value() const {
        if (nonFinite_ != 0.0) return nonFinite_;  // NaN too
        std::array<std::uint64_t, kWords> magnitude = words_;
        const bool negative = magnitude[kWords - 1] >> 63;
        if (negative) negate(magnitude);
        int top = -1;  // the highest bit set
        for (int w = kWords - 1; w >= 0 && top < 0; --w)
            for (int b = 63; b >= 0 && top < 0; --b)
                if ((magnitude[w] >> b) & 1u) top = w * 64 + b;
        if (top < 0) return 0.0;
        auto bit = [&](int i) -> std::uint64_t { return i < 0 ? 0 : (magnitude[i / 64] >> (i % 64)) & 1u; };
        // The 53 bits from the top (zeros below bit 0), then the rounding.
        const int last = top - 52;
        std::uint64_t significand = 0;
        for (int i = top; i >= last; --i) significand = (significand << 1) | bit(i);
        bool below = false;
        for (int i = last - 2; i >= 0 && !below; --i) below = bit(i);
        if (bit(last - 1) && (below || (significand & 1u))) ++significand;
        const double result = std::ldexp(double(significand), last - 149);
        return negative ? -result : result;
    }

private:
    static constexpr int kWords = 5;
    using Words = std::array<std::uint64_t, kWords>;

    static void negate(Words& w) {
        std::uint64_t carry = 1;
        for (std::uint64_t& word : w) {
            word = ~word + carry;
            carry = carry && word == 0;
        }
    }

    void addWords(const Words& term) {
        std::uint64_t carry = 0;
        for (int w = 0; w < kWords; ++w) {
            const std::uint64_t sum = words_[w] + term[w];
            const std::uint64_t out = sum < words_[w];
            words_[w] = sum + carry;
            carry = out | (words_[w] < sum);
        }
    }

    Words words_{};  // little-endian
    double nonFinite_ = 0.0;
};

}  // namespace carom
