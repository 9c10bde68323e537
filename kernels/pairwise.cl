/* The passes of a pairwise step (kernels/pairwise.h), one kernel each, for
 * both OpenCL pipelines; backends/opencl/pairwise.cpp enqueues them.
 *
 * A disk is its position k in sortedIndices (`ids`); `state[slots[k]]` is
 * its particle and `cellOf[slots[k]]` its cell: the host-grid pipeline stores the
 * particles by id (slots = ids), the resident one in the cell order of the
 * step before (slots = cellOrder) or, up to 2^18 disks, in the step's own
 * sorted order, gathered as its grid was built (slots null: carom_slot).
 *
 * A step's lists live in one buffer (CaromDeviceLists), whose first words
 * hold their lengths, two per round (CAROM_PENDING_LENGTH,
 * CAROM_CHANGED_LENGTH). startPairwiseStep zeroes them once per step; the
 * host reads them after it, or after a chunk of steps. Every kernel of a
 * step is given `halt` and does nothing
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

/* A step's lists, in the one buffer `words` (each buffer argument adds about
 * a quarter of a microsecond of the host's time to a launch on NVIDIA's
 * OpenCL): the lengths and the record (CAROM_LIST_HEADER_WORDS), then for n
 * disks the events, two words each, and n words each for the two pending
 * lists, the changed list, and the pending, changed and dirty marks. */
typedef struct CaromDeviceLists {
    __global uint* lengths;
    __global CaromEvent* events;
    __global uint* pending0;
    __global uint* pending1;
    __global uint* changed;
    __global uint* pendingMarks;
    __global uint* changedMarks;
    __global uint* dirtyMarks;
} CaromDeviceLists;

static inline CaromDeviceLists carom_device_lists(__global uint* words, uint n)
{
    CaromDeviceLists l;
    l.lengths = words;
    __global uint* const lists = words + CAROM_LIST_HEADER_WORDS;
    l.events = (__global CaromEvent*)lists;
    l.pending0 = lists + 2ul * n;
    l.pending1 = lists + 3ul * n;
    l.changed = lists + 4ul * n;
    l.pendingMarks = lists + 5ul * n;
    l.changedMarks = lists + 6ul * n;
    l.dirtyMarks = lists + 7ul * n;
    return l;
}

/* The pending list that round r fills (round r + 1 resolves it). */
static inline __global uint* carom_pending_of(CaromDeviceLists l, uint round)
{
    return round % 2 == 0 ? l.pending0 : l.pending1;
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

/* Round 0, every disk: its earliest event over all its neighbours. (The
 * CPU backend searches forward over each pair once, then all for the disks
 * met from behind: the same events, in a pass fewer here, where a pass is a
 * launch.) */
__kernel void findEvents(__global const uint* halt,
                         __global const Particle* state,
                         __global const uint* slots,
                         __global const uint* ids,
                         __global const uint* cellOf,
                         __global const GridCell* cells,
                         CaromStepParams step,
                         __global uint* words,
                         uint epoch)
{
    if (CAROM_HALTED(halt)) return;
    const uint k = get_global_id(0);
    if (k >= step.count) return;
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    const CaromList none = carom_list(0, l.lengths, 0, 0);
    carom_find_event(k, state, slots, ids, carom_grid_neighbours(cellOf, cells), step, l.events, CAROM_SEARCH_ALL, none,
                     none, carom_list(l.pending0, l.lengths, CAROM_PENDING_LENGTH(0), l.pendingMarks), epoch);
}

/* Round r's search of the disks it changed, which also searches the dirty
 * disks they find. */
static inline void carom_search_changed(uint e,
                                        __global const Particle* state,
                                        __global const uint* slots,
                                        __global const uint* ids,
                                        __global const uint* cellOf,
                                        __global const GridCell* cells,
                                        CaromStepParams step,
                                        CaromDeviceLists l,
                                        uint round,
                                        uint epoch)
{
    carom_find_event(
        l.changed[e], state, slots, ids, carom_grid_neighbours(cellOf, cells), step, l.events, CAROM_SEARCH_CHANGED,
        carom_list(l.changed, l.lengths, CAROM_CHANGED_LENGTH(round), l.changedMarks),
        carom_list(0, 0, 0, l.dirtyMarks),
        carom_list(carom_pending_of(l, round), l.lengths, CAROM_PENDING_LENGTH(round), l.pendingMarks), epoch);
}

/* Round r's resolve of entry e of round r - 1's pending list. */
static inline void carom_resolve_pending(uint e,
                                         __global Particle* state,
                                         __global const uint* slots,
                                         __global const uint* ids,
                                         CaromStepParams step,
                                         __global ContactTally* tallies,
                                         CaromDeviceLists l,
                                         uint round,
                                         uint epoch)
{
    carom_resolve_event(carom_pending_of(l, round - 1)[e], state, slots, ids, l.events, step, tallies,
                        carom_list(l.changed, l.lengths, CAROM_CHANGED_LENGTH(round), l.changedMarks),
                        carom_list(carom_pending_of(l, round), l.lengths, CAROM_PENDING_LENGTH(round), l.pendingMarks),
                        epoch);
}

/* Round r's search of the disks it changed (carom_search_changed). */
__kernel void searchChanged(__global const uint* halt,
                            __global const Particle* state,
                            __global const uint* slots,
                            __global const uint* ids,
                            __global const uint* cellOf,
                            __global const GridCell* cells,
                            CaromStepParams step,
                            __global uint* words,
                            uint round,
                            uint epoch)
{
    if (CAROM_HALTED(halt)) return;
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    const uint length = l.lengths[CAROM_CHANGED_LENGTH(round)];
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_search_changed(e, state, slots, ids, cellOf, cells, step, l, round, epoch);
}

/* Round r >= 1: resolves the events on round r - 1's pending list. */
__kernel void resolveEvents(__global const uint* halt,
                            __global Particle* state,
                            __global const uint* slots,
                            __global const uint* ids,
                            CaromStepParams step,
                            __global ContactTally* tallies,
                            __global uint* words,
                            uint round,
                            uint epoch)
{
    if (CAROM_HALTED(halt)) return;
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    const uint length = l.lengths[CAROM_PENDING_LENGTH(round - 1)];
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_resolve_pending(e, state, slots, ids, step, tallies, l, round, epoch);
}

/* Runs pass(e) for the entries e of a list whose length is lengths[index],
 * by the work-group, then waits for all of it. */
#define CAROM_FOR_LISTED(lengths, index, e, pass)                                      \
    do {                                                                               \
        const uint carom_length = (lengths)[index];                                    \
        for (uint e = get_local_id(0); e < carom_length; e += get_local_size(0)) pass; \
        barrier(CLK_GLOBAL_MEM_FENCE);                                                 \
    } while (0)

/* Rounds firstRound, firstRound + 1, ... of a step, by one work-group: those
 * of resolveEvents and searchChanged, with barriers instead of launches,
 * round after round until none is pending or round maxRounds ran. Round r
 * uses epoch firstEpoch + (r - firstRound), as the launches do. */
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
                                         CaromDeviceLists l)
{
    uint epoch = firstEpoch;
    for (uint round = firstRound; round <= maxRounds && l.lengths[CAROM_PENDING_LENGTH(round - 1)] != 0u;
         ++round, ++epoch) {
        CAROM_FOR_LISTED(l.lengths, CAROM_PENDING_LENGTH(round - 1), e,
                         carom_resolve_pending(e, state, slots, ids, step, tallies, l, round, epoch));
        CAROM_FOR_LISTED(l.lengths, CAROM_CHANGED_LENGTH(round), e,
                         carom_search_changed(e, state, slots, ids, cellOf, cells, step, l, round, epoch));
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
                                   __global uint* words,
                                   uint firstRound,
                                   uint maxRounds,
                                   uint firstEpoch)
{
    if (CAROM_HALTED(halt)) return;
    carom_rounds_in_group(firstRound, maxRounds, firstEpoch, state, slots, ids, cellOf, cells, step, tallies,
                          carom_device_lists(words, step.count));
}
