// The uniform grid built on an OpenCL device (kernels/grid.cl), for the
// resident pipeline: the state never leaves the device to be sorted into
// cells. It yields the same cells and sortedIndices as the shared host
// builder (engine/grid.h), so the step's results stay bitwise identical.
//
// The particles live in slots: slot s holds particle ids[s]; cellOrder()[k]
// is the slot of particle sortedIndices[k]. Two count arrays alternate: the current one holds the per-cell counts of
// the state the step reads; the step counts its new positions into the next
// one (the fused kernel in kernels/resident.cl), and advance() swaps them.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "backends/opencl/runtime.h"
#include "engine/grid.h"

namespace carom::opencl {

// Whether `device` is known to keep running a work-group once started,
// which the one-pass scan needs (a work-group waits there for those started
// before it). OpenCL promises no progress between work-groups: NVIDIA's and
// AMD's GPUs and CPU devices (PoCL's threads) keep it; Apple's M1 Max and M3
// GPUs are documented not to (Smith, Levien & Owens, SPAA 2025, "Decoupled
// Fallback"), and others are not known to. The environment variable
// CAROM_GRID_SCAN=launches or one-pass overrides the answer (the tests run
// both scans on one device); another value throws Error.
bool keepsWorkGroupsRunning(const DeviceInfo& device);

class DeviceGrid {
public:
    DeviceGrid() = default;
    // Kernels from `program`, buffers for `particleCount` particles; launches
    // are recorded in `profiler` when given. The scan's work-groups, of up
    // to maxScanGroupSize (a power of two), each scan a tile of 16 values per
    // work-item: in one launch where keepsWorkGroupsRunning(device)
    // (scanCountsIntoCells), else in three (scanTiles, scanTileSums,
    // addTileStarts), with the same result (kernels/grid.cl).
    DeviceGrid(cl_context context, const DeviceInfo& device, cl_program program, GridGeometry geometry,
               std::size_t particleCount, Profiler* profiler = nullptr, std::size_t maxScanGroupSize = 512);

    // Whether this grid has `geometry` and buffers for `particleCount`
    // particles or more; then setParticleCount takes it for as many as that.
    bool holds(GridGeometry geometry, std::size_t particleCount) const;
    void setParticleCount(std::size_t particleCount) { particleCount_ = particleCount; }

    // Counts the particles of `state` (slot order) into fresh current counts
    // (after a load).
    void count(cl_command_queue queue, cl_mem state);
    // From the counts and the slots' `ids`: the cells, cellOrder() and
    // `sortedIds` (sortedIndices: ascending id within a cell); zeroes the
    // next counts for the step to count into. Its kernels do nothing once
    // `halt` (two words, kernels/params.h: CAROM_RUNNING while a chunk runs
    // on) says a chunk of steps stopped, and resetScan() must then follow;
    // and only keep the grid's buffers ready for the next build where its
    // second word says that neighbour lists hold. With a Gather (a
    // pairwise step's), the particles of `state` (slot order) are gathered
    // into `gathered` in sorted order, particle sortedIds[k] at k, whose cell
    // cellOf() then holds at k (sortCellSegments).
    struct Gather {
        cl_mem state, gathered;  // {} (null): no gather
    };
    void build(cl_command_queue queue, cl_mem ids, cl_mem sortedIds, cl_mem halt, const Gather& gather = {});
    // Zeroes the scan's status words, which builds that did nothing left as they were.
    void resetScan(cl_command_queue queue);
    // The step has counted the new state into the next counts: make them current.
    void advance() { std::swap(counts_, nextCounts_); }
    // The current grid, read back (for tests and diagnostics). Call after
    // build(), with its `sortedIds`.
    Grid read(cl_command_queue queue, cl_mem sortedIds) const;
    std::size_t scanTiles() const { return tileLength_ > 0 ? tiles(cellCount_) : 0; }
    std::size_t cellCount() const { return cellCount_; }

    // The largest power-of-two work-group of at most maxGroupSize and
    // kernelLimit work-items whose scan tile of `items` values per work-item,
    // with otherBytesPerItem more local memory per work-item, fits the
    // device's local memory; and the local memory its scan takes: the tile
    // (padded by one word in 32: carom_padded) and a run sum per work-item
    // (kernels/grid.cl, carom_scan_tile).
    static constexpr std::size_t kScanItems = 16;  // values per work-item in a tile: CAROM_SCAN_ITEMS
    static std::size_t scanGroupSize(const DeviceInfo& device, std::size_t kernelLimit, std::size_t maxGroupSize,
                                     std::size_t items, std::size_t otherBytesPerItem = 0);
    static std::size_t scanTileBytes(std::size_t groupSize, std::size_t items);
    static std::size_t scanRunBytes(std::size_t groupSize) { return groupSize * sizeof(cl_uint); }

    cl_mem cells() const { return cells_.get(); }
    cl_mem counts() const { return counts_.get(); }
    cl_mem nextCounts() const { return nextCounts_.get(); }
    cl_mem cellOrder() const { return cellOrder_.get(); }
    cl_mem cellOf() const { return cellOf_.get(); }
    cl_mem rankInCell() const { return rankInCell_.get(); }
    // The scan status the next build starts from: 1 + scanTiles() words, all
    // zero between builds (the build before zeroed them); the tiles' sums
    // when the scan runs in launches.
    cl_mem scanStatus() const { return scanStatus_.get(); }

private:
    std::size_t tiles(std::size_t n) const { return (n + tileLength_ - 1) / tileLength_; }
    void scanInOnePass(cl_command_queue queue, cl_mem halt);
    void scanInLaunches(cl_command_queue queue, cl_mem halt);

    GridGeometry geometry_{};
    std::size_t particleCount_ = 0;
    std::size_t room_ = 0;  // particles the buffers hold
    Profiler* profiler_ = nullptr;
    std::size_t groupSize_ = 0;       // for the one-item-per-particle/cell kernels
    std::size_t scanGroupSize_ = 64;  // a power of two
    std::size_t tileLength_ = 0;      // values per scan work-group
    std::size_t cellCount_ = 0;

    bool onePassScan_ = true;  // keepsWorkGroupsRunning
    // scanKernel_ is scanCountsIntoCells, or scanTiles before the other two.
    Kernel countKernel_, scanKernel_, scatterKernel_, sortKernel_, scanTileSumsKernel_, addTileStartsKernel_;
    Buffer counts_, nextCounts_, cells_, cellOrder_, cellOf_, rankInCell_;  // cellOrder_: slots
    // The scan's ticket and tile words (scanCountsIntoCells): the current
    // one zero before each build, which zeroes the other and swaps them.
    // The scan in launches keeps the tiles' sums in scanStatus_.
    Buffer scanStatus_, nextScanStatus_;
};

}  // namespace carom::opencl
