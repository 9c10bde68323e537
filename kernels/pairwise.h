/* The pairwise collision scheme, per disk, written once for both backends
 * (like physics.h, compiled by the host and by the OpenCL compiler).
 *
 * Every collision is a binary elastic collision at its exact contact time, so
 * kinetic energy is conserved to rounding whatever the density. Within a step
 * of duration h each disk carries its own time (Particle.time): its position
 * and velocity hold at that time, and it flies freely, under gravity, until
 * its next event. The step runs in rounds:
 *
 *   find      every disk finds its earliest event in the rest of the step
 *             (carom_find_event, first forward over each pair once, then all
 *             neighbours for the disks met from behind): the first contact
 *             with a neighbour while approaching (the first root of
 *             |dx + dv t|^2 = sigma^2: both disks fall alike, so their
 *             relative motion is linear), or a wall (a quadratic under
 *             gravity);
 *   resolve   pairs whose earliest events are each other, and wall events,
 *             are resolved (carom_resolve_event): the disks fly to the
 *             contact time and receive the elastic impulse along the exact
 *             contact normal. A disk takes part in at most one impulse per
 *             round;
 *   search    the disks that changed look again, and mark the unchanged
 *             neighbours whose earliest event they invalidate or beat
 *             (CAROM_SEARCH_CHANGED); those look again too, at once;
 *
 * until no event is left before the end of the step; then every disk flies to
 * the end (carom_finish_step). Events are ordered by (time, lower id, higher id), so
 * the earliest event of a disk is a minimum, not a sum: it does not depend on
 * the order in which disks or neighbours are visited, and the backends agree
 * bit for bit. The globally earliest event is always mutual, so each round
 * resolves at least one event.
 *
 * The lists of pending, changed and dirty disks are filled with atomic
 * appends, in an order that depends on scheduling; nothing computed depends
 * on that order. A disk is identified by its position k in sortedIndices
 * (`ids[k]` is its id, `state[carom_slot(slots, k)]` its particle,
 * `cellOf[carom_slot(slots, k)]` the cell it started the step in). */
#ifndef CAROM_PAIRWISE_H
#define CAROM_PAIRWISE_H

#include "physics.h"

#ifdef __OPENCL_VERSION__
#define CAROM_NEVER HUGE_VALF
static inline unsigned int carom_append(volatile __global unsigned int* count)
{
    return atomic_inc(count);
}
/* 1 for the first caller of the round (epoch) only. */
static inline int carom_claim(volatile __global unsigned int* mark, unsigned int epoch)
{
    return atomic_xchg(mark, epoch) != epoch;
}
#else
#include <cstdint>
namespace carom {
constexpr float CAROM_NEVER = HUGE_VALF;
static inline unsigned int carom_append(unsigned int* count)
{
    return __atomic_fetch_add(count, 1u, __ATOMIC_RELAXED);
}
static inline int carom_claim(unsigned int* mark, unsigned int epoch)
{
    return __atomic_exchange_n(mark, epoch, __ATOMIC_RELAXED) != epoch;
}
#endif

/* CaromEvent.partner values beyond any sorted position (N <= kMaxParticles). */
#define CAROM_NO_PARTNER 0xFFFFFFFFu
#define CAROM_WALL 0xFFFFFFF0u /* + 0 left, 1 right, 2 bottom, 3 top */

/* The earliest event of a disk in the rest of the step. Aligned to its
 * size, so that the host reads and writes it whole (carom_load_event). */
typedef struct __attribute__((aligned(8))) CaromEvent {
    float time;           /* within the step, in [0, duration]; CAROM_NEVER for none */
    unsigned int partner; /* sorted position of the other disk, CAROM_WALL + wall, or CAROM_NO_PARTNER */
} CaromEvent;

/* A disk's event, which one search may write while another reads it
 * (carom_search_candidate): on the host, whole and without a data race. */
#ifdef __OPENCL_VERSION__
static inline CaromEvent carom_load_event(__global const CaromEvent* e)
{
    return *e;
}
static inline void carom_store_event(__global CaromEvent* e, CaromEvent value)
{
    *e = value;
}
#else
static inline CaromEvent carom_load_event(const CaromEvent* e)
{
    CaromEvent value;
    __atomic_load(e, &value, __ATOMIC_RELAXED);
    return value;
}
static inline void carom_store_event(CaromEvent* e, CaromEvent value)
{
    __atomic_store(e, &value, __ATOMIC_RELAXED);
}
#endif

/* Where the disk at sorted position k is stored: slots[k]; or k itself
 * where `slots` is null, the state being stored in sorted order (the
 * resident pipeline gathers it so as it builds a step's grid: a search then
 * reads its neighbours without looking up their slots). */
static inline unsigned int carom_slot(CAROM_GLOBAL const unsigned int* slots, unsigned int k)
{
    return slots ? slots[k] : k;
}

/* Rounding of positions: about 8 units in the last place of the largest
 * coordinate. A pair resolved deeper in overlap than this, or a disk found
 * further past a wall, was late: its contact was missed, not just rounded. */
static inline float carom_rounding_tolerance(CaromBox box)
{
    return 1e-6f * (box.width + box.height);
}

/* The disk flown freely from its own time to t >= p.time: exact for constant
 * gravity, so kinetic plus potential energy is conserved. */
static inline Particle carom_fly(Particle p, float t, float gravityX, float gravityY)
{
    if (t == p.time) return p; /* most disks have no event in a step: skip the arithmetic */
    const float s = t - p.time;
    p.position.x += s * (p.velocity.x + (0.5f * gravityX) * s);
    p.position.y += s * (p.velocity.y + (0.5f * gravityY) * s);
    p.velocity.x += gravityX * s;
    p.velocity.y += gravityY * s;
    p.time = t;
    return p;
}

/* When disks a and b (ids idA != idB) first touch while approaching, from
 * the later of their own times to the end of the step; CAROM_NEVER if they
 * do not. A pair already touching or overlapping and approaching meets at
 * once. Two disks whose last collision was with each other cannot meet
 * again in free flight (their relative motion is linear and receding): that
 * rule keeps float rounding from colliding them twice. Swapping a and b
 * negates d and dv exactly and changes no product or sum, so both disks
 * compute the same bits. */
static inline float carom_pair_event_time(
    Particle a, unsigned int idA, Particle b, unsigned int idB, CaromStepParams step)
{
    if (a.lastPartner == idB + 1u && b.lastPartner == idA + 1u) return CAROM_NEVER;
    const float t0 = a.time > b.time ? a.time : b.time;
    a = carom_fly(a, t0, step.gravityX, step.gravityY);
    b = carom_fly(b, t0, step.gravityX, step.gravityY);
    const float2 d = carom_offset(a.position, b.position, step.box);
    const float dvx = a.velocity.x - b.velocity.x;
    const float dvy = a.velocity.y - b.velocity.y;
    const float approach = d.x * dvx + d.y * dvy;
    if (!(approach < 0.0f)) return CAROM_NEVER;
    const float contact = a.radius + b.radius;
    const float gap = (d.x * d.x + d.y * d.y) - contact * contact;
    if (gap <= 0.0f) return t0;
    /* The root below is at least gap / (-2 approach) after t0: most
     * approaching pairs are too far apart to meet before the step ends, and
     * this (with a factor 2 to spare for rounding) skips their square root. */
    if (gap > (-4.0f * approach) * (step.duration - t0)) return CAROM_NEVER;
    const float discriminant = approach * approach - (dvx * dvx + dvy * dvy) * gap;
    if (!(discriminant > 0.0f)) return CAROM_NEVER;
    /* The smaller root, in the form without cancellation (approach < 0). */
    const float t = t0 + gap / (carom_sqrt(discriminant) - approach);
    return t <= step.duration ? t : CAROM_NEVER;
}

/* The delay until a disk `gap` away from touching a wall (negative: past
 * it), moving towards it at `speed` with acceleration `accel` towards it,
 * touches it while moving in; CAROM_NEVER if it does not. A disk resting
 * against a wall (no speed, pressed by gravity) has no impact to resolve. */
static inline float carom_wall_delay(float gap, float speed, float accel)
{
    const float discriminant = speed * speed + 2.0f * accel * gap;
    if (speed > 0.0f) {
        if (gap <= 0.0f) return 0.0f;
        if (!(discriminant > 0.0f)) return CAROM_NEVER; /* pulled back before it arrives */
        return (2.0f * gap) / (speed + carom_sqrt(discriminant));
    }
    if (!(accel > 0.0f) || !(discriminant > 0.0f)) return CAROM_NEVER;
    return (carom_sqrt(discriminant) - speed) / accel; /* moving away now, falling back later */
}

/* Wall w's gap, speed towards it and acceleration towards it. */
static inline void carom_wall_motion(Particle p, int w, CaromStepParams step, float* gap, float* speed, float* accel)
{
    const float position = w < 2 ? p.position.x : p.position.y;
    const float velocity = w < 2 ? p.velocity.x : p.velocity.y;
    const float gravity = w < 2 ? step.gravityX : step.gravityY;
    const float extent = w < 2 ? step.box.width : step.box.height;
    if (w % 2 == 0) {
        *gap = position - p.radius;
        *speed = -velocity;
        *accel = -gravity;
    } else {
        *gap = (extent - p.radius) - position;
        *speed = velocity;
        *accel = gravity;
    }
}

/* The earliest wall contact in the rest of the step of a disk that started
 * the step in cell (cellX, cellY); equal times go to the lower wall index.
 * Only the walls of the cell's own edge of the grid can be reached in a
 * step, as only neighbouring cells can (none in a periodic box). */
static inline CaromEvent carom_wall_event(Particle p, int cellX, int cellY, CaromStepParams step)
{
    CaromEvent event;
    event.time = CAROM_NEVER;
    event.partner = CAROM_NO_PARTNER;
    if (step.box.periodic) return event;
    const int reachable[4] = {cellX == 0, cellX == step.grid.cols - 1, cellY == 0, cellY == step.grid.rows - 1};
    for (int w = 0; w < 4; ++w) {
        if (!reachable[w]) continue;
        float gap, speed, accel;
        carom_wall_motion(p, w, step, &gap, &speed, &accel);
        const float t = p.time + carom_wall_delay(gap, speed, accel);
        if (t <= step.duration && t < event.time) {
            event.time = t;
            event.partner = CAROM_WALL + (unsigned int)w;
        }
    }
    return event;
}

/* Whether event (t, lo, hi) comes before event (u, uLo, uHi). */
static inline int carom_event_before(
    float t, unsigned int lo, unsigned int hi, float u, unsigned int uLo, unsigned int uHi)
{
    if (t != u) return t < u;
    if (lo != uLo) return lo < uLo;
    return hi < uHi;
}

/* Whether a pair event (t, ids a and b) comes before disk `self`'s event e. */
static inline int carom_pair_event_before(
    float t, unsigned int a, unsigned int b, CaromEvent e, unsigned int self, CAROM_GLOBAL const unsigned int* ids)
{
    if (e.time == CAROM_NEVER) return 1;
    unsigned int eLo = self, eHi = e.partner;
    if (e.partner < CAROM_WALL) {
        const unsigned int other = ids[e.partner];
        eLo = self < other ? self : other;
        eHi = self < other ? other : self;
    }
    return carom_event_before(t, a < b ? a : b, a < b ? b : a, e.time, eLo, eHi);
}

/* A list of sorted positions that a pass appends to, with one mark per
 * disk: the epoch of the round it was last added in, which keeps the list
 * free of repeats within a round and tells whether a disk is on it. */
typedef struct CaromList {
    CAROM_GLOBAL unsigned int* items;
    CAROM_GLOBAL unsigned int* count;
    CAROM_GLOBAL unsigned int* marks;
} CaromList;

static inline void carom_list_add(CaromList list, unsigned int k, unsigned int epoch)
{
    if (carom_claim(&list.marks[k], epoch)) list.items[carom_append(list.count)] = k;
}

/* Where a step's list lengths are kept (the OpenCL pipelines' `lengths`):
 * two words a round r, 0 being the first search: the length of the pending
 * list built in round r, and of the list of disks changed in it (none in
 * round 0). */
#define CAROM_PENDING_LENGTH(r) (2u * (r))
#define CAROM_CHANGED_LENGTH(r) (2u * (r) + 1u)
/* The words before the OpenCL pipelines' lists in their buffer: the
 * lengths, then the words the host reads back with them (its record). */
#define CAROM_LIST_HEADER_WORDS 256u
/* The resident pipeline's neighbour lists (kernels/pairwise.cl), in the
 * header's last words: whether the last build's entries overflowed their
 * room (or 32 bits); whether they hold for the state (built for its order
 * and positions); whether this substep builds them and whether its searches
 * use them (startPairwiseStep); the entries the last build needed; the
 * largest displacement squared since the build (the float's bits) of the
 * state each parity's finish wrote; and, for the record, how many builds
 * there were and how many substeps used them. */
#define CAROM_LISTS_OVERFLOW (CAROM_LIST_HEADER_WORDS - 9u)
#define CAROM_LISTS_BUILT (CAROM_LIST_HEADER_WORDS - 8u)
#define CAROM_LISTS_BUILD (CAROM_LIST_HEADER_WORDS - 7u)
#define CAROM_LISTS_USED (CAROM_LIST_HEADER_WORDS - 6u)
#define CAROM_LISTS_TOTAL (CAROM_LIST_HEADER_WORDS - 5u)
#define CAROM_LISTS_DISPLACEMENT(parity) (CAROM_LIST_HEADER_WORDS - 4u + (parity))
#define CAROM_LISTS_BUILDS (CAROM_LIST_HEADER_WORDS - 2u)
#define CAROM_LISTS_USES (CAROM_LIST_HEADER_WORDS - 1u)

/* Collisions within a substep can speed a disk up: substeps are sized so
 * that a disk this many times faster than the fastest one at the substep's
 * start still stays within the pairwise grid's allowance. */
#define CAROM_PAIRWISE_SPEED_MARGIN 2.0f

/* The farthest a disk travels in a substep of dt whose fastest disk starts
 * at sqrt(speedSquared), under gravity of this magnitude, on that margin. */
static inline float carom_substep_travel(float speedSquared, float gravity, float dt)
{
    return CAROM_PAIRWISE_SPEED_MARGIN * (carom_sqrt(speedSquared) + gravity * dt) * dt;
}

/* Whether neighbour lists of this skin hold every pair that can meet in a
 * substep in which no disk travels `travel` or more, after the disks moved
 * at most sqrt(displacementSquared) since their build. A pair left out was
 * more than contact plus the skin apart at the build: it can meet only once
 * both disks' moves since then and in the substep close the skin. A tenth
 * of the skin is left to rounding. */
static inline int carom_lists_cover(float skin, float displacementSquared, float travel)
{
    return 2.0f * (carom_sqrt(displacementSquared) + travel) < 0.9f * skin;
}

/* Whether disk b's centre lies within a's contact distance plus `skin` (to
 * the nearest image): b belongs on a's neighbour list. */
static inline int carom_within_reach(Particle a, Particle b, float skin, CaromBox box)
{
    const float2 d = carom_offset(a.position, b.position, box);
    const float reach = a.radius + b.radius + skin;
    return d.x * d.x + d.y * d.y < reach * reach;
}

/* How far a disk at `position` is from `origin`, where the lists' build
 * found it, squared (to the nearest image). */
static inline float carom_displacement_squared(float2 position, float2 origin, CaromBox box)
{
    const float2 d = carom_offset(position, origin, box);
    return d.x * d.x + d.y * d.y;
}

/* What a search visits, and whom it adds to the dirty list to search again. */
#define CAROM_SEARCH_ALL 0 /* every neighbour */
#define CAROM_SEARCH_FORWARD \
    1 /* the neighbours after k in sorted order, each pair once; those it can meet are
                                * dirty, to collect the pairs before them */
#define CAROM_SEARCH_CHANGED \
    2 /* every neighbour, for a disk that changed this round: unchanged neighbours
                                * whose earliest event it beats, or whose earliest event was with it, are dirty
                                * and searched at once by the search that marked them */

/* Where a search finds a disk's candidates: the grid's 3x3 cells around the
 * cell the disk started the step in (cellOf, by slot: the grid's cells are
 * wide enough for every pair that can meet within the step); or, where
 * `listStarts` is not null, the disk's neighbour list,
 * list[listStarts[k] .. listEnds[k]), which holds every disk it can meet
 * within the step (lists with a skin: the CPU backend's, positions
 * ascending, listEnds being listStarts + 1; the resident pipeline's, in the
 * grid's order). The earliest event is a minimum, so both give the same
 * bits. */
typedef struct CaromNeighbours {
    CAROM_GLOBAL const unsigned int* cellOf;
    CAROM_GLOBAL const GridCell* cells;
    CAROM_GLOBAL const unsigned int* listStarts;
    CAROM_GLOBAL const unsigned int* listEnds;
    CAROM_GLOBAL const unsigned int* list;
} CaromNeighbours;

static inline CaromNeighbours carom_grid_neighbours(CAROM_GLOBAL const unsigned int* cellOf,
                                                    CAROM_GLOBAL const GridCell* cells)
{
    CaromNeighbours neighbours;
    neighbours.cellOf = cellOf;
    neighbours.cells = cells;
    neighbours.listStarts = 0;
    neighbours.listEnds = 0;
    neighbours.list = 0;
    return neighbours;
}

/* The first entry from `begin` of an ascending list that is at least `first`. */
static inline unsigned int carom_skip_below(CAROM_GLOBAL const unsigned int* list,
                                            unsigned int begin,
                                            unsigned int end,
                                            unsigned int first)
{
    while (begin < end && list[begin] < first) ++begin;
    return begin;
}

/* Runs `visit` for each candidate q >= first of the disk at sorted position
 * k, which started the step in cell (cellX, cellY) (CaromNeighbours; `first`
 * > 0 needs a list in ascending order). */
#define CAROM_FOR_EACH_CANDIDATE(k, cellX, cellY, first, neighbours, step, q, visit)                           \
    do {                                                                                                       \
        if ((neighbours).listStarts) {                                                                         \
            const unsigned int carom_end = (neighbours).listEnds[k];                                           \
            for (unsigned int carom_e =                                                                        \
                     carom_skip_below((neighbours).list, (neighbours).listStarts[k], carom_end, first);        \
                 carom_e < carom_end; ++carom_e) {                                                             \
                const unsigned int q = (neighbours).list[carom_e];                                             \
                visit;                                                                                         \
            }                                                                                                  \
        } else {                                                                                               \
            for (int carom_run = 0; carom_run < 6; ++carom_run) {                                              \
                unsigned int carom_begin, carom_stop;                                                          \
                if (!carom_neighbour_run(carom_run, cellX, cellY, (neighbours).cells, (step).grid, (step).box, \
                                         &carom_begin, &carom_stop))                                           \
                    continue;                                                                                  \
                for (unsigned int q = carom_begin > (first) ? carom_begin : (first); q < carom_stop; ++q)      \
                    if (q != (k)) visit;                                                                       \
            }                                                                                                  \
        }                                                                                                      \
    } while (0)

/* What a search's best event so far is, with its pair's ids for ties. */
typedef struct CaromBest {
    CaromEvent event;
    unsigned int lo, hi;
} CaromBest;

/* The disk at sorted position k, what a search of it starts from: its
 * particle, id and start cell, and its earliest wall event as the best. */
typedef struct CaromSearcher {
    Particle self;
    unsigned int selfId;
    int cellX, cellY;
    CaromBest best;
} CaromSearcher;

static inline CaromSearcher carom_searcher(unsigned int k,
                                           CAROM_GLOBAL const Particle* state,
                                           CAROM_GLOBAL const unsigned int* slots,
                                           CAROM_GLOBAL const unsigned int* ids,
                                           CaromNeighbours neighbours,
                                           CaromStepParams step)
{
    CaromSearcher s;
    s.self = state[carom_slot(slots, k)];
    s.selfId = ids[k];
    const unsigned int cell = neighbours.cellOf[carom_slot(slots, k)];
    s.cellX = (int)(cell % (unsigned int)step.grid.cols);
    s.cellY = (int)(cell / (unsigned int)step.grid.cols);
    s.best.event = carom_wall_event(s.self, s.cellX, s.cellY, step);
    s.best.lo = s.selfId;
    s.best.hi = s.best.event.partner;
    return s;
}

/* Whether the pair event at time t (CAROM_NEVER for none) with the disk at
 * position q (id otherId) beats the best so far; if so it becomes the best. */
static inline int carom_consider(CaromBest* best, float t, unsigned int q, unsigned int selfId, unsigned int otherId)
{
    if (t == CAROM_NEVER) return 0;
    const unsigned int lo = selfId < otherId ? selfId : otherId;
    const unsigned int hi = selfId < otherId ? otherId : selfId;
    if (best->event.time == CAROM_NEVER || carom_event_before(t, lo, hi, best->event.time, best->lo, best->hi)) {
        best->event.time = t;
        best->event.partner = q;
        best->lo = lo;
        best->hi = hi;
    }
    return 1;
}

/* The earliest event of the disk at sorted position k over all its
 * candidates (CaromNeighbours). */
static inline CaromEvent carom_earliest_event(unsigned int k,
                                              CAROM_GLOBAL const Particle* state,
                                              CAROM_GLOBAL const unsigned int* slots,
                                              CAROM_GLOBAL const unsigned int* ids,
                                              CaromNeighbours neighbours,
                                              CaromStepParams step)
{
    CaromSearcher s = carom_searcher(k, state, slots, ids, neighbours, step);
    CAROM_FOR_EACH_CANDIDATE(
        k, s.cellX, s.cellY, 0u, neighbours, step, q,
        carom_consider(&s.best, carom_pair_event_time(s.self, s.selfId, state[carom_slot(slots, q)], ids[q], step), q,
                       s.selfId, ids[q]));
    return s.best.event;
}

/* Disk k's earliest event recorded, and k on the pending list if it has one. */
static inline void carom_record_event(
    unsigned int k, CaromEvent event, CAROM_GLOBAL CaromEvent* events, CaromList pending, unsigned int epoch)
{
    carom_store_event(&events[k], event);
    if (event.time != CAROM_NEVER) carom_list_add(pending, k, epoch);
}

/* Candidate q of the search of disk k (searcher s) in `mode`, FORWARD or
 * CHANGED (carom_find_event). A dirty neighbour found in CHANGED mode is searched
 * at once, by the search that claims it: its old event, which the other
 * changed disks' searches read, is then replaced only once it is claimed,
 * and a search that reads the new event finds it claimed already. */
static inline void carom_search_candidate(unsigned int k,
                                          CaromSearcher* s,
                                          unsigned int q,
                                          CAROM_GLOBAL const Particle* state,
                                          CAROM_GLOBAL const unsigned int* slots,
                                          CAROM_GLOBAL const unsigned int* ids,
                                          CaromNeighbours neighbours,
                                          CaromStepParams step,
                                          CAROM_GLOBAL CaromEvent* events,
                                          int mode,
                                          CaromList changed,
                                          CaromList dirty,
                                          CaromList pending,
                                          unsigned int epoch)
{
    const unsigned int otherId = ids[q];
    const float t = carom_pair_event_time(s->self, s->selfId, state[carom_slot(slots, q)], otherId, step);
    const int meets = carom_consider(&s->best, t, q, s->selfId, otherId);
    if (mode == CAROM_SEARCH_FORWARD) {
        if (meets) carom_list_add(dirty, q, epoch);
    } else if (changed.marks[q] != epoch) {
        const CaromEvent theirs = carom_load_event(&events[q]);
        if ((theirs.partner == k || (meets && carom_pair_event_before(t, s->selfId, otherId, theirs, otherId, ids))) &&
            carom_claim(&dirty.marks[q], epoch))
            carom_record_event(q, carom_earliest_event(q, state, slots, ids, neighbours, step), events, pending, epoch);
    }
}

/* A search pass: disk k's earliest event in `mode`, and k on the pending
 * list if it has one. The first search of a step runs forward for every
 * disk, then all for the disks it made dirty; a round's runs changed for
 * the disks it changed, which also searches the dirty ones. */
static inline void carom_find_event(unsigned int k,
                                    CAROM_GLOBAL const Particle* state,
                                    CAROM_GLOBAL const unsigned int* slots,
                                    CAROM_GLOBAL const unsigned int* ids,
                                    CaromNeighbours neighbours,
                                    CaromStepParams step,
                                    CAROM_GLOBAL CaromEvent* events,
                                    int mode,
                                    CaromList changed,
                                    CaromList dirty,
                                    CaromList pending,
                                    unsigned int epoch)
{
    if (mode == CAROM_SEARCH_ALL) {
        carom_record_event(k, carom_earliest_event(k, state, slots, ids, neighbours, step), events, pending, epoch);
        return;
    }
    CaromSearcher s = carom_searcher(k, state, slots, ids, neighbours, step);
    const unsigned int first = mode == CAROM_SEARCH_FORWARD ? k + 1u : 0u;
    CAROM_FOR_EACH_CANDIDATE(k, s.cellX, s.cellY, first, neighbours, step, q,
                             carom_search_candidate(k, &s, q, state, slots, ids, neighbours, step, events, mode,
                                                    changed, dirty, pending, epoch));
    carom_record_event(k, s.best.event, events, pending, epoch);
}

/* Disks a and b (ids idA < idB) collide at time t: both fly there and
 * receive the elastic impulse along their separation, which conserves
 * kinetic energy exactly for any normal. A pair found overlapping beyond
 * rounding (a late contact) is also pushed apart to contact, each by the
 * other's share of the mass, which keeps the centre of mass, and so the
 * potential energy under gravity, where it was. The collision, its virial
 * r_ij . J_ij = 2 mu_ij |v_n| r_ij and a late contact count on a's tally. */
static inline void carom_collide_pair(Particle* a,
                                      unsigned int idA,
                                      Particle* b,
                                      unsigned int idB,
                                      float t,
                                      CaromStepParams step,
                                      CAROM_GLOBAL ContactTally* tally)
{
    *a = carom_fly(*a, t, step.gravityX, step.gravityY);
    *b = carom_fly(*b, t, step.gravityX, step.gravityY);
    const float2 d = carom_offset(a->position, b->position, step.box);
    const float dist2 = d.x * d.x + d.y * d.y;
    const float approach = (a->velocity.x - b->velocity.x) * d.x + (a->velocity.y - b->velocity.y) * d.y;
    const float shareA = b->mass / (a->mass + b->mass); /* a's share of the impulse and of the push */
    const float shareB = a->mass / (a->mass + b->mass);
    if (approach < 0.0f) { /* also false when dist2 == 0 */
        const float perDist2 = approach / dist2;
        a->velocity.x -= ((2.0f * shareA) * perDist2) * d.x;
        a->velocity.y -= ((2.0f * shareA) * perDist2) * d.y;
        b->velocity.x += ((2.0f * shareB) * perDist2) * d.x;
        b->velocity.y += ((2.0f * shareB) * perDist2) * d.y;
        tally->collisions += 1u;
        tally->virial -= (2.0f * (a->mass * shareA)) * approach;
    }
    const float contact = a->radius + b->radius;
    const float dist = carom_sqrt(dist2);
    if (contact - dist > step.tolerance) {
        tally->lateContacts += 1u;
        const float overlap = contact - dist;
        if (dist > 0.0f) {
            a->position.x += (overlap * shareA) * (d.x / dist);
            a->position.y += (overlap * shareA) * (d.y / dist);
            b->position.x -= (overlap * shareB) * (d.x / dist);
            b->position.y -= (overlap * shareB) * (d.y / dist);
        } else { /* coincident centres: the lower id to the left */
            a->position.x -= overlap * shareA;
            b->position.x += overlap * shareB;
        }
    }
    a->lastPartner = idB + 1u;
    b->lastPartner = idA + 1u;
}

/* A disk past wall w by more than rounding, moved back towards it. Its
 * velocity component normal to the wall then points into the box, with the
 * magnitude that keeps kinetic plus potential energy what it was: moving out
 * of the wall against gravity costs speed. A disk whose speed cannot pay for
 * the whole way climbs as far as it pays for and rests there, still a little
 * past the wall (gravity cannot press it further: each step it sinks and
 * climbs back as far). Returns whether it was past the wall. */
static inline int carom_put_back(Particle* p, int w, CaromStepParams step)
{
    float gap, speed, accel;
    carom_wall_motion(*p, w, step, &gap, &speed, &accel);
    if (!(gap < -step.tolerance)) return 0;
    const float squared = speed * speed + 2.0f * accel * gap; /* gap < 0: moving out by -gap */
    /* accel > 0 when squared < 0: gravity presses the disk into this wall */
    const float climb = squared >= 0.0f ? -gap : (speed * speed) / (2.0f * accel);
    const float away = squared > 0.0f ? carom_sqrt(squared) : 0.0f;
    const float inward = w % 2 == 0 ? 1.0f : -1.0f; /* the direction into the box */
    if (w < 2) {
        p->position.x += inward * climb;
        p->velocity.x = inward * away;
    } else {
        p->position.y += inward * climb;
        p->velocity.y = inward * away;
    }
    return 1;
}

/* Disk p bounces off wall w at time t: its velocity component normal to the
 * wall reverses (or, past the wall, carom_put_back sets it). The momentum it
 * gives the wall goes to wallImpulse[w]. */
static inline Particle carom_bounce(Particle p, int w, float t, CaromStepParams step, CAROM_GLOBAL ContactTally* tally)
{
    p = carom_fly(p, t, step.gravityX, step.gravityY);
    const float before = w < 2 ? p.velocity.x : p.velocity.y;
    if (carom_put_back(&p, w, step)) {
        tally->lateContacts += 1u;
    } else if (w < 2) {
        p.velocity.x = -p.velocity.x;
    } else {
        p.velocity.y = -p.velocity.y;
    }
    const float after = w < 2 ? p.velocity.x : p.velocity.y;
    const float change = after - before;
    tally->wallImpulse[w] += p.mass * (change > 0.0f ? change : -change);
    p.lastPartner = 0u;
    return p;
}

/* A round's resolve pass, for pending disk k: a wall event is resolved; a
 * pair event is resolved if it is the partner's earliest event too (by the
 * lower id of the two, which writes both disks); an event that is not
 * mutual waits on the next round's pending list. Resolved disks go to
 * `changed`. */
static inline void carom_resolve_event(unsigned int k,
                                       CAROM_GLOBAL Particle* state,
                                       CAROM_GLOBAL const unsigned int* slots,
                                       CAROM_GLOBAL const unsigned int* ids,
                                       CAROM_GLOBAL const CaromEvent* events,
                                       CaromStepParams step,
                                       CAROM_GLOBAL ContactTally* tallies,
                                       CaromList changed,
                                       CaromList nextPending,
                                       unsigned int epoch)
{
    const CaromEvent event = events[k];
    if (event.time == CAROM_NEVER) return;
    if (event.partner >= CAROM_WALL) {
        const unsigned int slot = carom_slot(slots, k);
        state[slot] = carom_bounce(state[slot], (int)(event.partner - CAROM_WALL), event.time, step, &tallies[ids[k]]);
        carom_list_add(changed, k, epoch);
        return;
    }
    const unsigned int q = event.partner;
    if (events[q].partner != k) {
        carom_list_add(nextPending, k, epoch);
        return;
    }
    const unsigned int id = ids[k], otherId = ids[q];
    if (otherId < id) return; /* the partner resolves it */
    const unsigned int slotA = carom_slot(slots, k), slotB = carom_slot(slots, q);
    Particle a = state[slotA], b = state[slotB];
    carom_collide_pair(&a, id, &b, otherId, event.time, step, &tallies[id]);
    state[slotA] = a;
    state[slotB] = b;
    carom_list_add(changed, k, epoch);
    carom_list_add(changed, q, epoch);
}

/* The end of the step: the disk flies to the end; in a periodic box it is
 * wrapped back in (the wraps on its tally), with walls a disk found past one (its contact was not
 * resolved in the rounds) is put back (carom_put_back) as a late contact.
 * Its step time and last partner are cleared for the next step. */
static inline Particle carom_finish_step(Particle p, CaromStepParams step, CAROM_GLOBAL ContactTally* tally)
{
    p = carom_fly(p, step.duration, step.gravityX, step.gravityY);
    if (step.box.periodic) {
        int image[2] = {0, 0};
        p = carom_wrap_position(p, step.box, image);
        carom_record_image(tally, image);
    } else if (p.position.x - p.radius < -step.tolerance || p.position.y - p.radius < -step.tolerance ||
               (step.box.width - p.radius) - p.position.x < -step.tolerance ||
               (step.box.height - p.radius) - p.position.y < -step.tolerance) {
        for (int w = 0; w < 4; ++w) {
            const float before = w < 2 ? p.velocity.x : p.velocity.y;
            if (!carom_put_back(&p, w, step)) continue;
            const float after = w < 2 ? p.velocity.x : p.velocity.y;
            const float change = after - before;
            tally->wallImpulse[w] += p.mass * (change > 0.0f ? change : -change);
            tally->lateContacts += 1u;
        }
    }
    p.time = 0.0f;
    p.lastPartner = 0u;
    return p;
}

#ifndef __OPENCL_VERSION__
} /* namespace carom */
#endif

#endif /* CAROM_PAIRWISE_H */
