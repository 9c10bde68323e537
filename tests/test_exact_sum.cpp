// Exact sums of floats (engine/exact_sum.h), and the drain of the contact
// tallies that uses them: the same bits in any order, on any number of
// threads, rounded once.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "backends/backend.h"
#include "engine/exact_sum.h"

using namespace carom;

namespace {

double exactSum(const std::vector<float>& terms) {
    ExactSum sum;
    for (float x : terms) sum.add(x);
    return sum.value();
}

// Floats of every size from subnormal to 1e37, both signs.
std::vector<float> wideFloats(std::size_t count, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(1.0f, 2.0f);
    std::uniform_int_distribution<int> exponent(-149, 122);
    std::vector<float> terms(count);
    for (float& x : terms) x = std::ldexp(unit(random), exponent(random)) * (random() % 2 ? 1.0f : -1.0f);
    return terms;
}

}  // namespace

TEST_CASE("exact sum: no term is lost to rounding, and the result is rounded once, ties to even") {
    CHECK(exactSum({1e30f, 1.0f, -1e30f}) == 1.0);  // in double: 0
    const float big = std::ldexp(1.0f, 53);
    CHECK(exactSum({big, 1.0f, 1.0f}) == std::ldexp(1.0, 53) + 2.0);  // in double, one by one: 2^53
    const float bigger = std::ldexp(1.0f, 54);                        // doubles 4 apart from here
    CHECK(exactSum({bigger, 2.0f}) == std::ldexp(1.0, 54));           // a tie: to the even significand
    CHECK(exactSum({bigger, 4.0f, 2.0f}) == std::ldexp(1.0, 54) + 8.0);
    CHECK(exactSum({bigger, 4.0f, 2.0f, std::ldexp(1.0f, -149)}) == std::ldexp(1.0, 54) + 8.0);
    CHECK(exactSum({bigger, 2.0f, std::ldexp(1.0f, -149)}) == std::ldexp(1.0, 54) + 4.0);  // past the tie: up
    CHECK(exactSum({std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::denorm_min(),
                    std::numeric_limits<float>::denorm_min()}) == std::ldexp(3.0, -149));
    CHECK(exactSum({std::numeric_limits<float>::max(), std::numeric_limits<float>::max()}) ==
          2.0 * double(std::numeric_limits<float>::max()));
    CHECK(exactSum({-2.5f, 0.5f, -0.0f}) == -2.0);
    CHECK(exactSum({}) == 0.0);
    CHECK(std::isinf(exactSum({1.0f, std::numeric_limits<float>::infinity()})));
    CHECK(std::isnan(exactSum({std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()})));
}

TEST_CASE("exact sum: any order and any grouping give the same bits, and cancelling terms give zero") {
    std::vector<float> terms = wideFloats(10000, 7);
    const double whole = exactSum(terms);
    std::vector<float> negated(terms);
    for (float& x : negated) x = -x;
    CHECK(exactSum(negated) == -whole);
    std::mt19937 random(11);
    for (int round = 0; round < 5; ++round) {
        std::shuffle(terms.begin(), terms.end(), random);
        ExactSum parts[3];
        for (std::size_t i = 0; i < terms.size(); ++i) parts[(i * 7) % 3].add(terms[i]);
        parts[2].add(parts[0]);
        parts[2].add(parts[1]);
        CHECK(parts[2].value() == whole);
        CHECK(exactSum(terms) == whole);
    }
    std::vector<float> both(terms);
    both.insert(both.end(), negated.begin(), negated.end());
    std::shuffle(both.begin(), both.end(), random);
    CHECK(exactSum(both) == 0.0);
}

TEST_CASE("exact sum: a drain of the contact tallies is the same on any number of threads and in any order") {
    const std::size_t n = 200000;  // past kParallelLength: the drain runs on the team
    std::vector<ContactTally> tallies(n);
    std::mt19937 random(3);
    std::uniform_real_distribution<float> value(0.0f, 100.0f);
    for (ContactTally& t : tallies) {
        t = ContactTally{};
        t.collisions = random() % 4;
        t.lateContacts = random() % 2;
        t.virial = std::ldexp(value(random), int(random() % 40) - 20);
        for (float& w : t.wallImpulse) w = random() % 16 == 0 ? value(random) : 0.0f;
    }
    auto drained = [&](std::vector<ContactTally> copy) {
        ContactTotals totals;
        std::vector<Image> images(n);
        drainTallyArray(copy.data(), n, totals, images.data());
        CHECK(std::all_of(copy.begin(), copy.end(),
                          [](const ContactTally& t) { return t.collisions == 0 && t.virial == 0.0f; }));  // zeroed
        return totals;
    };
    const ContactTotals first = drained(tallies);
    std::uint64_t collisions = 0;
    for (const ContactTally& t : tallies) collisions += t.collisions;
    CHECK(first.collisions == collisions);
    double virial = 0.0;  // in double, one by one: within rounding of the exact sum
    for (const ContactTally& t : tallies) virial += t.virial;
    CHECK(first.virial == doctest::Approx(virial).epsilon(1e-12));
    std::vector<ContactTally> shuffled(tallies);
    std::shuffle(shuffled.begin(), shuffled.end(), random);
#ifdef _OPENMP
    const int threads = omp_get_max_threads();
    for (const int t : {1, 2, 3, 8}) {
        CAPTURE(t);
        omp_set_num_threads(t);
        for (const auto& order : {tallies, shuffled}) {
            const ContactTotals again = drained(order);
            CHECK(again.collisions == first.collisions);
            CHECK(again.lateContacts == first.lateContacts);
            CHECK(again.virial == first.virial);
            for (std::size_t w = 0; w < 4; ++w) CHECK(again.wallImpulse[w] == first.wallImpulse[w]);
        }
    }
    omp_set_num_threads(threads);
#else
    const ContactTotals again = drained(shuffled);
    CHECK(again.virial == first.virial);
#endif
}
