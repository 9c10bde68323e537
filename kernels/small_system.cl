/* Whole steps of a small system in one work-group, for the resident
 * pipeline (backends/opencl/small_system.cpp): at a few thousand disks
 * the launches of a step (the grid build's, the step's, the pairwise
 * rounds') cost more than the work, and one work-group does it all, with
 * barriers between the passes instead of launches. The passes are those of
 * kernels/grid.cl, resident.cl and pairwise.cl, through the same functions
 * on the same data, so the results are the same bits.
 *
 * The local size must be a power of two; `tile` and `runSums` are those of
 * carom_scan_tile, with CAROM_SMALL_SYSTEM_SCAN_ITEMS values per work-item:
 * a small tile, so that the work-group can be large (the host sizes them:
 * kSmallSystemScanItems). It uses the functions of resident.cl and
 * pairwise.cl, which program.cl puts before it. */

#define CAROM_SMALL_SYSTEM_SCAN_ITEMS 4

/* The grid of the state, by the work-group: on entry `counts`, `cellOf` and
 * `rankInCell` hold its per-cell counts and each slot's cell and arrival
 * rank; on return `cells` hold the cells, `cellOrder` and `sortedIds` the
 * slots and ids in cell order, ascending id within a cell, and `nextCounts`
 * is zeroed (it may be `counts`). */
static inline void carom_build_grid_in_group(uint count,
                                             uint cellCount,
                                             __global const uint* counts,
                                             __global GridCell* cells,
                                             __global const uint* cellOf,
                                             __global const uint* rankInCell,
                                             __global const uint* ids,
                                             __global uint* cellOrder,
                                             __global uint* sortedIds,
                                             __global uint* nextCounts,
                                             __local uint* tile,
                                             __local uint* runSums)
{
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    const uint tileLength = size * CAROM_SMALL_SYSTEM_SCAN_ITEMS;
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
    for (uint slot = lid; slot < count; slot += size)
        carom_scatter_slot(slot, cells[cellOf[slot]].start, rankInCell, ids, cellOrder, sortedIds);
    barrier(CLK_GLOBAL_MEM_FENCE);
    for (uint c = lid; c < cellCount; c += size) {
        nextCounts[c] = 0u;
        carom_sort_cell(cells[c], cellOrder, sortedIds);
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
}

/* `steps` simultaneous steps: the grid build and resolveIntegrateAndCount's
 * step, each step counting its state into `counts` in place. On entry
 * `counts`, `cellOf` and `rankInCell` hold the counts of `state` (whose slot
 * s holds particle ids[s]); on return, those of the last step's state, which
 * is in `next` and `sortedIds` when `steps` is odd. Step s records a disk
 * left non-finite under firstStepIndex + s. */
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
    const uint cellCount = (uint)(step.grid.cols * step.grid.rows);
    for (uint s = 0; s < steps; ++s) {
        carom_build_grid_in_group(step.count, cellCount, counts, cells, cellOf, rankInCell, ids, cellOrder, sortedIds,
                                  counts, tile, runSums);
        for (uint k = get_local_id(0); k < step.count; k += get_local_size(0))
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

/* Pairwise substeps, up to `substeps` of them, `substepsPerStep` to a step:
 * each the grid build, findEvents's pass (backends/opencl/pairwise.cpp),
 * the rounds until none is
 * pending or `maxRounds` ran (carom_rounds_in_group), then
 * finishPairwiseAndCount's. A step after the first starts only if its state
 * needs substepsPerStep substeps too (carom_substeps_needed under `rule`,
 * from the largest speed of the substep before) and no disk is non-finite:
 * the host planned the count from the first step's state, and a run that
 * stops early equals stepping one step at a time. The list lengths are
 * zeroed each substep (the first lengthCount words of the lists' buffer,
 * `words`: CaromDeviceLists); substep s uses epochs firstEpoch + s
 * (maxRounds + 1) on, as the host's launches would. Each
 * substep gathers its state into `next` in sorted order, where its rounds
 * and its finish run, and leaves it there (slot k: particle sortedIds[k]),
 * counted into `nextCounts`, and the three pairs of buffers swap roles for
 * the next: after an odd number of substeps the result is in `next`,
 * `sortedIds` and `nextCounts`. The record words after the lengths: a disk left
 * non-finite, under firstStepIndex + s, at nonFiniteIndex..+1; the last
 * state's largest v.x^2 + v.y^2 at speedIndex + parity (the other word
 * zeroed); the substeps taken and the most rounds one of them used at
 * takenIndex..+1. */
__kernel void stepSmallPairwise(__global Particle* state,
                                __global Particle* next,
                                __global uint* ids,
                                __global uint* sortedIds,
                                __global GridCell* cells,
                                __global uint* counts,
                                __global uint* nextCounts,
                                __global uint* cellOrder,
                                __global uint* cellOf,
                                __global uint* rankInCell,
                                CaromStepParams step,
                                __global ContactTally* tallies,
                                __global uint* words,
                                uint lengthCount,
                                uint firstEpoch,
                                uint maxRounds,
                                uint substeps,
                                uint substepsPerStep,
                                CaromSubstepRule rule,
                                uint firstStepIndex,
                                uint nonFiniteIndex,
                                uint speedIndex,
                                uint parity,
                                uint takenIndex,
                                __local uint* tile,
                                __local uint* runSums,
                                __local float* scratch)
{
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    const uint cellCount = (uint)(step.grid.cols * step.grid.rows);
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    __global uint* const lengths = l.lengths;
    float largest = 0.0f;
    uint mostRounds = 0;
    uint s = 0;
    for (; s < substeps; ++s) {
        if (s > 0 && lengths[nonFiniteIndex] != CAROM_ALL_FINITE) break;
        if (s > 0 && s % substepsPerStep == 0 && carom_substeps_needed(largest, rule) != substepsPerStep) break;
        carom_build_grid_in_group(step.count, cellCount, counts, cells, cellOf, rankInCell, ids, cellOrder, sortedIds,
                                  nextCounts, tile, runSums);
        /* The state gathered into sorted order in `next`, and each disk's
         * cell by sorted position in cellAt (rankInCell, unused until the
         * finish counts into it): the searches then look up no slots
         * (carom_slot), as in the launches (sortCellSegments). */
        __global uint* const cellAt = rankInCell;
        for (uint k = lid; k < step.count; k += size) {
            const uint slot = cellOrder[k];
            next[k] = state[slot];
            cellAt[k] = cellOf[slot];
        }
        for (uint i = lid; i < lengthCount; i += size) lengths[i] = 0u;
        barrier(CLK_GLOBAL_MEM_FENCE);

        /* Round 0: every disk over all its neighbours (findEvents). */
        const uint epoch = firstEpoch + s * (maxRounds + 1);
        const CaromList none = carom_list(0, lengths, 0, 0);
        const CaromList pendingList = carom_list(l.pending0, lengths, CAROM_PENDING_LENGTH(0), l.pendingMarks);
        const CaromNeighbours neighbours = carom_grid_neighbours(cellAt, cells);
        for (uint k = lid; k < step.count; k += size)
            carom_find_event(k, next, 0, sortedIds, neighbours, step, l.events, CAROM_SEARCH_ALL, none, none,
                             pendingList, epoch);
        barrier(CLK_GLOBAL_MEM_FENCE);

        carom_rounds_in_group(1, maxRounds, epoch + 1, next, 0, sortedIds, neighbours, step, tallies, l);
        for (uint r = 1; r <= maxRounds; ++r)
            if (lengths[CAROM_CHANGED_LENGTH(r)] > 0u) mostRounds = max(mostRounds, r);

        /* The finish, in place; then cellOf and rankInCell are by slot again. */
        float own = 0.0f;
        for (uint k = lid; k < step.count; k += size)
            own = fmax(own, carom_finish_slot(k, next, 0, sortedIds, step, next, tallies, nextCounts, cellOf,
                                              rankInCell, firstStepIndex + s, lengths + nonFiniteIndex, 0, 0));
        largest = carom_group_max(own, scratch);
        barrier(CLK_GLOBAL_MEM_FENCE);
        __global Particle* const stepped = next;
        next = state;
        state = stepped;
        __global uint* const steppedIds = sortedIds;
        sortedIds = ids;
        ids = steppedIds;
        __global uint* const steppedCounts = nextCounts;
        nextCounts = counts;
        counts = steppedCounts;
    }
    if (lid == 0) {
        lengths[speedIndex + parity] = as_uint(largest);
        lengths[speedIndex + 1 - parity] = 0u;
        lengths[takenIndex] = s;
        lengths[takenIndex + 1] = mostRounds;
    }
}
