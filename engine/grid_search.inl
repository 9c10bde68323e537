// Template body of forEachOverlappingPair (see grid.h).
#include "kernels/physics.h"

namespace carom {

template <class Visit>
void forEachOverlappingPair(const Particle* particles, std::size_t count, const Grid& grid, CaromBox box,
                            Visit&& visit) {
    const GridGeometry& g = grid.geometry;
    for (std::uint32_t i = 0; i < count; ++i) {
        const Particle& self = particles[i];
        const int cellX = carom_cell_coord(self.position.x, g.cellsPerLengthX, g.cols);
        const int cellY = carom_cell_coord(self.position.y, g.cellsPerLengthY, g.rows);
        for (int row = cellY - 1; row <= cellY + 1; ++row) {
            const int y = box.periodic ? (row + g.rows) % g.rows : row;
            if (y < 0 || y >= g.rows) continue;
            for (int column = cellX - 1; column <= cellX + 1; ++column) {
                const int x = box.periodic ? (column + g.cols) % g.cols : column;
                if (x < 0 || x >= g.cols) continue;
                const GridCell cell = grid.cells[std::size_t(y) * g.cols + x];
                for (std::uint32_t k = cell.start; k < cell.start + cell.count; ++k) {
                    const std::uint32_t j = grid.sortedIndices[k];
                    if (j <= i) continue;
                    const Particle& other = particles[j];
                    float dx = self.position.x - other.position.x;
                    float dy = self.position.y - other.position.y;
                    if (box.periodic) {
                        dx = carom_nearest_image(dx, box.width);
                        dy = carom_nearest_image(dy, box.height);
                    }
                    const float contact = self.radius + other.radius;
                    if (dx * dx + dy * dy < contact * contact) visit(i, j);
                }
            }
        }
    }
}

}  // namespace carom
