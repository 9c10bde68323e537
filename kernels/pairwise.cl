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

/* The resident pipeline's neighbour lists, in the buffer `words`
 * (DevicePairwise's neighbours), for n disks by sorted position: the n
 * words where each disk's list starts among the entries, the n where it
 * ends, where each disk was when they were built (carom_list_origins), then
 * the entries (carom_list_entries). Their state is in the lists' header
 * (CAROM_LISTS_BUILT and after). */
static inline __global float2* carom_list_origins(__global uint* words, uint n)
{
    return (__global float2*)(words + 2ul * n);
}

static inline __global uint* carom_list_entries(__global uint* words, uint n)
{
    return words + 4ul * n;
}

/* Where this substep's searches find their candidates: the lists where the
 * start found them usable (CAROM_LISTS_USED), else the grid. */
static inline CaromNeighbours carom_step_neighbours(__global const uint* cellOf,
                                                    __global const GridCell* cells,
                                                    __global uint* neighbourWords,
                                                    __global const uint* lengths,
                                                    uint n)
{
    CaromNeighbours neighbours = carom_grid_neighbours(cellOf, cells);
    if (neighbourWords && lengths[CAROM_LISTS_USED] != 0u) {
        neighbours.listStarts = neighbourWords;
        neighbours.listEnds = neighbourWords + n;
        neighbours.list = carom_list_entries(neighbourWords, n);
    }
    return neighbours;
}

/* The start's choice for a substep's neighbour lists (skin > 0), from the
 * largest speed squared of the state it starts from (0 before any finish:
 * unknown) and the disks' largest displacement squared since the lists were
 * built: search the lists that hold, or build them and search them, or where
 * lists built now would not cover the substep's travel, search the grid.
 * halt[1] tells the grid's kernels whether the grid is needed. */
static inline void carom_plan_lists(
    __global uint* halt, __global uint* lengths, float speedSquared, uint parity, float skin, float dt, float gravity)
{
    /* An unknown speed counts as all that the substeps allow, for which
     * lists built now do not hold. */
    const float travel = speedSquared > 0.0f ? carom_substep_travel(speedSquared, gravity, dt) : skin;
    const int holds = lengths[CAROM_LISTS_BUILT] != 0u &&
                      carom_lists_cover(skin, as_float(lengths[CAROM_LISTS_DISPLACEMENT(parity)]), travel);
    const int build = !holds && carom_lists_cover(skin, 0.0f, travel);
    lengths[CAROM_LISTS_BUILD] = (uint)build;
    lengths[CAROM_LISTS_USED] = (uint)(holds || build);
    if (!holds) lengths[CAROM_LISTS_BUILT] = 0u;
    if (build) lengths[CAROM_LISTS_TOTAL] = lengths[CAROM_LISTS_OVERFLOW] = 0u;
    if (holds || build) lengths[CAROM_LISTS_USES] += 1u;
    halt[1] = (uint)holds;
}

/* The start of a pairwise substep: zeroes the list lengths. In a chunk the
 * host enqueued without waiting (OpenClResidentBackend), it first checks
 * the state the substep starts from, unless `check` is 0: when a disk in it
 * is non-finite, or, at a step's first substep (check 2), when its largest
 * v.x^2 + v.y^2 (the float's bits in lengths[speedWord]) asks for another
 * count than the `substeps` the host planned (carom_substeps_needed under
 * `rule`), it records `stepIndex` in halt[0] instead, and the chunk's
 * kernels from here on do nothing. Every work-item decides alike. With a
 * skin (> 0: the resident pipeline's neighbour lists), it then chooses how
 * the substep finds neighbours (carom_plan_lists; the speed word's parity is
 * the state's); without, the substep searches the grid. */
__kernel void startPairwiseStep(__global uint* halt,
                                __global uint* lengths,
                                uint lengthCount,
                                uint check,
                                CaromSubstepRule rule,
                                uint substeps,
                                uint speedWord,
                                uint parity,
                                uint nonFiniteIndex,
                                uint stepIndex,
                                float skin,
                                float dt,
                                float gravity)
{
    if (CAROM_HALTED(halt)) return;
    const float speedSquared = as_float(lengths[speedWord]);
    if (check != 0u && (lengths[nonFiniteIndex] != CAROM_ALL_FINITE ||
                        (check == 2u && carom_substeps_needed(speedSquared, rule) != substeps))) {
        if (get_global_id(0) == 0) halt[0] = stepIndex;
        return;
    }
    for (uint i = get_global_id(0); i < lengthCount; i += get_global_size(0)) lengths[i] = 0u;
    if (get_global_id(0) != 0) return;
    if (skin > 0.0f) {
        carom_plan_lists(halt, lengths, speedSquared, parity, skin, dt, gravity);
    } else {
        lengths[CAROM_LISTS_USED] = 0u;
        halt[1] = 0u;
    }
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
                         __global uint* neighbourWords,
                         uint epoch)
{
    if (CAROM_HALTED(halt)) return;
    const uint k = get_global_id(0);
    if (k >= step.count) return;
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    const CaromList none = carom_list(0, l.lengths, 0, 0);
    carom_find_event(k, state, slots, ids, carom_step_neighbours(cellOf, cells, neighbourWords, l.lengths, step.count),
                     step, l.events, CAROM_SEARCH_ALL, none, none,
                     carom_list(l.pending0, l.lengths, CAROM_PENDING_LENGTH(0), l.pendingMarks), epoch);
}

/* Round r's search of the disks it changed, which also searches the dirty
 * disks they find. */
static inline void carom_search_changed(uint e,
                                        __global const Particle* state,
                                        __global const uint* slots,
                                        __global const uint* ids,
                                        CaromNeighbours neighbours,
                                        CaromStepParams step,
                                        CaromDeviceLists l,
                                        uint round,
                                        uint epoch)
{
    carom_find_event(l.changed[e], state, slots, ids, neighbours, step, l.events, CAROM_SEARCH_CHANGED,
                     carom_list(l.changed, l.lengths, CAROM_CHANGED_LENGTH(round), l.changedMarks),
                     carom_list(0, 0, 0, l.dirtyMarks),
                     carom_list(carom_pending_of(l, round), l.lengths, CAROM_PENDING_LENGTH(round), l.pendingMarks),
                     epoch);
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
                            __global uint* neighbourWords,
                            uint round,
                            uint epoch)
{
    if (CAROM_HALTED(halt)) return;
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    const CaromNeighbours neighbours = carom_step_neighbours(cellOf, cells, neighbourWords, l.lengths, step.count);
    const uint length = l.lengths[CAROM_CHANGED_LENGTH(round)];
    for (uint e = get_global_id(0); e < length; e += get_global_size(0))
        carom_search_changed(e, state, slots, ids, neighbours, step, l, round, epoch);
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
                                         CaromNeighbours neighbours,
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
                         carom_search_changed(e, state, slots, ids, neighbours, step, l, round, epoch));
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
                                   __global uint* neighbourWords,
                                   uint firstRound,
                                   uint maxRounds,
                                   uint firstEpoch)
{
    if (CAROM_HALTED(halt)) return;
    const CaromDeviceLists l = carom_device_lists(words, step.count);
    carom_rounds_in_group(firstRound, maxRounds, firstEpoch, state, slots, ids,
                          carom_step_neighbours(cellOf, cells, neighbourWords, l.lengths, step.count), step, tallies,
                          l);
}

/* Disk k's neighbour list from this substep's grid: the disks of the 3 x 3
 * cells around its start cell whose centres lie within its contact distance
 * plus `skin` (the grid's cells are that wide: DevicePairwise::enableLists),
 * counted, and written from entries[at] unless `entries` is null; returns
 * how many. The lists are built at the substep's start, where every disk's
 * own time is 0. */
static inline uint carom_collect_neighbours(uint k,
                                            __global const Particle* state,
                                            __global const uint* slots,
                                            __global const uint* cellOf,
                                            __global const GridCell* cells,
                                            CaromStepParams step,
                                            float skin,
                                            __global uint* entries,
                                            uint at)
{
    const Particle self = state[carom_slot(slots, k)];
    const uint cell = cellOf[carom_slot(slots, k)];
    const int cellX = (int)(cell % (uint)step.grid.cols);
    const int cellY = (int)(cell / (uint)step.grid.cols);
    uint length = 0;
    for (int run = 0; run < 6; ++run) {
        uint begin, stop;
        if (!carom_neighbour_run(run, cellX, cellY, cells, step.grid, step.box, &begin, &stop)) continue;
        for (uint q = begin; q < stop; ++q) {
            if (q == k) continue;
            if (carom_within_reach(self, state[carom_slot(slots, q)], skin, step.box)) {
                if (entries) entries[at + length] = q;
                ++length;
            }
        }
    }
    return length;
}

/* A build of the neighbour lists, where the start chose one
 * (CAROM_LISTS_BUILD), after the substep's grid, in two launches. The first
 * (`fill` 0) counts each disk's list, takes its place among the entries (a
 * work-group's places at once, after the places taken before: which list
 * lands where changes nothing computed), and keeps where the disk is, from
 * which the finishes measure how far it moves. The second writes the
 * entries where they all fit in `capacity` (and their count in 32 bits);
 * where they do not, the substep searches the grid instead, and the host
 * makes room for them before the next chunk (DevicePairwise::complete). */
__kernel void buildNeighbourLists(__global const uint* halt,
                                  __global const Particle* state,
                                  __global const uint* slots,
                                  __global const uint* cellOf,
                                  __global const GridCell* cells,
                                  CaromStepParams step,
                                  __global uint* words,
                                  __global uint* neighbourWords,
                                  float skin,
                                  uint capacity,
                                  uint fill)
{
    if (CAROM_HALTED(halt) || words[CAROM_LISTS_BUILD] == 0u) return;
    const uint k = get_global_id(0);
    if (fill) {
        if (k >= step.count) return;
        const int fits = words[CAROM_LISTS_OVERFLOW] == 0u;
        if (k == 0) {
            words[CAROM_LISTS_USED] = (uint)fits;
            words[CAROM_LISTS_BUILT] = (uint)fits;
            words[CAROM_LISTS_BUILDS] += (uint)fits;
            words[CAROM_LISTS_USES] -= (uint)!fits;
        }
        if (fits)
            carom_collect_neighbours(k, state, slots, cellOf, cells, step, skin,
                                     carom_list_entries(neighbourWords, step.count), neighbourWords[k]);
        return;
    }
    __local uint groupLength, groupStart;
    if (get_local_id(0) == 0) groupLength = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    uint length = 0, offset = 0;
    if (k < step.count) {
        length = carom_collect_neighbours(k, state, slots, cellOf, cells, step, skin, 0, 0u);
        offset = atomic_add(&groupLength, length);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0) {
        groupStart = atomic_add(&words[CAROM_LISTS_TOTAL], groupLength);
        const uint end = groupStart + groupLength;
        if (end < groupStart || end > capacity) words[CAROM_LISTS_OVERFLOW] = 1u;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (k >= step.count) return;
    neighbourWords[k] = groupStart + offset;
    neighbourWords[step.count + k] = groupStart + offset + length;
    const Particle self = state[carom_slot(slots, k)];
    carom_list_origins(neighbourWords, step.count)[k] = (float2)(self.position.x, self.position.y);
}
