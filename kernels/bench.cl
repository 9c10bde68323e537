/* The program of `carom bench` (embedded into the carom_bench library only):
 * the all-pairs baseline, with host_grid.cl's integrate and view.cl's kernels
 * (every OpenClBackend launches them), and the copy that measures the
 * device's memory bandwidth. */
#include "host_grid.cl"
#include "view.cl"

/* resolveCollisions against every other particle, O(N^2); integrate follows
 * as in the host-grid pipeline. */
__kernel void resolveAllPairs(__global const Particle* in,
                              CaromStepParams step,
                              __global Particle* out,
                              __global ContactTally* tallies)
{
    const uint i = get_global_id(0);
    if (i >= step.count) return;
    const Particle self = in[i];
    const CaromResponse sum = carom_collect_response_all_pairs(i, self, in, step.count, step.box);
    out[i] = carom_apply_response(self, sum);
    carom_record_collisions(&tallies[i], sum);
}

__kernel void copyFloat4(__global const float4* from, __global float4* to, uint count)
{
    const uint i = get_global_id(0);
    if (i < count) to[i] = from[i];
}
