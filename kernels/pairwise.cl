/* The passes of a pairwise step (kernels/pairwise.h), one kernel each, for
 * both OpenCL pipelines; backends/opencl/pairwise.cpp enqueues them.
 *
 * A disk is its position k in sortedIndices (`ids`); `state[slots[k]]` is
 * its particle and `cellOf[slots[k]]` its cell: the host-grid pipeline stores the
 * particles by id (slots = ids), the resident one in the cell order of the
 * step before (slots = cellOrder).
 *
 * The lists' lengths live in `counts`, two per round (CAROM_PENDING_LENGTH,
 * CAROM_CHANGED_LENGTH), and the first search's dirty list's
 * (CAROM_FIRST_DIRTY_LENGTH). startPairwiseStep zeroes them once per step; the host reads them after it, or after a
 * chunk of steps. Every kernel of a step is given `halt` and does nothing
 * once a chunk has stopped (startPairwiseStep). A list kernel runs a fixed number
 * of work-items that stride over its list, whose length only the device
 * knows when the kernel is enqueued. The first rounds, whose lists are long,
 * run as launches of these kernels; the rest, whose lists are short, run in
 * one launch of resolveRoundsInGroup, which does the same passes in one
 * work-group with barriers between them (two launches a round cost more
 * than a round of a few hundred disks). */
#include "pairwise.h"

static inline CaromList carom_list(__global uint* items, __global uint* counts, uint countIndex, __global uint* marks)
{
    CaromList list;
    list.items = items;
    list.count = counts + countIndex;
    list.marks = marks;
    return list;
}

/* The start of a pairwise substep: zeroes the list lengths. In a chunk the
 * host enqueued without waiting (OpenClResidentBackend), it first checks
 * the state the substep starts from, unless `check` is 0: when a disk in it
 * is non-finite, or, at a step's first substep (check 2), when its largest
 * v.x^2 + v.y^2 (the float's bits in lengths[speedWord]) asks for another
 * count than the `substeps` the host planned (carom_substeps_needed under
 * `rule`), it records `stepIndex` in halt[0] instead, and the chunk's
 * kernels from here on do nothing. Every work-item decides alike. */
__kernel void startPairwiseStep(__global uint* halt,
                                __global uint* lengths,
                                uint lengthCount,
                                uint check,
                                CaromSubstepRule rule,
                                uint substeps,
                                uint speedWord,
                                uint nonFiniteIndex,
                                uint stepIndex)
{
    if (CAROM_HALTED(halt)) return;
    if (check != 0u && (lengths[nonFiniteIndex] != CAROM_ALL_FINITE ||
                        (check == 2u && carom_substeps_needed(as_float(lengths[speedWord]), rule) != substeps))) {
        if (get_global_id(0) == 0) halt[0] = stepIndex;
        return;
    }
    for (uint i = get_global_id(0); i < lengthCount; i += get_global_size(0)) lengths[i] = 0u;
}

/* Round 0, every disk: its earliest event over the pairs after it. */
__kernel void findEventsForward(__global const uint* halt,
                                __global const Particle* state,
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
    if (CAROM_HALTED(halt)) return;
    const uint k = get_global_id(0);
    if (k >= step.count) return;
    const CaromList none = carom_list(0, counts, 0, 0);
    carom_find_event(k, state, slots, ids, carom_grid_neighbours(cellOf, cells), step, events, CAROM_SEARCH_FORWARD,
                     none, carom_list(dirty, counts, CAROM_FIRST_DIRTY_LENGTH, dirtyMarks),
                     carom_list(pending, counts, CAROM_PENDING_LENGTH(0), pendingMarks), epoch);
}

/* Round r's search of the disks on `listed` (counts[listIndex] of them) in
 * `mode`: CAROM_SEARCH_ALL for the first search's dirty list,
 * CAROM_SEARCH_CHANGED for a round's changed one (which also searches the
 * dirty disks it finds). */
__kernel void searchListed(__global const uint* halt,
                           __global const Particle* state,
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
    if (CAROM_HALTED(halt)) return;
    const uint length = counts[listIndex];
    const CaromList changedList = carom_list(changed, counts, CAROM_CHANGED_LENGTH(round), changedMarks);
    const CaromList dirtyList = carom_list(dirty, counts, CAROM_FIRST_DIRTY_LENGTH, dirtyMarks);
    const CaromList pendingList = carom_list(pending, counts, CAROM_PENDING_LENGTH(round), pendingMarks);
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_find_event(listed[e], state, slots, ids, carom_grid_neighbours(cellOf, cells), step, events, mode,
                         changedList, dirtyList, pendingList, epoch);
}

/* Round r >= 1: resolves the events on round r - 1's pending list. */
__kernel void resolveEvents(__global const uint* halt,
                            __global Particle* state,
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
    if (CAROM_HALTED(halt)) return;
    const uint length = counts[CAROM_PENDING_LENGTH(round - 1)];
    const CaromList changedList = carom_list(changed, counts, CAROM_CHANGED_LENGTH(round), changedMarks);
    const CaromList nextList = carom_list(nextPending, counts, CAROM_PENDING_LENGTH(round), pendingMarks);
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_resolve_event(pending[e], state, slots, ids, events, step, tallies, changedList, nextList, epoch);
}

/* Runs pass(k) for the entries of a list whose length is lengths[index], by
 * the work-group, then waits for all of it. */
#define CAROM_FOR_LISTED(items, lengths, index, k, pass)                                             \
    do {                                                                                             \
        const uint carom_length = (lengths)[index];                                                  \
        for (uint carom_e = get_local_id(0); carom_e < carom_length; carom_e += get_local_size(0)) { \
            const uint k = (items)[carom_e];                                                         \
            pass;                                                                                    \
        }                                                                                            \
        barrier(CLK_GLOBAL_MEM_FENCE);                                                               \
    } while (0)

/* Rounds firstRound, firstRound + 1, ... of a step, by one work-group: those
 * of resolveEvents and searchListed, with barriers instead of launches, round
 * after round until none is pending or round maxRounds ran. Round r uses
 * epoch firstEpoch + (r - firstRound) and reads the pending list of round
 * r - 1 from pending0 for odd r and pending1 for even r, as the launches do;
 * the lengths of the rounds before are in `lengths`. */
static inline void carom_rounds_in_group(uint firstRound,
                                         uint maxRounds,
                                         uint firstEpoch,
                                         __global Particle* state,
                                         __global const uint* slots,
                                         __global const uint* ids,
                                         __global const uint* cellOf,
                                         __global const GridCell* cells,
                                         CaromStepParams step,
                                         __global ContactTally* tallies,
                                         __global CaromEvent* events,
                                         __global uint* pending0,
                                         __global uint* pending1,
                                         __global uint* changed,
                                         __global uint* dirty,
                                         __global uint* pendingMarks,
                                         __global uint* changedMarks,
                                         __global uint* dirtyMarks,
                                         __global uint* lengths)
{
    uint epoch = firstEpoch;
    for (uint round = firstRound; round <= maxRounds && lengths[CAROM_PENDING_LENGTH(round - 1)] != 0u;
         ++round, ++epoch) {
        __global const uint* resolving = round % 2 == 1 ? pending0 : pending1;
        const CaromList changedList = carom_list(changed, lengths, CAROM_CHANGED_LENGTH(round), changedMarks);
        const CaromList dirtyList = carom_list(dirty, lengths, CAROM_FIRST_DIRTY_LENGTH, dirtyMarks);
        const CaromList pendingList =
            carom_list(round % 2 == 1 ? pending1 : pending0, lengths, CAROM_PENDING_LENGTH(round), pendingMarks);
        CAROM_FOR_LISTED(
            resolving, lengths, CAROM_PENDING_LENGTH(round - 1), k,
            carom_resolve_event(k, state, slots, ids, events, step, tallies, changedList, pendingList, epoch));
        CAROM_FOR_LISTED(changed, lengths, CAROM_CHANGED_LENGTH(round), k,
                         carom_find_event(k, state, slots, ids, carom_grid_neighbours(cellOf, cells), step, events,
                                          CAROM_SEARCH_CHANGED, changedList, dirtyList, pendingList, epoch));
    }
}

/* Rounds firstRound .. maxRounds (those with events left) in one work-group:
 * carom_rounds_in_group, after the launches of the rounds before. */
__kernel void resolveRoundsInGroup(__global const uint* halt,
                                   __global Particle* state,
                                   __global const uint* slots,
                                   __global const uint* ids,
                                   __global const uint* cellOf,
                                   __global const GridCell* cells,
                                   CaromStepParams step,
                                   __global ContactTally* tallies,
                                   __global CaromEvent* events,
                                   __global uint* pending0,
                                   __global uint* pending1,
                                   __global uint* changed,
                                   __global uint* dirty,
                                   __global uint* pendingMarks,
                                   __global uint* changedMarks,
                                   __global uint* dirtyMarks,
                                   __global uint* lengths,
                                   uint firstRound,
                                   uint maxRounds,
                                   uint firstEpoch)
{
    if (CAROM_HALTED(halt)) return;
    carom_rounds_in_group(firstRound, maxRounds, firstEpoch, state, slots, ids, cellOf, cells, step, tallies, events,
                          pending0, pending1, changed, dirty, pendingMarks, changedMarks, dirtyMarks, lengths);
}
