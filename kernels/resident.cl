/* The step of the resident pipeline: resolveCollisions and integrate fused per
 * particle (as the CPU backend does: integrate only reads the particle that
 * resolveCollisions just produced, so this equals the two kernels bit for
 * bit), then the new position is counted into the next step's grid, which
 * saves reading the state again.
 *
 * Work-item k handles particle sortedIds[k], stored in slot cellOrder[k] of
 * `state` (kernels/grid.cl), and writes it to slot k of `next`: the new
 * state comes out in this step's cell order, which the next step starts
 * from. A disk left non-finite is recorded under
 * `stepIndex` (carom_record_non_finite). Small systems run whole steps in one
 * work-group (stepSmallSystem). */
#include "grid.cl"
#include "pairwise.h"

/* One particle's step: particle sortedIds[k], in slot cellOrder[k] of
 * `state`, resolved, integrated, written to slot k of `next` and counted
 * into the next grid's `counts`. */
static inline void carom_step_slot(uint k,
                                   __global const Particle* state,
                                   __global const uint* cellOrder,
                                   __global const uint* sortedIds,
                                   __global const GridCell* cells,
                                   CaromStepParams step,
                                   __global Particle* next,
                                   __global ContactTally* tallies,
                                   __global uint* counts,
                                   __global uint* cellOf,
                                   __global uint* rankInCell,
                                   uint stepIndex,
                                   __global uint* firstNonFinite)
{
    const uint i = sortedIds[k];
    const Particle self = state[cellOrder[k]];
    const CaromResponse sum =
        carom_collect_response_from(i, self, state, sortedIds, cellOrder, cells, step.grid, step.box);
    float wallImpulse[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const Particle moved = carom_integrate(carom_apply_response(self, sum), step.duration, step.gravityX, step.gravityY,
                                           step.box, wallImpulse);
    next[k] = moved;
    /* The tallies stay in id order, so reading them needs no slot map. */
    carom_record_collisions(&tallies[i], sum);
    carom_record_walls(&tallies[i], wallImpulse);
    carom_count_into_cell(k, moved.position, step.grid, counts, cellOf, rankInCell);
    carom_record_non_finite(moved, i, stepIndex, firstNonFinite);
}

__kernel void resolveIntegrateAndCount(__global const Particle* state,
                                       __global const uint* cellOrder,
                                       __global const uint* sortedIds,
                                       __global const GridCell* cells,
                                       CaromStepParams step,
                                       __global Particle* next,
                                       __global ContactTally* tallies,
                                       __global uint* nextCounts,
                                       __global uint* cellOf,
                                       __global uint* rankInCell,
                                       uint stepIndex,
                                       __global uint* firstNonFinite)
{
    const uint k = get_global_id(0);
    if (k >= step.count) return;
    carom_step_slot(k, state, cellOrder, sortedIds, cells, step, next, tallies, nextCounts, cellOf, rankInCell,
                    stepIndex, firstNonFinite);
}

/* `steps` simultaneous steps of a small system in one launch of one
 * work-group: the grid build of kernels/grid.cl and the step above, with
 * barriers between their passes instead of kernel launches (at a few
 * thousand disks a launch costs more than its work). The same passes on the
 * same data as the launches, so the same bits. On entry `counts`, `cellOf`
 * and `rankInCell` hold the counts of `state` (whose slot s holds particle
 * ids[s]); on return, those of the last step's state, which is in `next`
 * and `sortedIds` when `steps` is odd. Step s records a disk left non-finite
 * under firstStepIndex + s. The local size must be a power of two; `tile`
 * and `runSums` as for scanCountsIntoCells, with CAROM_SMALL_SYSTEM_SCAN_ITEMS
 * values per work-item. */
#define CAROM_SMALL_SYSTEM_SCAN_ITEMS 4
__kernel void stepSmallSystem(__global Particle* state,
                              __global Particle* next,
                              __global uint* ids,
                              __global uint* sortedIds,
                              __global GridCell* cells,
                              __global uint* counts,
                              __global uint* cellOrder,
                              __global uint* cellOf,
                              __global uint* rankInCell,
                              CaromStepParams step,
                              uint steps,
                              __global ContactTally* tallies,
                              uint firstStepIndex,
                              __global uint* firstNonFinite,
                              __local uint* tile,
                              __local uint* runSums)
{
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    const uint tileLength = size * CAROM_SMALL_SYSTEM_SCAN_ITEMS;
    const uint cellCount = (uint)(step.grid.cols * step.grid.rows);
    for (uint s = 0; s < steps; ++s) {
        uint before = 0; /* the particles in the tiles scanned so far */
        for (uint first = 0; first < cellCount; first += tileLength) {
            const uint total = carom_scan_tile(counts, cellCount, first, CAROM_SMALL_SYSTEM_SCAN_ITEMS, tile, runSums);
            for (uint k = lid; k < tileLength && first + k < cellCount; k += size) {
                GridCell cell;
                cell.start = before + tile[carom_padded(k)];
                cell.count = counts[first + k];
                cells[first + k] = cell;
            }
            before += total;
            barrier(CLK_LOCAL_MEM_FENCE); /* the next tile overwrites this one */
        }
        barrier(CLK_GLOBAL_MEM_FENCE);
        for (uint slot = lid; slot < step.count; slot += size)
            carom_scatter_slot(slot, cells[cellOf[slot]].start, rankInCell, ids, cellOrder, sortedIds);
        barrier(CLK_GLOBAL_MEM_FENCE);
        for (uint c = lid; c < cellCount; c += size) {
            counts[c] = 0u;
            carom_sort_cell(cells[c], cellOrder, sortedIds);
        }
        barrier(CLK_GLOBAL_MEM_FENCE);
        for (uint k = lid; k < step.count; k += size)
            carom_step_slot(k, state, cellOrder, sortedIds, cells, step, next, tallies, counts, cellOf, rankInCell,
                            firstStepIndex + s, firstNonFinite);
        barrier(CLK_GLOBAL_MEM_FENCE);
        __global Particle* const stepped = next;
        next = state;
        state = stepped;
        __global uint* const steppedIds = sortedIds;
        sortedIds = ids;
        ids = steppedIds;
    }
}

/* The end of a pairwise step (its rounds: kernels/pairwise.cl), if its
 * rounds are done: lengths[condition] is 0 (backends/opencl_pairwise.h;
 * otherwise the host enqueues more rounds and this kernel again). For each
 * k, particle sortedIds[k] is finished from slot cellOrder[k] of `state`
 * into slot k of `next` and counted into the next step's grid. The kernel
 * also takes the largest v.x^2 + v.y^2 of the new state, which sizes the
 * next step's substeps, so that needs no pass of its own: each work-item
 * strides over the particles, the work-group (a power of two) reduces, and
 * atomic_max on the float's bits (non-negative floats order like their bits)
 * collects it in speedBits[parity]; the first work-item zeroes the other
 * word for the step after. max is exact in any order: this equals the
 * maxSpeedSquared reduction bit for bit. A disk left non-finite is recorded
 * under `stepIndex` in lengths[nonFiniteIndex..+1] (carom_record_non_finite),
 * which the host reads back with the list lengths. */
__kernel void finishPairwiseAndCount(__global const Particle* state,
                                     __global const uint* cellOrder,
                                     __global const uint* sortedIds,
                                     CaromStepParams step,
                                     __global Particle* next,
                                     __global ContactTally* tallies,
                                     __global uint* nextCounts,
                                     __global uint* cellOf,
                                     __global uint* rankInCell,
                                     __local float* scratch,
                                     __global uint* speedBits,
                                     uint parity,
                                     __global uint* lengths,
                                     uint condition,
                                     uint stepIndex,
                                     uint nonFiniteIndex)
{
    if (lengths[condition] != 0u) return; /* the same for every work-item */
    float largest = 0.0f;
    for (uint k = get_global_id(0); k < step.count; k += get_global_size(0)) {
        const Particle moved = carom_finish_step(state[cellOrder[k]], step, &tallies[sortedIds[k]]);
        next[k] = moved;
        carom_count_into_cell(k, moved.position, step.grid, nextCounts, cellOf, rankInCell);
        carom_record_non_finite(moved, sortedIds[k], stepIndex, lengths + nonFiniteIndex);
        largest = fmax(largest, carom_speed_squared(moved));
    }
    if (get_global_id(0) == 0) speedBits[1 - parity] = 0u;
    const uint lid = get_local_id(0);
    scratch[lid] = largest;
    for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid < stride) scratch[lid] = fmax(scratch[lid], scratch[lid + stride]);
    }
    if (lid == 0) atomic_max(&speedBits[parity], as_uint(scratch[0]));
}
