/* The host-grid pipeline's simultaneous step (backends/opencl/host_grid.cpp),
 * one work-item per particle: the impulses from the state before the step,
 * then the integration. The physics itself lives in physics.h, which the CPU
 * backend compiles too. */
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
