// Template body of forEachOverlappingPair (see grid.h).
#include <algorithm>

#include "kernels/physics.h"

namespace carom {

template <class Visit>
bool forEachOverlappingPair(const Particle* particles, const DiskCells& cells, Visit&& visit) {
    using Entry = DiskCells::Entry;
    const std::vector<Entry>& sorted = cells.sorted;
    const auto byCell = [](const Entry& e, std::uint64_t cell) { return e.cell < cell; };
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
    for (auto first = sorted.begin(); first != sorted.end();) {
        const std::uint64_t cell = first->cell;
        const auto last = std::find_if(first, sorted.end(), [&](const Entry& e) { return e.cell != cell; });
        std::uint64_t columns[3], rows[3];
        const int columnCount = around(cell % cells.cols, cells.cols, columns);
        const int rowCount = around(cell / cells.cols, cells.rows, rows);
        for (int r = 0; r < rowCount; ++r) {
            for (int c = 0; c < columnCount; ++c) {
                const std::uint64_t other = rows[r] * cells.cols + columns[c];
                auto begin = std::lower_bound(sorted.begin(), sorted.end(), other, byCell);
                auto end = begin;
                while (end != sorted.end() && end->cell == other) ++end;
                for (auto a = first; a != last; ++a) {
                    const Particle& self = particles[a->id];
                    for (auto b = begin; b != end; ++b) {
                        if (b->id <= a->id) continue;
                        const Particle& them = particles[b->id];
                        float dx = self.position.x - them.position.x;
                        float dy = self.position.y - them.position.y;
                        if (cells.box.periodic) {
                            dx = carom_nearest_image(dx, cells.box.width);
                            dy = carom_nearest_image(dy, cells.box.height);
                        }
                        const float contact = self.radius + them.radius;
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
