/* The physics of one step, per particle, written once for both backends.
 *
 * The OpenMP backend calls these functions in a parallel loop; the OpenCL
 * kernels in step.cl call them once per work-item. Because both compile the
 * same source with contraction off and correctly rounded divide and sqrt,
 * every float operation happens in the same order with the same rounding, and
 * the two backends produce bitwise identical trajectories.
 *
 * Rules for this file: float literals carry the f suffix (a bare 2.0 would
 * promote the host arithmetic to double), no built-ins whose rounding may
 * differ between compilers (dot, mad, fma, native_*), and sums run in a
 * fixed order. */
#ifndef CAROM_PHYSICS_H
#define CAROM_PHYSICS_H

#include "particle.h"

#ifdef __OPENCL_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define CAROM_GLOBAL __global
#define carom_sqrt sqrt
#else
#include <cmath>
#define CAROM_GLOBAL
namespace carom {
static inline float carom_sqrt(float x) { return std::sqrt(x); }
#endif

/* The cell coordinate of a position along one axis. Positions on or beyond
 * the box edge belong to the edge cell; clamping before the conversion also
 * keeps NaN from being undefined behaviour (it lands in cell 0). */
static inline int carom_cell_coord(float position, float cellsPerLength, int cellCount)
{
    float c = position * cellsPerLength;
    float last = (float)(cellCount - 1);
    c = c > 0.0f ? c : 0.0f;
    c = c < last ? c : last;
    return (int)c;
}

static inline int carom_cell_index(float2 position, GridGeometry grid)
{
    return carom_cell_coord(position.y, grid.cellsPerLengthY, grid.rows) * grid.cols +
           carom_cell_coord(position.x, grid.cellsPerLengthX, grid.cols);
}

/* The changes that particle i collects from its neighbours in one step. */
typedef struct CaromResponse {
    float dvx, dvy; /* velocity change */
    float dpx, dpy; /* position change */
    unsigned int impulses; /* pairs (i, j > i) that received an impulse */
} CaromResponse;

/* Adds the response of particle i (`self`) to neighbour j (`other`), if they
 * overlap:
 *  - if the pair approaches, the elastic impulse
 *      dv_i = -(2 m_j / (m_i + m_j)) * ((v_i - v_j).(x_i - x_j) / |x_i - x_j|^2) (x_i - x_j)
 *    which needs no square root;
 *  - the mass-weighted positional correction: particle i moves away from j by
 *    the share m_j / (m_i + m_j) of the overlap, so the pair separates by
 *    exactly the overlap.
 * Callers visit neighbours in a fixed order, so the sums are reproducible. */
static inline void carom_add_pair_response(unsigned int i, Particle self, unsigned int j, Particle other,
                                           CaromResponse* sum)
{
    const float dx = self.position.x - other.position.x;
    const float dy = self.position.y - other.position.y;
    const float dist2 = dx * dx + dy * dy;
    const float contact = self.radius + other.radius;
    if (dist2 >= contact * contact) return;

    const float share = other.mass / (self.mass + other.mass);
    const float approach = (self.velocity.x - other.velocity.x) * dx +
                           (self.velocity.y - other.velocity.y) * dy;
    if (approach < 0.0f) { /* also false when dist2 == 0 */
        const float scale = (2.0f * share) * (approach / dist2);
        sum->dvx -= scale * dx;
        sum->dvy -= scale * dy;
        if (j > i) ++sum->impulses;
    }

    const float dist = carom_sqrt(dist2);
    const float push = (contact - dist) * share;
    if (dist > 0.0f) {
        sum->dpx += push * (dx / dist);
        sum->dpy += push * (dy / dist);
    } else {
        /* Coincident centres have no normal: separate along x, the lower id
         * to the left, so the choice is deterministic. */
        sum->dpx += j > i ? -push : push;
    }
}

/* The response of particle i (`self`) to its neighbours in the 3x3 cells
 * around it, visited in the fixed order: cell rows, then columns, then
 * ascending id within a cell. Particle sortedIndices[k] is stored at
 * in[slots[k]]: with particles stored by id, `slots` is sortedIndices itself;
 * the resident pipeline stores them in the cell order of the step before,
 * so that neighbours sit close together in memory.
 *
 * The cells of a row are consecutive, and so are their lists in
 * sortedIndices (each cell starts where the one before it ends), so one run
 * over sortedIndices covers a row's three cells in exactly that order: one
 * loop per row instead of three, which keeps the work-items of a GPU
 * wavefront in step. */
static inline CaromResponse carom_collect_response_from(unsigned int i, Particle self,
                                                        CAROM_GLOBAL const Particle* in,
                                                        CAROM_GLOBAL const unsigned int* sortedIndices,
                                                        CAROM_GLOBAL const unsigned int* slots,
                                                        CAROM_GLOBAL const GridCell* cells,
                                                        GridGeometry grid)
{
    const int cellX = carom_cell_coord(self.position.x, grid.cellsPerLengthX, grid.cols);
    const int cellY = carom_cell_coord(self.position.y, grid.cellsPerLengthY, grid.rows);
    const int firstX = cellX > 0 ? cellX - 1 : cellX;
    const int lastX = cellX + 1 < grid.cols ? cellX + 1 : cellX;
    CaromResponse sum = {0.0f, 0.0f, 0.0f, 0.0f, 0u};
    for (int y = cellY - 1; y <= cellY + 1; ++y) {
        if (y < 0 || y >= grid.rows) continue;
        const unsigned int begin = cells[y * grid.cols + firstX].start;
        const GridCell last = cells[y * grid.cols + lastX];
        for (unsigned int k = begin; k < last.start + last.count; ++k) {
            const unsigned int j = sortedIndices[k];
            if (j != i) carom_add_pair_response(i, self, j, in[slots[k]], &sum);
        }
    }
    return sum;
}

/* The response from the particles stored by id. */
static inline CaromResponse carom_collect_response(unsigned int i, Particle self,
                                                   CAROM_GLOBAL const Particle* in,
                                                   CAROM_GLOBAL const unsigned int* sortedIndices,
                                                   CAROM_GLOBAL const GridCell* cells,
                                                   GridGeometry grid)
{
    return carom_collect_response_from(i, self, in, sortedIndices, sortedIndices, cells, grid);
}

/* The same response without a grid, for the all-pairs baseline of `carom
 * bench`: every other particle, in ascending id, O(N) per particle. The same
 * pairs as the grid search, summed in another order, so not bitwise equal. */
static inline CaromResponse carom_collect_response_all_pairs(unsigned int i, Particle self,
                                                             CAROM_GLOBAL const Particle* in,
                                                             unsigned int count)
{
    CaromResponse sum = {0.0f, 0.0f, 0.0f, 0.0f, 0u};
    for (unsigned int j = 0; j < count; ++j)
        if (j != i) carom_add_pair_response(i, self, j, in[j], &sum);
    return sum;
}

/* The particle with its summed response applied. */
static inline Particle carom_apply_response(Particle self, CaromResponse sum)
{
    self.velocity.x += sum.dvx;
    self.velocity.y += sum.dvy;
    self.position.x += sum.dpx;
    self.position.y += sum.dpy;
    return self;
}

/* resolveCollisions for particle i: reads the state from before the step
 * (`in`) and writes particle i of the new state (`out`), so no work-item reads
 * what another one writes. All neighbours' responses are summed before the
 * single write. collisionCounts[i] counts the pairs (i, j > i) that received
 * an impulse, so each pair counts once. */
static inline void carom_resolve_collisions(unsigned int i,
                                            CAROM_GLOBAL const Particle* in,
                                            CAROM_GLOBAL const unsigned int* sortedIndices,
                                            CAROM_GLOBAL const GridCell* cells,
                                            GridGeometry grid,
                                            CAROM_GLOBAL Particle* out,
                                            CAROM_GLOBAL unsigned int* collisionCounts)
{
    const Particle self = in[i];
    const CaromResponse sum = carom_collect_response(i, self, in, sortedIndices, cells, grid);
    out[i] = carom_apply_response(self, sum);
    collisionCounts[i] += sum.impulses;
}

/* Reflective walls along one axis: the disk is clamped to
 * [radius, extent - radius] and its velocity component is reflected if it
 * points out of the box. (Negating unconditionally would send a disk that a
 * neighbour pushed into the wall, while it was already moving away from it,
 * back through the wall.) Two functions because OpenCL C cannot take the
 * address of a vector component. */
static inline float carom_wall_velocity(float position, float velocity, float radius, float extent)
{
    if (position < radius && velocity < 0.0f) return -velocity;
    if (position > extent - radius && velocity > 0.0f) return -velocity;
    return velocity;
}

static inline float carom_wall_position(float position, float radius, float extent)
{
    if (position < radius) return radius;
    if (position > extent - radius) return extent - radius;
    return position;
}

/* integrate: one semi-implicit Euler step (velocity first, then position
 * with the new velocity), then the walls. */
static inline Particle carom_integrate(Particle p, float dt, float gravityX, float gravityY,
                                       float width, float height)
{
    p.velocity.x += gravityX * dt;
    p.velocity.y += gravityY * dt;
    p.position.x += p.velocity.x * dt;
    p.position.y += p.velocity.y * dt;
    p.velocity.x = carom_wall_velocity(p.position.x, p.velocity.x, p.radius, width);
    p.velocity.y = carom_wall_velocity(p.position.y, p.velocity.y, p.radius, height);
    p.position.x = carom_wall_position(p.position.x, p.radius, width);
    p.position.y = carom_wall_position(p.position.y, p.radius, height);
    return p;
}

#ifndef __OPENCL_VERSION__
} /* namespace carom */
#endif

#endif /* CAROM_PHYSICS_H */
