/* What the host reads of the state without reading it whole
 * (backends/opencl/view.cpp): what the viewer draws of every disk and its
 * readouts' sums (World::readView), so that a frame reads back 16 bytes a
 * disk, and the largest speed, which sizes substeps. */
#include "physics.h"

/* a + b in float-float (high, low): Knuth's two-sum, renormalised. Additions
 * only, so no contraction into fma can change it. */
float2 carom_float_float_add(float2 a, float2 b)
{
    const float sum = a.x + b.x;
    const float bPart = sum - a.x;
    const float error = (a.x - (sum - bPart)) + (b.x - bPart);
    const float low = error + a.y + b.y;
    const float high = sum + low;
    return (float2)(high, low - (high - sum));
}

/* views[s] = (position, radius, value) of the disk in slot s, whose id is
 * ids[s] (s itself where ids is null: the state in id order). Each work-item
 * takes every (global size)-th slot; each work-group then halves its sums in
 * local memory (scratch: 2 floats per work-item) and writes CAROM_VIEW_SUM_COUNT
 * floats to groupSums. The local size must be a power of two. */
__kernel void writeDiskViews(__global const Particle* state,
                             __global const uint* ids,
                             uint count,
                             uint valueKind,
                             float2 gravity,
                             __global float4* views,
                             __global float* groupSums,
                             __local float2* scratch)
{
    float2 sums[CAROM_VIEW_SUM_PAIRS];
    for (int q = 0; q < CAROM_VIEW_SUM_PAIRS; ++q) sums[q] = (float2)(0.0f, 0.0f);
    float lowest = INFINITY, highest = -INFINITY;
    for (uint s = get_global_id(0); s < count; s += get_global_size(0)) {
        const Particle p = state[s];
        const float speedSquared = dot(p.velocity, p.velocity);
        float value = p.radius;
        if (valueKind == CAROM_VIEW_VALUE_SPEED)
            value = sqrt(speedSquared);
        else if (valueKind == CAROM_VIEW_VALUE_MASS)
            value = p.mass;
        else if (valueKind == CAROM_VIEW_VALUE_ID)
            value = (float)(ids ? ids[s] : s);
        views[s] = (float4)(p.position, p.radius, value);
        const float terms[CAROM_VIEW_SUM_PAIRS] = {0.5f * p.mass * speedSquared,
                                                   -p.mass * dot(gravity, p.position),
                                                   p.mass * p.velocity.x,
                                                   p.mass * p.velocity.y,
                                                   p.mass,
                                                   speedSquared};
        for (int q = 0; q < CAROM_VIEW_SUM_PAIRS; ++q)
            sums[q] = carom_float_float_add(sums[q], (float2)(terms[q], 0.0f));
        lowest = fmin(lowest, value);
        highest = fmax(highest, value);
    }
    const uint lid = get_local_id(0);
    __global float* out = groupSums + get_group_id(0) * CAROM_VIEW_SUM_COUNT;
    for (int q = 0; q <= CAROM_VIEW_SUM_PAIRS; ++q) {
        /* q < CAROM_VIEW_SUM_PAIRS: a sum; the last round the extremes, as a pair. */
        scratch[lid] = q < CAROM_VIEW_SUM_PAIRS ? sums[q] : (float2)(lowest, highest);
        for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
            barrier(CLK_LOCAL_MEM_FENCE);
            if (lid < stride) {
                const float2 a = scratch[lid], b = scratch[lid + stride];
                scratch[lid] =
                    q < CAROM_VIEW_SUM_PAIRS ? carom_float_float_add(a, b) : (float2)(fmin(a.x, b.x), fmax(a.y, b.y));
            }
        }
        if (lid == 0) {
            out[2 * q] = scratch[0].x;
            out[2 * q + 1] = scratch[0].y;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
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
