/* The host-grid pipeline's kernels (backends/opencl/host_grid.cpp), one
 * work-item per particle, the particles stored by id: the simultaneous step
 * (the impulses from the state before the step, then the integration) and
 * the end of a pairwise step, after pairwise.cl's rounds. The physics itself
 * lives in physics.h and pairwise.h, which the CPU backend compiles too. */
#include "pairwise.h"

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

/* The end of a pairwise step, every disk flying on to it, in place.
 * A disk left non-finite is recorded under `stepIndex` (carom_record_non_finite). */
__kernel void finishStepById(__global Particle* state,
                             CaromStepParams step,
                             __global ContactTally* tallies,
                             uint stepIndex,
                             __global uint* firstNonFinite)
{
    const uint i = get_global_id(0);
    if (i >= step.count) return;
    state[i] = carom_finish_step(state[i], step, &tallies[i]);
    carom_record_non_finite(state[i], i, stepIndex, firstNonFinite);
}
