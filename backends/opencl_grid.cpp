#include "backends/opencl_grid.h"

#include <algorithm>
#include <limits>

namespace carom::opencl {
namespace {

// Values per work-item in a scan tile: CAROM_SCAN_ITEMS in kernels/grid.cl.
constexpr std::size_t kScanItems = 16;

// The work-group of the kernels that take one particle or one cell per
// work-item (at most; the kernels' own limit may be lower). Each work-item
// does a few loads and stores; on an H200, 256 rather than 64 made a
// simultaneous step 7-9 % faster at 10^6 and 1.6*10^7 disks (and faster from
// 10^4 up), a pairwise one 1-4 % at those sizes and no different below, and
// on PoCL a simultaneous step at 10^5 11-14 % faster, the rest within noise
// (bench/results/nvidia-h200-grid-groups.txt).
constexpr std::size_t kGridGroupSize = 256;

// The largest power of two <= limit (limit >= 1).
std::size_t powerOfTwoAtMost(std::size_t limit) {
    std::size_t p = 1;
    while (p * 2 <= limit) p *= 2;
    return p;
}

}  // namespace

std::size_t DeviceGrid::scanTileBytes(std::size_t groupSize, std::size_t items) {
    const std::size_t tileLength = groupSize * items;
    return (tileLength + tileLength / 32) * sizeof(cl_uint);
}

std::size_t DeviceGrid::scanGroupSize(const DeviceInfo& device, std::size_t kernelLimit, std::size_t maxGroupSize,
                                      std::size_t items, std::size_t otherBytesPerItem) {
    std::size_t group = powerOfTwoAtMost(std::min(maxGroupSize, kernelLimit));
    while (group > 1 &&
           scanTileBytes(group, items) + scanRunBytes(group) + group * otherBytesPerItem > device.localMemoryBytes)
        group /= 2;
    return group;
}

DeviceGrid::DeviceGrid(cl_context context, const DeviceInfo& device, cl_program program, GridGeometry geometry,
                       std::size_t particleCount, Profiler* profiler, std::size_t maxScanGroupSize)
    : geometry_(geometry), particleCount_(particleCount), profiler_(profiler) {
    const std::size_t cellCount = std::size_t(geometry.cols) * geometry.rows;
    if (cellCount >= std::numeric_limits<cl_uint>::max())
        throw Error("the resident pipeline supports fewer than 2^32 grid cells, this scene needs " +
                    std::to_string(cellCount) +
                    "; use the host-grid pipeline (ComputeEngine::OpenClHostGrid, --pipeline seed)");

    countKernel_ = createKernel(program, "countCells");
    scanCountsKernel_ = createKernel(program, "scanCountsIntoCells");
    scanKernel_ = createKernel(program, "scanTiles");
    addOffsetsKernel_ = createKernel(program, "addTileOffsets");
    scatterKernel_ = createKernel(program, "scatterToCells");
    sortKernel_ = createKernel(program, "sortCellSegments");
    groupSize_ = kGridGroupSize;
    for (cl_kernel k : {countKernel_.get(), addOffsetsKernel_.get(), scatterKernel_.get(), sortKernel_.get()})
        groupSize_ = std::min(groupSize_, kernelWorkGroupLimit(k, device.id));
    const std::size_t scanLimit = std::min(kernelWorkGroupLimit(scanCountsKernel_.get(), device.id),
                                           kernelWorkGroupLimit(scanKernel_.get(), device.id));
    scanGroupSize_ = scanGroupSize(device, scanLimit, maxScanGroupSize, kScanItems);
    tileLength_ = scanGroupSize_ * kScanItems;

    counts_ = createBuffer(context, cellCount * sizeof(cl_uint), "cell counts");
    nextCounts_ = createBuffer(context, cellCount * sizeof(cl_uint), "next cell counts");
    cells_ = createBuffer(context, cellCount * sizeof(GridCell), "grid cells");
    cellOrder_ = createBuffer(context, particleCount * sizeof(cl_uint), "slots in cell order");
    cellOf_ = createBuffer(context, particleCount * sizeof(cl_uint), "cell of each particle");
    rankInCell_ = createBuffer(context, particleCount * sizeof(cl_uint), "rank in cell");
    zeroOffset_ = createBuffer(context, sizeof(cl_uint), "zero tile offset");
    levelSizes_.push_back(cellCount);
    while (levelSizes_.back() > tileLength_) levelSizes_.push_back(tiles(levelSizes_.back()));
    for (std::size_t size : levelSizes_)
        tileSums_.push_back(createBuffer(context, tiles(size) * sizeof(cl_uint), "scan tile sums"));
}

void DeviceGrid::count(cl_command_queue queue, cl_mem state) {
    enqueueZero(queue, zeroOffset_.get(), sizeof(cl_uint), "zero tile offset");
    enqueueZero(queue, counts_.get(), levelSizes_[0] * sizeof(cl_uint), "cell counts");
    setKernelArgs(countKernel_.get(), state, cl_uint(particleCount_), geometry_, counts_.get(), cellOf_.get(),
                  rankInCell_.get());
    enqueue1d(queue, countKernel_.get(), particleCount_, groupSize_, "countCells", profiler_);
}

void DeviceGrid::build(cl_command_queue queue, cl_mem ids, cl_mem sortedIds) {
    scanCellCounts(queue);
    const cl_uint tileLength = cl_uint(tileLength_);
    setKernelArgs(scatterKernel_.get(), cellOf_.get(), rankInCell_.get(), cells_.get(), cellTileOffsets(), tileLength,
                  cl_uint(particleCount_), ids, cellOrder_.get(), sortedIds);
    enqueue1d(queue, scatterKernel_.get(), particleCount_, groupSize_, "scatterToCells", profiler_);
    const cl_uint cellCount = cl_uint(levelSizes_[0]);
    setKernelArgs(sortKernel_.get(), cells_.get(), cellTileOffsets(), tileLength, cellCount, cellOrder_.get(),
                  sortedIds, nextCounts_.get());
    enqueue1d(queue, sortKernel_.get(), cellCount, groupSize_, "sortCellSegments", profiler_);
}

// Scans the counts into the cells and every level of tile sums upwards (each
// tile's total lands in the level above), then adds the scanned tile sums
// back downwards to level 1: scatterToCells and sortCellSegments add level 0's.
void DeviceGrid::scanCellCounts(cl_command_queue queue) {
    const std::size_t tileBytes = scanTileBytes(scanGroupSize_, kScanItems), runBytes = scanRunBytes(scanGroupSize_);
    setKernelArgs(scanCountsKernel_.get(), counts_.get(), cl_uint(levelSizes_[0]), cells_.get(), tileSums_[0].get());
    setLocalArg(scanCountsKernel_.get(), 4, tileBytes);
    setLocalArg(scanCountsKernel_.get(), 5, runBytes);
    enqueue1d(queue, scanCountsKernel_.get(), tiles(levelSizes_[0]) * scanGroupSize_, scanGroupSize_,
              "scanCountsIntoCells", profiler_);
    for (std::size_t level = 1; level < levelSizes_.size(); ++level) {
        setKernelArgs(scanKernel_.get(), tileSums_[level - 1].get(), cl_uint(levelSizes_[level]),
                      tileSums_[level].get());
        setLocalArg(scanKernel_.get(), 3, tileBytes);
        setLocalArg(scanKernel_.get(), 4, runBytes);
        enqueue1d(queue, scanKernel_.get(), tiles(levelSizes_[level]) * scanGroupSize_, scanGroupSize_, "scanTiles",
                  profiler_);
    }
    for (std::size_t level = levelSizes_.size() - 1; level-- > 1;) {
        setKernelArgs(addOffsetsKernel_.get(), tileSums_[level - 1].get(), cl_uint(levelSizes_[level]),
                      cl_uint(tileLength_), tileSums_[level].get());
        enqueue1d(queue, addOffsetsKernel_.get(), levelSizes_[level], groupSize_, "addTileOffsets", profiler_);
    }
}

Grid DeviceGrid::read(cl_command_queue queue, cl_mem sortedIds) const {
    Grid grid;
    grid.geometry = geometry_;
    grid.cells.resize(levelSizes_[0]);
    grid.sortedIndices.resize(particleCount_);
    check(clEnqueueReadBuffer(queue, cells_.get(), CL_TRUE, 0, grid.cells.size() * sizeof(GridCell), grid.cells.data(),
                              0, nullptr, nullptr),
          "clEnqueueReadBuffer(grid cells)");
    check(clEnqueueReadBuffer(queue, sortedIds, CL_TRUE, 0, particleCount_ * sizeof(cl_uint), grid.sortedIndices.data(),
                              0, nullptr, nullptr),
          "clEnqueueReadBuffer(sorted indices)");
    return grid;
}

}  // namespace carom::opencl
