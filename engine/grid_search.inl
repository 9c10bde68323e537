// Template body of forEachOverlappingPair (see grid.h).
#include <algorithm>
#include <iterator>
#include <vector>

#include "kernels/physics.h"

namespace carom {

template <class Visit>
bool forEachOverlappingPair(const DiskCells& cells, Visit&& visit) {
    return forEachOverlappingPairIn(cells, 0, cells.sorted.size(), visit);
}

template <class Visit>
bool forEachOverlappingPairIn(const DiskCells& cells, std::size_t from, std::size_t to, Visit&& visit) {
    using Entry = DiskCells::Entry;
    const auto& sorted = cells.sorted;
    const auto byCell = [](const Entry& e, std::uint64_t cell) { return e.cell < cell; };
    // The first entry of cell `other` or after it, found from `hint` onwards
    // in steps that double where every entry before the hint lies in an
    // earlier cell (the sweep's usual case: a few entries on), else by
    // bisection of the whole.
    using Iterator = decltype(sorted.begin());
    const auto seek = [&](std::uint64_t other, Iterator hint) {
        if (hint != sorted.begin() && std::prev(hint)->cell >= other)
            return std::lower_bound(sorted.begin(), sorted.end(), other, byCell);
        std::ptrdiff_t step = 1;
        Iterator low = hint;
        while (sorted.end() - low > step && low[step - 1].cell < other) {
            low += step;
            step *= 2;
        }
        return std::lower_bound(low, low + std::min(step, sorted.end() - low), other, byCell);
    };
    // The neighbouring columns or rows of `c` (itself included), each once:
    // a periodic box narrower than 3 cells wraps onto the same ones.
    const auto around = [&](std::uint64_t c, std::uint64_t n, std::uint64_t out[3]) {
        int found = 0;
        for (int d = -1; d <= 1; ++d) {
            std::uint64_t k = c + std::uint64_t(d);
            if (d < 0 && c == 0) {
                if (!cells.box.periodic) continue;
                k = n - 1;
            } else if (k >= n) {
                if (!cells.box.periodic) continue;
                k -= n;
            }
            if (std::find(out, out + found, k) == out + found) out[found++] = k;
        }
        return found;
    };
    const auto stop = sorted.begin() + std::ptrdiff_t(to);
    Iterator rowHints[3] = {sorted.begin(), sorted.begin(), sorted.begin()};  // the last search of each row
    for (auto first = sorted.begin() + std::ptrdiff_t(from); first != stop;) {
        const std::uint64_t cell = first->cell;
        const auto last = std::find_if(first, stop, [&](const Entry& e) { return e.cell != cell; });
        std::uint64_t columns[3], rows[3];
        const int columnCount = around(cell % cells.cols, cells.cols, columns);
        const int rowCount = around(cell / cells.cols, cells.rows, rows);
        for (int r = 0; r < rowCount; ++r) {
            Iterator hint = rowHints[r];
            for (int c = 0; c < columnCount; ++c) {
                const std::uint64_t other = rows[r] * cells.cols + columns[c];
                const Iterator begin = seek(other, hint);
                if (c == 0) rowHints[r] = begin;
                auto end = begin;
                while (end != sorted.end() && end->cell == other) ++end;
                hint = end;
                for (auto a = first; a != last; ++a) {
                    for (auto b = begin; b != end; ++b) {
                        if (b->id <= a->id) continue;
                        float dx = a->x - b->x;
                        float dy = a->y - b->y;
                        if (cells.box.periodic) {
                            dx = carom_nearest_image(dx, cells.box.width);
                            dy = carom_nearest_image(dy, cells.box.height);
                        }
                        const float contact = a->radius + b->radius;
                        if (dx * dx + dy * dy < contact * contact && !visit(a->id, b->id)) return false;
                    }
                }
            }
        }
        first = last;
    }
    return true;
}

}  // namespace carom
