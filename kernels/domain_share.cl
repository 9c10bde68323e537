/* A process's share of a decomposed world kept on its device
 * (backends/opencl/domain_share.h), so that only the halo's copies and the
 * disks handed on cross the bus.
 *
 * The held share is in id order: slot k holds particles[k], tallies[k],
 * images[k] and ids[k] (the disk's id in the whole world), and own[k] is 1
 * for a disk of this process's domain, 0 for a copy of another's or a disk
 * handed on. The next share merges the own disks with those that arrived and
 * the new copies (both uploaded, by id): a disk's slot is its place among its
 * kind plus the disks of the other two kinds with lower ids. Its place among
 * the own disks is an exclusive prefix sum of `own` (scanOwnTiles, then the
 * grid build's scanTileSums); the others are counted by bisection.
 *
 * Lists of slots (leavers, near disks) are filled by atomic_inc in any
 * order: the host sorts what it receives by id, so the order changes no
 * result. */
#ifndef CAROM_DOMAIN_SHARE_CL
#define CAROM_DOMAIN_SHARE_CL
#include "grid.cl"

/* How many of sorted[0..count) are below `id`. */
static inline uint carom_count_below(__global const uint* sorted, uint count, uint id)
{
    uint low = 0, high = count;
    while (low < high) {
        const uint middle = low + (high - low) / 2;
        if (sorted[middle] < id)
            low = middle + 1;
        else
            high = middle;
    }
    return low;
}

/* The process whose domain holds `position` (DomainMap::ownerOf). */
static inline int carom_owner_of(float2 position,
                                 GridGeometry grid,
                                 __global const int* domainOfColumn,
                                 __global const int* domainOfRow,
                                 int domainsX)
{
    return domainOfRow[carom_cell_coord(position.y, grid.cellsPerLengthY, grid.rows)] * domainsX +
           domainOfColumn[carom_cell_coord(position.x, grid.cellsPerLengthX, grid.cols)];
}

/* Appends `slot` to list[1..]; list[0] counts. */
static inline void carom_list_slot(__global uint* list, uint slot)
{
    list[1 + atomic_inc(&list[0])] = slot;
}

/* rank[k]: the own disks before slot k within its tile; tileSums[tile]: the
 * tile's own disks. */
__kernel void scanOwnTiles(__global const uint* own,
                           uint count,
                           __global uint* rank,
                           __global uint* tileSums,
                           __local uint* tile,
                           __local uint* runSums)
{
    const uint size = get_local_size(0);
    const uint tileLength = size * CAROM_SCAN_ITEMS;
    const uint first = get_group_id(0) * tileLength;
    const uint total = carom_scan_tile(own, count, first, CAROM_SCAN_ITEMS, tile, runSums);
    if (get_local_id(0) == 0) tileSums[get_group_id(0)] = total;
    for (uint k = get_local_id(0); k < tileLength && first + k < count; k += size)
        rank[first + k] = tile[carom_padded(k)];
}

/* The own disks before slot `slot` of the held share (ownTotal past its end). */
static inline uint carom_own_before(
    uint slot, uint count, __global const uint* rank, __global const uint* tileStarts, uint tileLength, uint ownTotal)
{
    return slot < count ? tileStarts[slot / tileLength] + rank[slot] : ownTotal;
}

/* Each own disk of the held share into its slot of the next. */
__kernel void mergeOwn(__global const Particle* particles,
                       __global const ContactTally* tallies,
                       __global const int2* images,
                       __global const uint* ids,
                       __global const uint* own,
                       uint count,
                       __global const uint* rank,
                       __global const uint* tileStarts,
                       uint tileLength,
                       __global const uint* incomingIds,
                       uint arrived,
                       uint copies,
                       __global Particle* nextParticles,
                       __global ContactTally* nextTallies,
                       __global int2* nextImages,
                       __global uint* nextIds,
                       __global uint* nextOwn)
{
    const uint k = get_global_id(0);
    if (k >= count || !own[k]) return;
    const uint id = ids[k];
    const uint s = tileStarts[k / tileLength] + rank[k] + carom_count_below(incomingIds, arrived, id) +
                   carom_count_below(incomingIds + arrived, copies, id);
    nextParticles[s] = particles[k];
    nextTallies[s] = tallies[k];
    nextImages[s] = images[k];
    nextIds[s] = id;
    nextOwn[s] = 1u;
}

/* Each incoming disk into its slot of the next share: incomingIds[0..arrived)
 * the disks handed to this process (with their tallies and images), then
 * `copies` copies of the others' disks (with none). */
__kernel void placeIncoming(__global const Particle* incoming,
                            __global const ContactTally* incomingTallies,
                            __global const int2* incomingImages,
                            __global const uint* incomingIds,
                            uint arrived,
                            uint copies,
                            __global const uint* ids,
                            uint count,
                            __global const uint* rank,
                            __global const uint* tileStarts,
                            uint tileLength,
                            uint ownTotal,
                            __global Particle* nextParticles,
                            __global ContactTally* nextTallies,
                            __global int2* nextImages,
                            __global uint* nextIds,
                            __global uint* nextOwn)
{
    const uint j = get_global_id(0);
    if (j >= arrived + copies) return;
    const uint id = incomingIds[j];
    const uint ownBefore =
        carom_own_before(carom_count_below(ids, count, id), count, rank, tileStarts, tileLength, ownTotal);
    const int came = j < arrived;
    const uint s =
        (came ? j : j - arrived) + ownBefore +
        (came ? carom_count_below(incomingIds + arrived, copies, id) : carom_count_below(incomingIds, arrived, id));
    nextParticles[s] = incoming[j];
    ContactTally none = {0};
    nextTallies[s] = came ? incomingTallies[j] : none;
    nextImages[s] = came ? incomingImages[j] : (int2)(0, 0);
    nextIds[s] = id;
    nextOwn[s] = came ? 1u : 0u;
}

/* The stepped share, in the engine's slots (slot s holds share disk
 * slotIds[s]), into id order; for its own disks, the last round that
 * changed one (changed marks by slot above `epoch`; none without marks) into
 * record[0] and the lowest id of one left non-finite into record[1]. */
__kernel void keepStepped(__global const Particle* state,
                          __global const uint* slotIds,
                          uint count,
                          __global const uint* lists,
                          uint marksWord,
                          uint epoch,
                          __global const uint* ids,
                          __global const uint* own,
                          __global Particle* held,
                          __global uint* record)
{
    const uint s = get_global_id(0);
    if (s >= count) return;
    const uint k = slotIds[s];
    const Particle p = state[s];
    held[k] = p;
    if (!own[k]) return;
    if (lists) {
        const uint mark = lists[marksWord + s];
        if (mark > epoch) atomic_max(&record[0], mark - epoch);
    }
    if (!carom_is_finite(p)) atomic_min(&record[1], ids[k]);
}

/* Lists the own disks whose centre left this process's domain (`rank`) and
 * makes them not own. */
__kernel void findLeavers(__global const Particle* particles,
                          __global uint* own,
                          uint count,
                          GridGeometry grid,
                          __global const int* domainOfColumn,
                          __global const int* domainOfRow,
                          int domainsX,
                          int rank,
                          __global uint* list)
{
    const uint k = get_global_id(0);
    if (k >= count || !own[k]) return;
    if (carom_owner_of(particles[k].position, grid, domainOfColumn, domainOfRow, domainsX) == rank) return;
    own[k] = 0u;
    carom_list_slot(list, k);
}

/* Lists the own disks in a cell whose column or row is marked near
 * another domain. */
__kernel void findNear(__global const Particle* particles,
                       __global const uint* own,
                       uint count,
                       GridGeometry grid,
                       __global const uchar* nearColumn,
                       __global const uchar* nearRow,
                       __global uint* list)
{
    const uint k = get_global_id(0);
    if (k >= count || !own[k]) return;
    const float2 at = particles[k].position;
    if (nearColumn[carom_cell_coord(at.x, grid.cellsPerLengthX, grid.cols)] ||
        nearRow[carom_cell_coord(at.y, grid.cellsPerLengthY, grid.rows)])
        carom_list_slot(list, k);
}

/* The listed slots' disks, packed: ids and particles, and where `outTallies`
 * is not null their tallies and images too. */
__kernel void packListed(__global const uint* list,
                         uint listed,
                         __global const Particle* particles,
                         __global const ContactTally* tallies,
                         __global const int2* images,
                         __global const uint* ids,
                         __global uint* outIds,
                         __global Particle* outParticles,
                         __global ContactTally* outTallies,
                         __global int2* outImages)
{
    const uint j = get_global_id(0);
    if (j >= listed) return;
    const uint k = list[1 + j];
    outIds[j] = ids[k];
    outParticles[j] = particles[k];
    if (!outTallies) return;
    outTallies[j] = tallies[k];
    outImages[j] = images[k];
}

/* The largest v.x^2 + v.y^2 of the own disks, as the bits of a float (which
 * order as unsigned integers where it is not negative); NaN is passed over,
 * as the host's max passes it over. */
__kernel void ownMaxSpeedSquared(__global const Particle* particles,
                                 __global const uint* own,
                                 uint count,
                                 __global uint* largest)
{
    const uint k = get_global_id(0);
    if (k >= count || !own[k]) return;
    const float speedSquared = carom_speed_squared(particles[k]);
    if (speedSquared == speedSquared) atomic_max(largest, as_uint(speedSquared));
}

/* Adds the own disks' wraps to their images (modulo 2^32, as addToImage)
 * and zeroes every tally. */
__kernel void clearShareTallies(__global ContactTally* tallies,
                                __global int2* images,
                                __global const uint* own,
                                uint count)
{
    const uint k = get_global_id(0);
    if (k >= count) return;
    if (own[k]) {
        const int2 image = images[k];
        images[k] =
            (int2)((int)((uint)image.x + (uint)tallies[k].image[0]), (int)((uint)image.y + (uint)tallies[k].image[1]));
    }
    ContactTally none = {0};
    tallies[k] = none;
}
#endif /* CAROM_DOMAIN_SHARE_CL */
