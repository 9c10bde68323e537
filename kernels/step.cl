/* The kernels of the host-grid pipeline's step, one work-item per particle, and
 * the max-speed reduction that sizes substeps. The physics itself lives in
 * physics.h, which the CPU backend compiles too. */
#include "physics.h"

__kernel void resolveCollisions(__global const Particle* in,
                                __global const uint* sortedIndices,
                                __global const GridCell* cells,
                                CaromStepParams step,
                                __global Particle* out,
                                __global ContactTally* tallies)
{
    const uint i = get_global_id(0);
    if (i >= step.count) return;
    carom_resolve_collisions(i, in, sortedIndices, cells, step.grid, step.box, out, tallies);
}

__kernel void integrate(__global Particle* particles,
                        CaromStepParams step,
                        __global ContactTally* tallies,
                        uint stepIndex,
                        __global uint* firstNonFinite)
{
    const uint i = get_global_id(0);
    if (i >= step.count) return;
    carom_integrate_into(i, particles, step.duration, step.gravityX, step.gravityY, step.box, tallies);
    carom_record_non_finite(particles[i], i, stepIndex, firstNonFinite);
}

/* The largest v.x^2 + v.y^2 of each work-group's particles, into
 * groupMax[group]: each work-item takes every (global size)-th particle,
 * then the work-group halves its values in local memory. max is exact in any
 * order, so the host's max over groupMax equals the CPU backend's bit for
 * bit. The local size must be a power of two. */
__kernel void maxSpeedSquared(__global const Particle* particles,
                              uint count,
                              __local float* scratch,
                              __global float* groupMax)
{
    float largest = 0.0f;
    for (uint i = get_global_id(0); i < count; i += get_global_size(0))
        largest = fmax(largest, carom_speed_squared(particles[i]));
    const uint lid = get_local_id(0);
    scratch[lid] = largest;
    for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid < stride) scratch[lid] = fmax(scratch[lid], scratch[lid + stride]);
    }
    if (lid == 0) groupMax[get_group_id(0)] = scratch[0];
}
