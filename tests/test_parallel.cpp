// The parallel helpers of a large start (engine/parallel.h): each gives what
// its one-thread counterpart in the standard library gives, on any number of
// threads.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "engine/parallel.h"

using namespace carom;

namespace {

// Calls check() with 1, 2, 3 and 8 OpenMP threads (once without OpenMP).
template <class Check>
void onThreadCounts(Check&& check) {
#ifdef _OPENMP
    const int threads = omp_get_max_threads();
    for (const int t : {1, 2, 3, 8}) {
        CAPTURE(t);
        omp_set_num_threads(t);
        check();
    }
    omp_set_num_threads(threads);
#else
    check();
#endif
}

}  // namespace

TEST_CASE("parallel: merging along the merge path in pieces is std::merge, ties included") {
    std::mt19937 random(3);
    std::uniform_int_distribution<int> key(0, 40);  // many equal keys
    using Item = std::pair<int, int>;               // (key, which range and place): ties are visible
    const auto less = [](const Item& a, const Item& b) { return a.first < b.first; };
    for (const std::size_t na : {0u, 1u, 7u, 300u}) {
        for (const std::size_t nb : {0u, 1u, 5u, 301u}) {
            std::vector<Item> a(na), b(nb);
            for (std::size_t i = 0; i < na; ++i) a[i] = {key(random), int(i)};
            for (std::size_t i = 0; i < nb; ++i) b[i] = {key(random), -1 - int(i)};
            std::stable_sort(a.begin(), a.end(), less);
            std::stable_sort(b.begin(), b.end(), less);
            std::vector<Item> expected(na + nb);
            std::merge(a.begin(), a.end(), b.begin(), b.end(), expected.begin(), less);
            for (const std::size_t pieces : {1u, 2u, 3u, 16u}) {
                CAPTURE(na);
                CAPTURE(nb);
                CAPTURE(pieces);
                std::vector<Item> merged(na + nb);
                for (std::size_t p = 0; p < pieces; ++p) {
                    const std::size_t d0 = (na + nb) * p / pieces, d1 = (na + nb) * (p + 1) / pieces;
                    const std::size_t i0 = mergePathSplit(a.data(), na, b.data(), nb, d0, less);
                    const std::size_t i1 = mergePathSplit(a.data(), na, b.data(), nb, d1, less);
                    std::merge(a.data() + i0, a.data() + i1, b.data() + (d0 - i0), b.data() + (d1 - i1),
                               merged.begin() + std::ptrdiff_t(d0), less);
                }
                CHECK(merged == expected);
            }
        }
    }
}

TEST_CASE("parallel: sortInParallel sorts as std::sort does, on any number of threads") {
    std::mt19937_64 random(11);
    for (const std::size_t n : {0u, 1u, 1000u, 700'001u}) {
        CAPTURE(n);
        UninitialisedVector<std::uint64_t> values(n);
        for (auto& v : values) v = random() % (4 * n + 1);
        std::vector<std::uint64_t> expected(values.begin(), values.end());
        std::sort(expected.begin(), expected.end());
        onThreadCounts([&] {
            UninitialisedVector<std::uint64_t> sorted = values;
            sortInParallel(sorted, std::less<std::uint64_t>());
            CHECK(std::equal(sorted.begin(), sorted.end(), expected.begin(), expected.end()));
        });
    }
}

TEST_CASE("parallel: kthSmallest finds what std::nth_element leaves at k, for floats and doubles") {
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto check = [&](auto values) {
        using T = typename decltype(values)::value_type;
        for (const std::size_t k : {std::size_t{0}, values.size() / 2, values.size() - 1}) {
            CAPTURE(k);
            std::vector<T> copy = values;
            std::nth_element(copy.begin(), copy.begin() + std::ptrdiff_t(k), copy.end());
            onThreadCounts([&] {
                const T found = kthSmallest(values.size(), k, [&](std::size_t i) { return values[i]; });
                CHECK(found == copy[k]);
                CHECK(!std::signbit(found));
            });
        }
    };
    std::vector<double> doubles(200'003);
    for (double& v : doubles) v = std::exp(40.0 * unit(random) - 20.0);         // many binades, all bits in play
    for (std::size_t i = 0; i < doubles.size(); i += 7) doubles[i] = HUGE_VAL;  // the disks that do not move
    for (std::size_t i = 3; i < doubles.size(); i += 11) doubles[i] = 0.25;     // ties
    doubles[1] = -0.0;
    doubles[2] = std::numeric_limits<double>::denorm_min();
    check(doubles);
    std::vector<float> floats(100'001);
    for (float& v : floats) v = float(0.5 + unit(random));
    for (std::size_t i = 0; i < floats.size(); i += 5) floats[i] = 1.0f;  // ties
    check(floats);
    check(std::vector<float>{2.0f});
}
