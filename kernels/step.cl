/* The two kernels of one step, one work-item per particle. The physics itself
 * lives in physics.h, which the CPU backend compiles too. */
#include "physics.h"

__kernel void resolveCollisions(__global const Particle* in,
                                __global const uint* sortedIndices,
                                __global const GridCell* cells,
                                float cellsPerLengthX,
                                float cellsPerLengthY,
                                int cols,
                                int rows,
                                uint count,
                                __global Particle* out,
                                __global uint* collisionCounts)
{
    const uint i = get_global_id(0);
    if (i >= count) return;
    GridGeometry grid;
    grid.cellsPerLengthX = cellsPerLengthX;
    grid.cellsPerLengthY = cellsPerLengthY;
    grid.cols = cols;
    grid.rows = rows;
    carom_resolve_collisions(i, in, sortedIndices, cells, grid, out, collisionCounts);
}

__kernel void integrate(__global Particle* particles,
                        uint count,
                        float dt,
                        float gravityX,
                        float gravityY,
                        float width,
                        float height)
{
    const uint i = get_global_id(0);
    if (i >= count) return;
    particles[i] = carom_integrate(particles[i], dt, gravityX, gravityY, width, height);
}
