/* The grid built on the device, for the resident pipeline: the same cells and
 * the same sortedIndices as the shared host builder (engine/grid.cpp).
 *
 * The pipeline stores its particles in slots: slot s holds particle ids[s],
 * in the cell order of the step before (so neighbours sit close together in
 * memory, however far apart their ids are). cellOrder[k] is the slot of
 * particle sortedIndices[k].
 *
 *   countCells           the cell of each slot's particle, and its arrival
 *                        rank in that cell (atomic_inc on the cell's count)
 *   scanCountsIntoCells  exclusive prefix sum of the counts into the cells'
 *                        starts in one pass: each work-group scans a tile
 *                        and adds the sum of the tiles before it, which it
 *                        learns from them as they finish (decoupled look-back);
 *                        or, where a work-group may not wait for another,
 *                        in three launches (scanTiles, scanTileSums,
 *                        addTileStarts)
 *   scatterToCells       each slot, and its id, to start + rank of its cell
 *   sortCellSegments     each cell's slots and ids into ascending id: the ids
 *                        are then sortedIndices (for a pairwise step it
 *                        can also gather the particles into that order)
 *
 * Arrival ranks depend on thread scheduling; sorting each cell's few slots by
 * id makes the result deterministic and equal to the host's ascending-id
 * scatter.
 * Only OpenCL C 1.2 core features: 32-bit global atomics, local memory,
 * barriers. */
#ifndef CAROM_GRID_CL
#define CAROM_GRID_CL
#include "physics.h"

/* Values each work-item scans in a tile of the grid build's scan kernels; a
 * tile is get_local_size(0) times this. The host sizes the local buffers to
 * match (backends/opencl/grid.cpp). */
#define CAROM_SCAN_ITEMS 16

/* Counts the particle in slot i into its cell. `counts` must start at zero.
 * A disk whose position is not finite (the state blew up; the host stops at
 * its next wait for the device) goes to a cell by its slot: in cell 0, where
 * carom_cell_index puts NaN, such disks would be searched against each other
 * and sorted one by one, and the steps until that wait would cost N^2. */
static inline void carom_count_into_cell(
    uint i, float2 position, GridGeometry grid, __global uint* counts, __global uint* cellOf, __global uint* rankInCell)
{
    const uint cell = carom_isfinite(position.x) && carom_isfinite(position.y) ? (uint)carom_cell_index(position, grid)
                                                                               : i % (uint)(grid.cols * grid.rows);
    cellOf[i] = cell;
    rankInCell[i] = atomic_inc(&counts[cell]);
}

__kernel void countCells(__global const Particle* particles,
                         uint count,
                         GridGeometry grid,
                         __global uint* counts,
                         __global uint* cellOf,
                         __global uint* rankInCell)
{
    const uint i = get_global_id(0);
    if (i >= count) return;
    carom_count_into_cell(i, particles[i].position, grid, counts, cellOf, rankInCell);
}

/* Where tile value k lives in local memory: one word of padding every 32
 * puts the runs of neighbouring work-items in different memory banks. */
static inline uint carom_padded(uint k)
{
    return k + k / 32;
}

/* The exclusive prefix sum of the tile of `values` (n in all) that starts at
 * `first`, `items` values per work-item, left in `tile` (padded); returns
 * the tile's total. The local size must be a power of two. */
static inline uint carom_scan_tile(
    __global const uint* values, uint n, uint first, uint items, __local uint* tile, __local uint* runSums)
{
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    /* `items` loads a work-item, counted so that the compiler can unroll
     * them and have them in flight at once, rather than wait for each. */
    for (uint j = 0; j < items; ++j) {
        const uint k = lid + j * size;
        tile[carom_padded(k)] = first + k < n ? values[first + k] : 0u;
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    /* Each work-item owns a run of `items` consecutive values. */
    const uint runStart = lid * items;
    uint run = 0;
    for (uint k = 0; k < items; ++k) run += tile[carom_padded(runStart + k)];
    runSums[lid] = run;
    barrier(CLK_LOCAL_MEM_FENCE);

    /* Inclusive scan of the run sums (Hillis-Steele). */
    for (uint offset = 1; offset < size; offset <<= 1) {
        const uint before = lid >= offset ? runSums[lid - offset] : 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        runSums[lid] += before;
        barrier(CLK_LOCAL_MEM_FENCE);
    }

    uint prefix = runSums[lid] - run;
    for (uint k = 0; k < items; ++k) {
        const uint at = carom_padded(runStart + k);
        const uint value = tile[at];
        tile[at] = prefix;
        prefix += value;
    }
    const uint total = runSums[size - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
    return total;
}

/* The cells of the tile that starts at `first`, scanned into `tile`
 * (carom_scan_tile, which returned `total`): starts after `before`. */
static inline void carom_tile_cells(
    uint first, uint n, uint before, uint total, __local const uint* tile, __global GridCell* cells)
{
    const uint size = get_local_size(0);
    const uint tileLength = size * CAROM_SCAN_ITEMS;
    for (uint k = get_local_id(0); k < tileLength && first + k < n; k += size) {
        GridCell cell;
        cell.start = before + tile[carom_padded(k)];
        cell.count = (k + 1 < tileLength ? tile[carom_padded(k + 1)] : total) - tile[carom_padded(k)];
        cells[first + k] = cell;
    }
}

/* A tile's word in the scan's status (scanCountsIntoCells): 0 until the tile
 * publishes; then a flag and a value of 30 bits (a sum of particles, at
 * most kMaxParticles = 10^9 < 2^30). */
#define CAROM_TILE_TOTAL 0x40000000u  /* the value is the tile's own total */
#define CAROM_TILE_PREFIX 0x80000000u /* the value is the sum of this tile and every tile before it */
#define CAROM_TILE_VALUE 0x3FFFFFFFu

/* Each cell's start and count, in one pass. A work-group takes the next tile
 * in the order work-groups start (a ticket in status[0]), scans it, publishes
 * its total in status[1 + tile], and adds up the published words of the tiles
 * before it, back to the first that holds a prefix; then it publishes its own
 * prefix. It waits only for tiles whose work-groups started before it: OpenCL
 * 1.2 promises no progress between work-groups, so the host runs this only on
 * devices known to keep a started work-group running (DeviceGrid), and the
 * scan in launches elsewhere. The
 * words are read and written with atomics, so a word is seen whole. `status` must be zero on entry; the kernel
 * zeroes `nextStatus`, which the next build passes as its status. */
__kernel void scanCountsIntoCells(__global const uint* halt,
                                  __global const uint* counts,
                                  uint n,
                                  __global GridCell* cells,
                                  __global uint* status,
                                  __global uint* nextStatus,
                                  __local uint* tile,
                                  __local uint* runSums)
{
    if (CAROM_HALTED(halt)) return;
    __local uint tileIndex, before;
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    if (CAROM_GRID_SKIPPED(halt)) { /* `status` stays zero; `nextStatus` is zeroed all the same */
        if (lid == 0) nextStatus[1 + get_group_id(0)] = 0u;
        if (get_global_id(0) == 0) nextStatus[0] = 0u;
        return;
    }
    if (lid == 0) tileIndex = atomic_inc(&status[0]);
    barrier(CLK_LOCAL_MEM_FENCE);
    const uint t = tileIndex;
    const uint tileLength = size * CAROM_SCAN_ITEMS;
    const uint first = t * tileLength;
    const uint total = carom_scan_tile(counts, n, first, CAROM_SCAN_ITEMS, tile, runSums);
    if (lid == 0) {
        nextStatus[1 + t] = 0u;
        if (t == 0) nextStatus[0] = 0u;
        uint prefix = 0u;
        if (t > 0) {
            atomic_xchg(&status[1 + t], CAROM_TILE_TOTAL | total);
            for (uint j = t; j-- > 0;) {
                uint word;
                do word = atomic_or(&status[1 + j], 0u);
                while (word == 0u);
                prefix += word & CAROM_TILE_VALUE;
                if (word & CAROM_TILE_PREFIX) break;
            }
        }
        atomic_xchg(&status[1 + t], CAROM_TILE_PREFIX | (prefix + total));
        before = prefix;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    carom_tile_cells(first, n, before, total, tile, cells);
}

/* The scan in three launches, for devices not known to keep a started
 * work-group running while another waits for it (Apple's GPUs among them):
 * no work-group waits for another. scanTiles scans each tile into its
 * cells' starts within the tile and its total into tileSums[tile];
 * scanTileSums, one work-group, turns the totals into the tiles' starts;
 * addTileStarts adds them. The cells are those of scanCountsIntoCells. */
__kernel void scanTiles(__global const uint* halt,
                        __global const uint* counts,
                        uint n,
                        __global GridCell* cells,
                        __global uint* tileSums,
                        __local uint* tile,
                        __local uint* runSums)
{
    if (CAROM_HALTED(halt) || CAROM_GRID_SKIPPED(halt)) return;
    const uint first = get_group_id(0) * get_local_size(0) * CAROM_SCAN_ITEMS;
    const uint total = carom_scan_tile(counts, n, first, CAROM_SCAN_ITEMS, tile, runSums);
    if (get_local_id(0) == 0) tileSums[get_group_id(0)] = total;
    carom_tile_cells(first, n, 0u, total, tile, cells);
}

/* The exclusive prefix sum of tileSums[0..tiles), in place, by one work-group. */
__kernel void scanTileSums(
    __global const uint* halt, __global uint* tileSums, uint tiles, __local uint* tile, __local uint* runSums)
{
    if (CAROM_HALTED(halt) || CAROM_GRID_SKIPPED(halt)) return;
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    const uint tileLength = size * CAROM_SCAN_ITEMS;
    uint before = 0;
    for (uint first = 0; first < tiles; first += tileLength) {
        const uint total = carom_scan_tile(tileSums, tiles, first, CAROM_SCAN_ITEMS, tile, runSums);
        for (uint k = lid; k < tileLength && first + k < tiles; k += size)
            tileSums[first + k] = before + tile[carom_padded(k)];
        before += total;
        barrier(CLK_LOCAL_MEM_FENCE); /* the next tile overwrites this one */
    }
}

__kernel void addTileStarts(
    __global const uint* halt, __global GridCell* cells, uint n, __global const uint* tileStarts, uint tileLength)
{
    if (CAROM_HALTED(halt) || CAROM_GRID_SKIPPED(halt)) return;
    const uint c = get_global_id(0);
    if (c >= n) return;
    cells[c].start += tileStarts[c / tileLength];
}

/* Slot `slot` to the start of its cell plus its arrival rank, with its id:
 * the id is read here, in slot order, rather than gathered by the sort. */
static inline void carom_scatter_slot(uint slot,
                                      uint cellStart,
                                      __global const uint* rankInCell,
                                      __global const uint* ids,
                                      __global uint* cellOrder,
                                      __global uint* sortedIds)
{
    const uint at = cellStart + rankInCell[slot];
    cellOrder[at] = slot;
    sortedIds[at] = ids[slot];
}

__kernel void scatterToCells(__global const uint* halt,
                             __global const uint* cellOf,
                             __global const uint* rankInCell,
                             __global const GridCell* cells,
                             uint count,
                             __global const uint* ids,
                             __global uint* cellOrder,
                             __global uint* sortedIds)
{
    if (CAROM_HALTED(halt)) return;
    const uint slot = get_global_id(0);
    if (slot >= count) return;
    if (CAROM_GRID_SKIPPED(halt)) { /* the state keeps its order: each slot its own position */
        cellOrder[slot] = slot;
        sortedIds[slot] = ids[slot];
        return;
    }
    carom_scatter_slot(slot, cells[cellOf[slot]].start, rankInCell, ids, cellOrder, sortedIds);
}

/* Sorts a cell's slots and ids, as scattered in arrival order, into ascending
 * id (insertion sort: a cell is about one diameter wide, so it holds a
 * handful of disks; most hold none or one, which costs no write). */
static inline void carom_sort_cell(GridCell cell, __global uint* cellOrder, __global uint* sortedIds)
{
    __global uint* slots = cellOrder + cell.start;
    __global uint* sorted = sortedIds + cell.start;
    for (uint a = 1; a < cell.count; ++a) {
        const uint slot = slots[a];
        const uint id = sorted[a];
        uint b = a;
        for (; b > 0 && sorted[b - 1] > id; --b) {
            slots[b] = slots[b - 1];
            sorted[b] = sorted[b - 1];
        }
        if (b == a) continue;
        slots[b] = slot;
        sorted[b] = id;
    }
}

/* Per cell: zeroes the cell's count in `nextCounts`, which the step counts
 * the new positions into; sorts the cell's slots and ids by id: sortedIds is
 * then sortedIndices. Where `gathered` is not null (a pairwise step's), the
 * cell's particles are then gathered from their slots in `state` into
 * `gathered` in sorted order, and their cell into cellOf[k], k being the
 * sorted position: the step's searches then read a neighbour without looking
 * up its slot (kernels/pairwise.h, carom_slot). cellOf was by slot until
 * here; the scatter, its last reader so, ran before. */
__kernel void sortCellSegments(__global const uint* halt,
                               __global const GridCell* cells,
                               uint cellCount,
                               __global uint* cellOrder,
                               __global uint* sortedIds,
                               __global uint* nextCounts,
                               __global const Particle* state,
                               __global Particle* gathered,
                               __global uint* cellOf)
{
    if (CAROM_HALTED(halt)) return;
    const uint c = get_global_id(0);
    if (c >= cellCount) return;
    nextCounts[c] = 0u;
    if (CAROM_GRID_SKIPPED(halt)) return; /* never with a gather (OpenClResidentBackend) */
    const GridCell cell = cells[c];
    carom_sort_cell(cell, cellOrder, sortedIds);
    if (!gathered) return;
    for (uint k = cell.start; k < cell.start + cell.count; ++k) {
        gathered[k] = state[cellOrder[k]];
        cellOf[k] = c;
    }
}
#endif /* CAROM_GRID_CL */
