/* The parameters of a step, shared by the host C++ and the OpenCL C kernels
 * (like particle.h, compiled by both): every kernel of a (sub)step takes one
 * CaromStepParams by value (an OpenCL C 1.2 struct argument) instead of a
 * list of scalars, and the CPU backend passes the same struct to the
 * pairwise scheme's functions (pairwise.h). Every field is 4 bytes wide, so
 * the host and the device lay the structs out alike; the static_asserts at
 * the end check it on the host. */
#ifndef CAROM_PARAMS_H
#define CAROM_PARAMS_H

#include "particle.h"

#ifndef __OPENCL_VERSION__
namespace carom {
#endif

/* The box as the kernels see it (WorldDef: width, height, boundary). */
typedef struct CaromBox {
    float width;  /* [length] */
    float height; /* [length] */
    int periodic; /* 0: reflective walls; 1: the box repeats */
} CaromBox;

static inline CaromBox carom_box(float width, float height, int periodic)
{
    CaromBox box;
    box.width = width;
    box.height = height;
    box.periodic = periodic;
    return box;
}

/* What every kernel of one (sub)step reads (Backend::stepParams). */
typedef struct CaromStepParams {
    GridGeometry grid; /* the cells the grid of the step has */
    CaromBox box;
    float gravityX, gravityY; /* [length/time^2] */
    float duration;           /* the step (or substep) h [time] */
    float tolerance;          /* pairwise: overlaps up to this are float rounding, not late contacts [length] */
    unsigned int count;       /* the number of disks */
} CaromStepParams;

/* halt[0] while a chunk of steps the host enqueued without waiting runs on
 * (startPairwiseStep, kernels/pairwise.cl); else the index of the substep
 * it stopped before, and every kernel given `halt` does nothing. halt[1] is
 * not 0 where a pairwise substep searches neighbour lists that hold already:
 * its grid build then only keeps the grid's buffers ready for the next
 * (kernels/grid.cl). */
#define CAROM_RUNNING 0xFFFFFFFFu
#ifdef __OPENCL_VERSION__
#define CAROM_HALTED(halt) ((halt)[0] != CAROM_RUNNING)
#define CAROM_GRID_SKIPPED(halt) ((halt)[1] != 0u)
#endif

/* How a step is split into substeps (Backend::step, carom_substeps_needed):
 * the fewest equal substeps in which the fastest disk, sped up by gravity for
 * the whole step, moves at most `allowed` in each. */
typedef struct CaromSubstepRule {
    float dt;                 /* the whole step [time] */
    float gravity;            /* |g| [length/time^2] */
    float allowed;            /* the longest move of one substep [length] */
    unsigned int maxSubsteps; /* more are refused (kMaxSubsteps) */
} CaromSubstepRule;

#ifndef __OPENCL_VERSION__
static_assert(sizeof(CaromSubstepRule) == 16, "CaromSubstepRule must match the OpenCL struct");
static_assert(sizeof(GridGeometry) == 16 && offsetof(GridGeometry, cols) == 8 && offsetof(GridGeometry, rows) == 12,
              "GridGeometry must match the OpenCL struct");
static_assert(sizeof(CaromBox) == 12 && offsetof(CaromBox, periodic) == 8, "CaromBox must match the OpenCL struct");
static_assert(sizeof(CaromStepParams) == 48 && offsetof(CaromStepParams, box) == 16 &&
                  offsetof(CaromStepParams, gravityX) == 28 && offsetof(CaromStepParams, gravityY) == 32 &&
                  offsetof(CaromStepParams, duration) == 36 && offsetof(CaromStepParams, tolerance) == 40 &&
                  offsetof(CaromStepParams, count) == 44,
              "CaromStepParams must match the OpenCL struct");
} /* namespace carom */
#endif

#endif /* CAROM_PARAMS_H */
