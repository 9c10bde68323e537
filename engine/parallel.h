// Loops over whole states on the OpenMP threads, whose results do not depend
// on the number of threads: the start of a large run (placing, converting,
// checking and sorting 10^8 disks) has to scale as a step does.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace carom {

// Elements below which a loop runs on one thread (starting the team costs more).
constexpr std::int64_t kParallelLength = 1 << 16;

inline int parallelThreads() {
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

// The calling thread's number in its OpenMP team (0 outside one).
inline int threadNumber() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

// body(i) for every i in [0, n), in static blocks over the threads.
template <class Body>
void parallelFor(std::size_t n, Body&& body) {
    const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(static) if (count >= kParallelLength)
    for (std::int64_t i = 0; i < count; ++i) body(std::size_t(i));
}

// body(first, end) over [0, n) cut into one block per thread (one block
// below kParallelLength), for passes that carry state from one element to
// the next.
template <class Body>
void parallelBlocks(std::size_t n, Body&& body) {
    const auto blocks = static_cast<std::int64_t>(n) >= kParallelLength ? std::int64_t(parallelThreads()) : 1;
#pragma omp parallel for schedule(static) if (blocks > 1)
    for (std::int64_t b = 0; b < blocks; ++b)
        body(n * std::size_t(b) / std::size_t(blocks), n * std::size_t(b + 1) / std::size_t(blocks));
}

// An allocator whose resize leaves the new elements default-initialised
// (not zeroed) where they have a trivial constructor, so that the parallel
// loop that writes them is the first to touch their pages.
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitialisedAllocator<U>;
    };
    UninitialisedAllocator() = default;
    template <class U>
    UninitialisedAllocator(const UninitialisedAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T>
using UninitialisedVector = std::vector<T, UninitialisedAllocator<T>>;

// How many of a[0, na) come first in the merge of a and b (std::merge's,
// which takes a's element first where two are equal) when it has written
// d elements: the merge path's crossing of diagonal d, by bisection.
template <class It, class Less>
std::size_t mergePathSplit(It a, std::size_t na, It b, std::size_t nb, std::size_t d, Less less) {
    std::size_t lo = d > nb ? d - nb : 0, hi = std::min(d, na);
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (less(b[d - mid - 1], a[mid]))
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

// std::sort of `items` by `less`, a total order (so the result is the one
// sorted sequence, whatever the thread count): blocks sorted in parallel,
// then merged pairwise level by level, each merge cut along its merge path
// into pieces for every thread, so the last merges run in parallel too.
template <class T, class Less>
void sortInParallel(UninitialisedVector<T>& items, Less less) {
    const std::size_t n = items.size();
    const int threads = parallelThreads();
    std::size_t blocks = 1;
    while (blocks < std::size_t(threads) && n / (2 * blocks) >= std::size_t(kParallelLength)) blocks *= 2;
    const auto bound = [&](std::size_t b) { return n * b / blocks; };
    const auto blockCount = static_cast<std::int64_t>(blocks);
#pragma omp parallel for schedule(static, 1) if (blocks > 1)
    for (std::int64_t b = 0; b < blockCount; ++b)
        std::sort(items.begin() + bound(std::size_t(b)), items.begin() + bound(std::size_t(b) + 1), less);
    if (blocks == 1) return;

    UninitialisedVector<T> other(n);
    T* from = items.data();
    T* to = other.data();
    const std::size_t pieces = std::size_t(threads);  // per merge
    for (std::size_t width = 1; width < blocks; width *= 2) {
        const auto tasks = static_cast<std::int64_t>(blocks / (2 * width) * pieces);
#pragma omp parallel for schedule(static, 1)
        for (std::int64_t t = 0; t < tasks; ++t) {
            const std::size_t pair = std::size_t(t) / pieces, piece = std::size_t(t) % pieces;
            const std::size_t begin = bound(2 * width * pair), middle = bound(2 * width * pair + width),
                              end = bound(2 * width * (pair + 1));
            const T* a = from + begin;
            const T* b = from + middle;
            const std::size_t na = middle - begin, nb = end - middle;
            const std::size_t d0 = (na + nb) * piece / pieces, d1 = (na + nb) * (piece + 1) / pieces;
            const std::size_t i0 = mergePathSplit(a, na, b, nb, d0, less);
            const std::size_t i1 = mergePathSplit(a, na, b, nb, d1, less);
            std::merge(a + i0, a + i1, b + (d0 - i0), b + (d1 - i1), to + begin + d0, less);
        }
        std::swap(from, to);
    }
    if (from != items.data()) items.swap(other);
}

// The k-th smallest (from 0) of value(0), ..., value(n - 1), k < n, each a
// float or double >= 0 (their bits then order as their values do, +inf
// last): what std::nth_element would leave at k, found by radix selection,
// whose passes over the values each fix 16 more bits of the answer and run
// in parallel (the counts of each thread added, so exact).
template <class Value>
auto kthSmallest(std::size_t n, std::size_t k, Value&& value) {
    using T = decltype(value(std::size_t{0}));
    static_assert(std::is_floating_point_v<T> && (sizeof(T) == 4 || sizeof(T) == 8), "float or double values");
    using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
    constexpr int kBits = int(sizeof(T)) * 8, kDigitBits = 16;
    constexpr std::size_t kDigits = std::size_t(1) << kDigitBits;
    const auto bitsOf = [](T v) {
        v += T(0);  // -0 as +0
        Bits bits;
        std::memcpy(&bits, &v, sizeof bits);
        return bits;
    };
    Bits prefix = 0;
    std::size_t rank = k;
    std::vector<std::uint64_t> counts(kDigits);
    for (int shift = kBits - kDigitBits; shift >= 0; shift -= kDigitBits) {
        const Bits fixed = shift + kDigitBits == kBits ? Bits(0) : ~Bits(0) << (shift + kDigitBits);
        std::fill(counts.begin(), counts.end(), 0);
        const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel if (count >= kParallelLength)
        {
            std::vector<std::uint64_t> mine(kDigits, 0);
#pragma omp for schedule(static)
            for (std::int64_t i = 0; i < count; ++i) {
                const Bits bits = bitsOf(value(std::size_t(i)));
                if ((bits & fixed) == prefix) ++mine[std::size_t(bits >> shift) & (kDigits - 1)];
            }
#pragma omp critical
            for (std::size_t d = 0; d < kDigits; ++d) counts[d] += mine[d];
        }
        std::size_t digit = 0;
        while (rank >= counts[digit]) rank -= counts[digit++];
        prefix |= Bits(digit) << shift;
    }
    T result;
    std::memcpy(&result, &prefix, sizeof result);
    return result;
}

}  // namespace carom
