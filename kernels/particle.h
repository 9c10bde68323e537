/* The data layout shared by the host C++ and the OpenCL C kernels.
 *
 * This header is compiled twice: by the host compiler (inside namespace carom)
 * and by the OpenCL compiler (embedded in the binary at build time). Both must
 * see byte-identical structs, so every type here has a fixed size and
 * alignment, checked on the host by the static_asserts at the end. */
#ifndef CAROM_PARTICLE_H
#define CAROM_PARTICLE_H

#ifdef __OPENCL_VERSION__
#define CAROM_ALIGNED(n) __attribute__((aligned(n)))
#else
#define CAROM_ALIGNED(n) alignas(n)
#include <cstddef>

#include <carom/types.h>
namespace carom {
/* OpenCL's float2 is the public Vec2: two floats, 8-byte aligned. */
using float2 = Vec2;
#endif

/* One disk. 32 bytes, 32-byte aligned, so a particle never straddles two
 * 32-byte memory segments on a GPU. */
typedef struct CAROM_ALIGNED(32) Particle {
    float2 position; /* centre [length], inside the box [0,W]x[0,H] */
    float2 velocity; /* [length/time] */
    float mass;      /* > 0 [mass] */
    float radius;    /* > 0 [length] */
    /* Used only inside a step of the pairwise scheme (kernels/pairwise.h), and
     * zero between steps: */
    float time;               /* the time within the step that position and velocity hold [time] */
    unsigned int lastPartner; /* 1 + the id of the disk it last collided with, 0 for none */
} Particle;

/* What one particle's collisions and wall bounces delivered, summed over the
 * substeps since the host last read and zeroed the tallies (Backend::contacts).
 * Pair quantities count on the lower id of the pair only, so each pair once. */
typedef struct ContactTally {
    unsigned int collisions;   /* pairs (i, j > i) that received an impulse */
    float virial;              /* sum of r_ij . J_ij over those impulses [mass length^2/time] */
    float wallImpulse[4];      /* momentum given to the left, right, bottom, top wall [mass length/time] */
    unsigned int lateContacts; /* pairwise scheme: pairs (i, j > i) found already overlapping, and
                                * wall contacts found past the wall, when resolved */
    int image[2];              /* periodic box: the box lengths the disk was wrapped back across in x
                                * and y, +1 for leaving by the right (top) side, -1 by the left (bottom) */
} ContactTally;

/* The particles of one grid cell: sortedIndices[start .. start+count). */
typedef struct GridCell {
    unsigned int start;
    unsigned int count;
} GridCell;

/* How positions map to cells. The box [0,W]x[0,H] is cut into cols x rows
 * cells; cellsPerLength is cols/W (rows/H), so a cell is at least as wide as
 * the largest disk diameter and the 3x3 cells around a disk hold every disk
 * that can touch it. */
typedef struct GridGeometry {
    float cellsPerLengthX;
    float cellsPerLengthY;
    int cols;
    int rows;
} GridGeometry;

/* What writeDiskViews (kernels/view.cl) measures, for World::readView: each
 * work-group writes CAROM_VIEW_SUM_COUNT floats, the sums as float-float pairs
 * (high, low) at these offsets, then the smallest and largest value. */
#define CAROM_VIEW_SUM_KINETIC 0        /* m v^2 / 2 */
#define CAROM_VIEW_SUM_POTENTIAL 2      /* -m g . x */
#define CAROM_VIEW_SUM_MOMENTUM_X 4     /* m v.x */
#define CAROM_VIEW_SUM_MOMENTUM_Y 6     /* m v.y */
#define CAROM_VIEW_SUM_MASS 8           /* m */
#define CAROM_VIEW_SUM_SPEED_SQUARED 10 /* v^2 */
#define CAROM_VIEW_SUM_PAIRS 6
#define CAROM_VIEW_SUM_MIN_VALUE 12
#define CAROM_VIEW_SUM_MAX_VALUE 13
#define CAROM_VIEW_SUM_COUNT 14
/* Which value writeDiskViews writes: the public ViewValue's order. */
#define CAROM_VIEW_VALUE_SPEED 0u
#define CAROM_VIEW_VALUE_MASS 1u
#define CAROM_VIEW_VALUE_RADIUS 2u
#define CAROM_VIEW_VALUE_ID 3u

#ifndef __OPENCL_VERSION__
static_assert(sizeof(float2) == 8 && alignof(float2) == 8, "float2 must match OpenCL's");
static_assert(sizeof(Particle) == 32 && alignof(Particle) == 32, "Particle is 32 bytes, 32-aligned");
static_assert(offsetof(Particle, position) == 0 && offsetof(Particle, velocity) == 8 &&
                  offsetof(Particle, mass) == 16 && offsetof(Particle, radius) == 20 &&
                  offsetof(Particle, time) == 24 && offsetof(Particle, lastPartner) == 28,
              "Particle field offsets must match the OpenCL struct");
static_assert(sizeof(ContactTally) == 36 && offsetof(ContactTally, wallImpulse) == 8 &&
                  offsetof(ContactTally, lateContacts) == 24 && offsetof(ContactTally, image) == 28,
              "ContactTally must match the OpenCL struct");
static_assert(sizeof(GridCell) == 8 && offsetof(GridCell, count) == 4, "GridCell is two uints");
static_assert(sizeof(DiskView) == 16 && offsetof(DiskView, value) == 12, "DiskView is kernels/view.cl's float4");
static_assert(int(ViewValue::Speed) == CAROM_VIEW_VALUE_SPEED && int(ViewValue::Mass) == CAROM_VIEW_VALUE_MASS &&
                  int(ViewValue::Radius) == CAROM_VIEW_VALUE_RADIUS && int(ViewValue::Id) == CAROM_VIEW_VALUE_ID,
              "ViewValue in the order of CAROM_VIEW_VALUE_*");
} /* namespace carom */
#endif

#endif /* CAROM_PARTICLE_H */
