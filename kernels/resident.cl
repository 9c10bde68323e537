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
 * work-group instead (kernels/small_system.cl). */
#include "grid.cl"
#include "pairwise.h"

/* ids[s] = s: slot s holds particle s, as a load leaves the state. */
__kernel void numberSlots(__global uint* ids, uint count)
{
    const uint s = get_global_id(0);
    if (s < count) ids[s] = s;
}

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
    int image[2] = {0, 0};
    const Particle moved = carom_integrate(carom_apply_response(self, sum), step.duration, step.gravityX, step.gravityY,
                                           step.box, wallImpulse, image);
    next[k] = moved;
    /* The tallies stay in id order, so reading them needs no slot map. */
    carom_record_collisions(&tallies[i], sum);
    carom_record_walls(&tallies[i], wallImpulse);
    carom_record_image(&tallies[i], image);
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

/* One particle's end of a pairwise step: particle sortedIds[k] finished
 * from slot carom_slot(cellOrder, k) of `state` into slot k of `next` and
 * counted into the next grid's `counts`; returns its v.x^2 + v.y^2. Where
 * `origins` is not null (neighbour lists), `displacementSquared` becomes at
 * least the squared distance it moved from origins[k] (to the nearest image
 * in a periodic box). */
static inline float carom_finish_slot(uint k,
                                      __global const Particle* state,
                                      __global const uint* cellOrder,
                                      __global const uint* sortedIds,
                                      CaromStepParams step,
                                      __global Particle* next,
                                      __global ContactTally* tallies,
                                      __global uint* counts,
                                      __global uint* cellOf,
                                      __global uint* rankInCell,
                                      uint stepIndex,
                                      __global uint* firstNonFinite,
                                      __global const float2* origins,
                                      float* displacementSquared)
{
    const Particle moved = carom_finish_step(state[carom_slot(cellOrder, k)], step, &tallies[sortedIds[k]]);
    next[k] = moved;
    carom_count_into_cell(k, moved.position, step.grid, counts, cellOf, rankInCell);
    carom_record_non_finite(moved, sortedIds[k], stepIndex, firstNonFinite);
    if (origins)
        *displacementSquared =
            fmax(*displacementSquared, carom_displacement_squared(moved.position, origins[k], step.box));
    return carom_speed_squared(moved);
}

/* The largest of the work-group's values (the local size a power of two;
 * `scratch` one float per work-item), for every work-item. */
static inline float carom_group_max(float value, __local float* scratch)
{
    const uint lid = get_local_id(0);
    scratch[lid] = value;
    for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid < stride) scratch[lid] = fmax(scratch[lid], scratch[lid + stride]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    const float largest = scratch[0];
    barrier(CLK_LOCAL_MEM_FENCE); /* scratch may be reused */
    return largest;
}

/* The end of a pairwise step, after its rounds (kernels/pairwise.cl): for
 * each k, particle sortedIds[k] is finished from slot
 * carom_slot(cellOrder, k) of `state` into slot k of `next` (in place where
 * the state was gathered into sorted order, sortCellSegments: `state` is
 * `next` and cellOrder null) and counted into the next step's grid. The
 * kernel also takes the largest v.x^2 + v.y^2 of the new state, which sizes
 * the next step's substeps, so that needs no pass of its own: each work-item
 * strides over the particles, the work-group (a power of two) reduces, and
 * atomic_max on the float's bits (non-negative floats order like their bits)
 * collects it in lengths[speedIndex + parity]; the first work-item zeroes the
 * other word for the step after. max is exact in any order: this equals the
 * maxSpeedSquared reduction bit for bit. A disk left non-finite is recorded
 * under `stepIndex` in lengths[nonFiniteIndex..+1] (carom_record_non_finite),
 * and the rounds this step used, at most, in lengths[roundsIndex]. The host
 * reads them back with the list lengths, in one read. With neighbour lists
 * (neighbourWords not null) the largest displacement since their build is
 * taken alike, into CAROM_LISTS_DISPLACEMENT(parity). */
__kernel void finishPairwiseAndCount(__global const uint* halt,
                                     __global const Particle* state,
                                     __global const uint* cellOrder,
                                     __global const uint* sortedIds,
                                     CaromStepParams step,
                                     __global Particle* next,
                                     __global ContactTally* tallies,
                                     __global uint* nextCounts,
                                     __global uint* cellOf,
                                     __global uint* rankInCell,
                                     __global uint* lengths,
                                     uint speedIndex,
                                     uint parity,
                                     uint stepIndex,
                                     uint nonFiniteIndex,
                                     uint roundsIndex,
                                     __global uint* neighbourWords,
                                     __local float* scratch)
{
    if (CAROM_HALTED(halt)) return;
    __global uint* speedWords = lengths + speedIndex;
    __global const float2* origins = neighbourWords ? carom_list_origins(neighbourWords, step.count) : 0;
    /* The last round that changed a disk, a round a work-item (a loop of
     * global loads on one would set the kernel's pace at small N); the
     * lengths end where the record starts. */
    for (uint r = get_global_id(0) + 1u; CAROM_CHANGED_LENGTH(r) < nonFiniteIndex; r += get_global_size(0))
        if (lengths[CAROM_CHANGED_LENGTH(r)] > 0u) atomic_max(&lengths[roundsIndex], r);
    float largest = 0.0f, farthest = 0.0f;
    for (uint k = get_global_id(0); k < step.count; k += get_global_size(0))
        largest =
            fmax(largest, carom_finish_slot(k, state, cellOrder, sortedIds, step, next, tallies, nextCounts, cellOf,
                                            rankInCell, stepIndex, lengths + nonFiniteIndex, origins, &farthest));
    if (get_global_id(0) == 0) {
        speedWords[1 - parity] = 0u;
        lengths[CAROM_LISTS_DISPLACEMENT(1 - parity)] = 0u;
    }
    const float groupLargest = carom_group_max(largest, scratch);
    if (get_local_id(0) == 0) atomic_max(&speedWords[parity], as_uint(groupLargest));
    if (!origins) return;
    const float groupFarthest = carom_group_max(farthest, scratch);
    if (get_local_id(0) == 0) atomic_max(&lengths[CAROM_LISTS_DISPLACEMENT(parity)], as_uint(groupFarthest));
}
