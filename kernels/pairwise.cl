/* The passes of a pairwise step (kernels/pairwise.h), one kernel each, for
 * both OpenCL pipelines; backends/opencl_pairwise.cpp enqueues them.
 *
 * A disk is its position k in sortedIndices (`ids`); `state[slots[k]]` is
 * its particle and `cellOf[slots[k]]` its cell: the seed pipeline stores the
 * particles by id (slots = ids), the resident one in the cell order of the
 * step before (slots = cellOrder).
 *
 * The lists' lengths live in `counts`, three per round r (0 = the first
 * search): counts[3r] the pending list built in round r, counts[3r + 1] the
 * disks changed in it, counts[3r + 2] the dirty ones. The host zeroes them
 * once per step, and reads them to see when no event is left. A list kernel
 * runs a fixed number of work-items that stride over its list, whose length
 * only the device knows when the kernel is enqueued. */
#include "pairwise.h"

static inline CaromList carom_list(__global uint* items, __global uint* counts, uint countIndex, __global uint* marks)
{
    CaromList list;
    list.items = items;
    list.count = counts + countIndex;
    list.marks = marks;
    return list;
}

/* Round 0, every disk: its earliest event over the pairs after it. */
__kernel void findEventsForward(__global const Particle* state,
                                __global const uint* slots,
                                __global const uint* ids,
                                __global const uint* cellOf,
                                __global const GridCell* cells,
                                CaromStepParams step,
                                __global CaromEvent* events,
                                __global uint* pending,
                                __global uint* pendingMarks,
                                __global uint* dirty,
                                __global uint* dirtyMarks,
                                __global uint* counts,
                                uint epoch)
{
    const uint k = get_global_id(0);
    if (k >= step.count) return;
    const CaromList none = carom_list(0, counts, 0, 0);
    carom_find_event(k, state, slots, ids, cellOf, cells, step, events, CAROM_SEARCH_FORWARD, none,
                     carom_list(dirty, counts, 2, dirtyMarks), carom_list(pending, counts, 0, pendingMarks), epoch);
}

/* Round r's search of the disks on `listed` (counts[listIndex] of them) in
 * `mode`: CAROM_SEARCH_ALL for the dirty list, CAROM_SEARCH_CHANGED for the
 * changed one (which adds to the dirty list). */
__kernel void searchListed(__global const Particle* state,
                           __global const uint* slots,
                           __global const uint* ids,
                           __global const uint* cellOf,
                           __global const GridCell* cells,
                           CaromStepParams step,
                           __global CaromEvent* events,
                           int mode,
                           __global const uint* listed,
                           __global uint* changed,
                           __global uint* changedMarks,
                           __global uint* dirty,
                           __global uint* dirtyMarks,
                           __global uint* pending,
                           __global uint* pendingMarks,
                           __global uint* counts,
                           uint round,
                           uint listIndex,
                           uint epoch)
{
    const uint length = counts[listIndex];
    const CaromList changedList = carom_list(changed, counts, 3 * round + 1, changedMarks);
    const CaromList dirtyList = carom_list(dirty, counts, 3 * round + 2, dirtyMarks);
    const CaromList pendingList = carom_list(pending, counts, 3 * round, pendingMarks);
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_find_event(listed[e], state, slots, ids, cellOf, cells, step, events, mode, changedList, dirtyList,
                         pendingList, epoch);
}

/* Round r >= 1: resolves the events on round r - 1's pending list. */
__kernel void resolveEvents(__global Particle* state,
                            __global const uint* slots,
                            __global const uint* ids,
                            __global const CaromEvent* events,
                            CaromStepParams step,
                            __global ContactTally* tallies,
                            __global const uint* pending,
                            __global uint* nextPending,
                            __global uint* pendingMarks,
                            __global uint* changed,
                            __global uint* changedMarks,
                            __global uint* counts,
                            uint round,
                            uint epoch)
{
    const uint length = counts[3 * (round - 1)];
    const CaromList changedList = carom_list(changed, counts, 3 * round + 1, changedMarks);
    const CaromList nextList = carom_list(nextPending, counts, 3 * round, pendingMarks);
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_resolve_event(pending[e], state, slots, ids, events, step, tallies, changedList, nextList, epoch);
}

/* The end of the step, particles stored by id (seed pipeline): in place.
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
