/* The physics of one step, per particle, written once for both backends.
 *
 * The OpenMP backend calls these functions in a parallel loop; the OpenCL
 * kernels call them once per work-item. Because both compile the
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

#include "params.h"

#ifdef __OPENCL_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define CAROM_GLOBAL __global
#define carom_sqrt sqrt
#define carom_ceil ceil
#define carom_isfinite isfinite
#else
#include <cmath>
#define CAROM_GLOBAL
namespace carom {
static inline float carom_sqrt(float x)
{
    return std::sqrt(x);
}
static inline float carom_ceil(float x)
{
    return std::ceil(x);
}
static inline bool carom_isfinite(float x)
{
    return std::isfinite(x);
}
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

/* The substeps a step needs when the fastest disk's v.x^2 + v.y^2 is
 * `speedSquared` (CaromSubstepRule); 0 when that is more than
 * rule.maxSubsteps or not finite. In float on the host and the device alike,
 * so that a device can check, at the start of each step it runs unattended,
 * the count the host planned for it. */
static inline unsigned int carom_substeps_needed(float speedSquared, CaromSubstepRule rule)
{
    const float speed = carom_sqrt(speedSquared) + rule.gravity * rule.dt;
    const float needed = carom_ceil(speed * rule.dt / rule.allowed);
    if (!(needed <= (float)rule.maxSubsteps)) return 0u;
    return needed < 1.0f ? 1u : (unsigned int)needed;
}

/* One component of the separation between the nearest images of two disks
 * in a periodic box of this extent. The box is at least three cells wide
 * (gridGeometryFor), so no other image can touch. */
static inline float carom_nearest_image(float d, float extent)
{
    if (d > 0.5f * extent) return d - extent;
    if (d < -0.5f * extent) return d + extent;
    return d;
}

/* a - b, to the nearest image in a periodic box. */
static inline float2 carom_offset(float2 a, float2 b, CaromBox box)
{
    float2 d;
    d.x = a.x - b.x;
    d.y = a.y - b.y;
    if (box.periodic) {
        d.x = carom_nearest_image(d.x, box.width);
        d.y = carom_nearest_image(d.y, box.height);
    }
    return d;
}

/* A periodic coordinate back into [0, extent), adding the box lengths it
 * moved back by to *image (+1 for one taken off). x + extent can round up to
 * extent itself, which is 0 in a periodic box: x was a hair below 0, which
 * is 0 in this image, so *image stays. Anything still outside after one
 * correction (a disk that crossed a whole box in one substep) goes to 0 too.
 * NaN stays NaN, for the diagnostics to report. */
static inline float carom_wrap(float x, float extent, int* image)
{
    if (x < 0.0f) {
        x += extent;
        if (x >= extent) return 0.0f;
        *image -= 1;
    } else if (x >= extent) {
        x -= extent;
        *image += 1;
    }
    if (x >= extent || x < 0.0f) return 0.0f;
    return x;
}

/* carom_wrap for both coordinates of a disk in a periodic box. */
static inline Particle carom_wrap_position(Particle p, CaromBox box, int* image)
{
    p.position.x = carom_wrap(p.position.x, box.width, &image[0]);
    p.position.y = carom_wrap(p.position.y, box.height, &image[1]);
    return p;
}

/* The changes that particle i collects from its neighbours in one step. */
typedef struct CaromResponse {
    float dvx, dvy;        /* velocity change */
    float dpx, dpy;        /* position change */
    unsigned int impulses; /* pairs (i, j > i) that received an impulse */
    float virial;          /* their r_ij . J_ij, summed */
} CaromResponse;

/* Adds the response of particle i (`self`) to neighbour j (`other`), if they
 * overlap:
 *  - if the pair approaches, the elastic impulse
 *      dv_i = -(2 m_j / (m_i + m_j)) * ((v_i - v_j).(x_i - x_j) / |x_i - x_j|^2) (x_i - x_j)
 *    which needs no square root; its virial r_ij . J_ij = 2 mu_ij |(v_i - v_j).(x_i - x_j)|
 *    (J_ij = 2 mu_ij |v_n| along x_i - x_j) needs none either;
 *  - the mass-weighted positional correction: particle i moves away from j by
 *    the share m_j / (m_i + m_j) of the overlap, so the pair separates by
 *    exactly the overlap.
 * In a periodic box the separation is to j's nearest image.
 * Callers visit neighbours in a fixed order, so the sums are reproducible. */
static inline void carom_add_pair_response(
    unsigned int i, Particle self, unsigned int j, Particle other, CaromBox box, CaromResponse* sum)
{
    const float2 d = carom_offset(self.position, other.position, box);
    const float dx = d.x, dy = d.y;
    const float dist2 = dx * dx + dy * dy;
    const float contact = self.radius + other.radius;
    if (dist2 >= contact * contact) return;

    const float share = other.mass / (self.mass + other.mass);
    const float approach = (self.velocity.x - other.velocity.x) * dx + (self.velocity.y - other.velocity.y) * dy;
    if (approach < 0.0f) { /* also false when dist2 == 0 */
        const float scale = (2.0f * share) * (approach / dist2);
        sum->dvx -= scale * dx;
        sum->dvy -= scale * dy;
        if (j > i) {
            ++sum->impulses;
            sum->virial -= (2.0f * (self.mass * share)) * approach;
        }
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

/* Adds the responses to the particles sortedIndices[begin .. end). */
static inline void carom_add_run_response(unsigned int i,
                                          Particle self,
                                          CAROM_GLOBAL const Particle* in,
                                          CAROM_GLOBAL const unsigned int* sortedIndices,
                                          CAROM_GLOBAL const unsigned int* slots,
                                          unsigned int begin,
                                          unsigned int end,
                                          CaromBox box,
                                          CaromResponse* sum)
{
    for (unsigned int k = begin; k < end; ++k) {
        const unsigned int j = sortedIndices[k];
        if (j != i) carom_add_pair_response(i, self, j, in[slots[k]], box, sum);
    }
}

/* The 3x3 cells around cell (cellX, cellY) as up to six runs of
 * sortedIndices, in a fixed order: run 2r is row r's (up to) three cells,
 * run 2r + 1 the column across the edge of a periodic box in that row.
 * The cells of a row are consecutive, and so are their lists in
 * sortedIndices (each cell starts where the one before it ends), so one run
 * covers a row's three cells in the order cell by cell would: one loop per
 * row instead of three, which keeps the work-items of a GPU wavefront in
 * step. In a periodic box the rows wrap around, and a disk in an edge column
 * also visits the column across the edge (the grid is at least 3 x 3, so
 * that column is never in the row's run). Returns 0 for a run that does not
 * exist (a row outside a walled box, no column across). */
static inline int carom_neighbour_run(int run,
                                      int cellX,
                                      int cellY,
                                      CAROM_GLOBAL const GridCell* cells,
                                      GridGeometry grid,
                                      CaromBox box,
                                      unsigned int* begin,
                                      unsigned int* end)
{
    int y = cellY - 1 + run / 2;
    if (box.periodic)
        y = y < 0 ? y + grid.rows : (y >= grid.rows ? y - grid.rows : y);
    else if (y < 0 || y >= grid.rows)
        return 0;
    if (run % 2 == 0) {
        const int firstX = cellX > 0 ? cellX - 1 : cellX;
        const int lastX = cellX + 1 < grid.cols ? cellX + 1 : cellX;
        const GridCell last = cells[y * grid.cols + lastX];
        *begin = cells[y * grid.cols + firstX].start;
        *end = last.start + last.count;
        return 1;
    }
    int acrossX = -1;
    if (box.periodic && cellX == 0) acrossX = grid.cols - 1;
    if (box.periodic && cellX == grid.cols - 1) acrossX = 0;
    if (acrossX < 0) return 0;
    const GridCell across = cells[y * grid.cols + acrossX];
    *begin = across.start;
    *end = across.start + across.count;
    return 1;
}

/* The response of particle i (`self`) to its neighbours in the 3x3 cells
 * around it, visited in the fixed order of carom_neighbour_run, ascending
 * id within a cell. Particle sortedIndices[k] is stored at in[slots[k]]:
 * with particles stored by id, `slots` is sortedIndices itself; the resident
 * pipeline stores them in the cell order of the step before, so that
 * neighbours sit close together in memory. */
static inline CaromResponse carom_collect_response_from(unsigned int i,
                                                        Particle self,
                                                        CAROM_GLOBAL const Particle* in,
                                                        CAROM_GLOBAL const unsigned int* sortedIndices,
                                                        CAROM_GLOBAL const unsigned int* slots,
                                                        CAROM_GLOBAL const GridCell* cells,
                                                        GridGeometry grid,
                                                        CaromBox box)
{
    const int cellX = carom_cell_coord(self.position.x, grid.cellsPerLengthX, grid.cols);
    const int cellY = carom_cell_coord(self.position.y, grid.cellsPerLengthY, grid.rows);
    CaromResponse sum = {0.0f, 0.0f, 0.0f, 0.0f, 0u, 0.0f};
    for (int run = 0; run < 6; ++run) {
        unsigned int begin, end;
        if (carom_neighbour_run(run, cellX, cellY, cells, grid, box, &begin, &end))
            carom_add_run_response(i, self, in, sortedIndices, slots, begin, end, box, &sum);
    }
    return sum;
}

/* The response from the particles stored by id. */
static inline CaromResponse carom_collect_response(unsigned int i,
                                                   Particle self,
                                                   CAROM_GLOBAL const Particle* in,
                                                   CAROM_GLOBAL const unsigned int* sortedIndices,
                                                   CAROM_GLOBAL const GridCell* cells,
                                                   GridGeometry grid,
                                                   CaromBox box)
{
    return carom_collect_response_from(i, self, in, sortedIndices, sortedIndices, cells, grid, box);
}

/* The same response without a grid, for the all-pairs baseline of `carom
 * bench`: every other particle, in ascending id, O(N) per particle. The same
 * pairs as the grid search, summed in another order, so not bitwise equal. */
static inline CaromResponse carom_collect_response_all_pairs(
    unsigned int i, Particle self, CAROM_GLOBAL const Particle* in, unsigned int count, CaromBox box)
{
    CaromResponse sum = {0.0f, 0.0f, 0.0f, 0.0f, 0u, 0.0f};
    for (unsigned int j = 0; j < count; ++j)
        if (j != i) carom_add_pair_response(i, self, j, in[j], box, &sum);
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

/* Adds a step's collisions and wall impulses to the particle's tally. Most
 * particles receive no impulse and touch no wall in a step: they skip the
 * read-modify-write. */
static inline void carom_record_collisions(CAROM_GLOBAL ContactTally* tally, CaromResponse sum)
{
    if (sum.impulses == 0u) return;
    tally->collisions += sum.impulses;
    tally->virial += sum.virial;
}

static inline void carom_record_walls(CAROM_GLOBAL ContactTally* tally, const float* wallImpulse)
{
    if (wallImpulse[0] == 0.0f && wallImpulse[1] == 0.0f && wallImpulse[2] == 0.0f && wallImpulse[3] == 0.0f) return;
    for (int w = 0; w < 4; ++w) tally->wallImpulse[w] += wallImpulse[w];
}

/* Adds the box lengths a wrap moved the disk back by (carom_wrap). */
static inline void carom_record_image(CAROM_GLOBAL ContactTally* tally, const int* image)
{
    if (image[0] == 0 && image[1] == 0) return;
    tally->image[0] += image[0];
    tally->image[1] += image[1];
}

/* resolveCollisions for particle i: reads the state from before the step
 * (`in`) and writes particle i of the new state (`out`), so no work-item reads
 * what another one writes. All neighbours' responses are summed before the
 * single write. */
static inline void carom_resolve_collisions(unsigned int i,
                                            CAROM_GLOBAL const Particle* in,
                                            CAROM_GLOBAL const unsigned int* sortedIndices,
                                            CAROM_GLOBAL const GridCell* cells,
                                            GridGeometry grid,
                                            CaromBox box,
                                            CAROM_GLOBAL Particle* out,
                                            CAROM_GLOBAL ContactTally* tallies)
{
    const Particle self = in[i];
    const CaromResponse sum = carom_collect_response(i, self, in, sortedIndices, cells, grid, box);
    out[i] = carom_apply_response(self, sum);
    carom_record_collisions(&tallies[i], sum);
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

/* The momentum 2 m |v| a reflection of velocity component `before` gives
 * the wall it points at: wallImpulse[low] if it pointed down the axis, else
 * wallImpulse[low + 1]. Nothing if the wall did not reflect it. */
static inline void carom_add_wall_impulse(float mass, float before, float after, int low, float* wallImpulse)
{
    if (after == before) return;
    if (before < 0.0f)
        wallImpulse[low] += (2.0f * mass) * -before;
    else
        wallImpulse[low + 1] += (2.0f * mass) * before;
}

/* integrate: one semi-implicit Euler step (velocity first, then position
 * with the new velocity), then the boundary: wrapped around a periodic box,
 * the wraps added to image (x, y), or reflected by the walls, whose impulses
 * are added to wallImpulse (left, right, bottom, top). */
static inline Particle carom_integrate(
    Particle p, float dt, float gravityX, float gravityY, CaromBox box, float* wallImpulse, int* image)
{
    p.velocity.x += gravityX * dt;
    p.velocity.y += gravityY * dt;
    p.position.x += p.velocity.x * dt;
    p.position.y += p.velocity.y * dt;
    if (box.periodic) return carom_wrap_position(p, box, image);
    const float vx = p.velocity.x;
    const float vy = p.velocity.y;
    p.velocity.x = carom_wall_velocity(p.position.x, vx, p.radius, box.width);
    p.velocity.y = carom_wall_velocity(p.position.y, vy, p.radius, box.height);
    carom_add_wall_impulse(p.mass, vx, p.velocity.x, 0, wallImpulse);
    carom_add_wall_impulse(p.mass, vy, p.velocity.y, 2, wallImpulse);
    p.position.x = carom_wall_position(p.position.x, p.radius, box.width);
    p.position.y = carom_wall_position(p.position.y, p.radius, box.height);
    return p;
}

/* integrate for particle i, recording its wall impulses and wraps. */
static inline void carom_integrate_into(unsigned int i,
                                        CAROM_GLOBAL Particle* particles,
                                        float dt,
                                        float gravityX,
                                        float gravityY,
                                        CaromBox box,
                                        CAROM_GLOBAL ContactTally* tallies)
{
    float wallImpulse[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    int image[2] = {0, 0};
    particles[i] = carom_integrate(particles[i], dt, gravityX, gravityY, box, wallImpulse, image);
    carom_record_walls(&tallies[i], wallImpulse);
    carom_record_image(&tallies[i], image);
}

/* v.x^2 + v.y^2: the quantity the max-speed reduction compares. */
static inline float carom_speed_squared(Particle p)
{
    return p.velocity.x * p.velocity.x + p.velocity.y * p.velocity.y;
}

/* Whether a disk's position and velocity are finite. A step that leaves one
 * that is not has blown up: the backends stop there (Backend::nonFinite). */
static inline int carom_is_finite(Particle p)
{
    return carom_isfinite(p.position.x) && carom_isfinite(p.position.y) && carom_isfinite(p.velocity.x) &&
           carom_isfinite(p.velocity.y);
}

/* firstNonFinite[0] before any disk went non-finite (carom_record_non_finite). */
#define CAROM_ALL_FINITE 0xFFFFFFFFu

#ifdef __OPENCL_VERSION__
/* Records particle `id`, left by step `step` (counted from a start the host
 * chooses), if it is not finite: firstNonFinite[0] is the first step that
 * left one, [1] the lowest id among that step's (the host sets both to
 * CAROM_ALL_FINITE). A step is one kernel launch after another, so [0] only ever
 * drops to the step running, and a later step leaves it alone. */
static inline void carom_record_non_finite(Particle p, uint id, uint step, __global uint* firstNonFinite)
{
    if (carom_is_finite(p) || firstNonFinite[0] < step) return;
    firstNonFinite[0] = step;
    atomic_min(&firstNonFinite[1], id);
}
#else
} /* namespace carom */
#endif

#endif /* CAROM_PHYSICS_H */
