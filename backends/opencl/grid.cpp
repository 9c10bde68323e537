#include "backends/opencl/grid.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>

namespace carom::opencl {
namespace {

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

bool keepsWorkGroupsRunning(const DeviceInfo& device) {
    return forcedChoice("CAROM_GRID_SCAN", "one-pass", "launches",
                        device.type == "CPU" || device.platformName.find("NVIDIA") != std::string::npos ||
                            device.platformName.find("AMD") != std::string::npos);
}

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
    : geometry_(geometry), particleCount_(particleCount), room_(particleCount), profiler_(profiler) {
    const std::size_t cellCount = std::size_t(geometry.cols) * geometry.rows;
    if (cellCount >= std::numeric_limits<cl_uint>::max())
        throw Error("the resident pipeline supports fewer than 2^32 grid cells, this scene needs " +
                    std::to_string(cellCount) +
                    "; use the host-grid pipeline (ComputeEngine::OpenClHostGrid, --pipeline host-grid)");

    // The scan publishes sums of particles in 30 bits (scanCountsIntoCells).
    if (particleCount >= (std::size_t(1) << 30))
        throw Error("the device grid holds fewer than 2^30 disks, got " + std::to_string(particleCount));

    countKernel_ = createKernel(program, "countCells");
    onePassScan_ = keepsWorkGroupsRunning(device);
    scanKernel_ = createKernel(program, onePassScan_ ? "scanCountsIntoCells" : "scanTiles");
    if (!onePassScan_) {
        scanTileSumsKernel_ = createKernel(program, "scanTileSums");
        addTileStartsKernel_ = createKernel(program, "addTileStarts");
    }
    scatterKernel_ = createKernel(program, "scatterToCells");
    sortKernel_ = createKernel(program, "sortCellSegments");
    groupSize_ = kGridGroupSize;
    for (cl_kernel k : {countKernel_.get(), scatterKernel_.get(), sortKernel_.get()})
        groupSize_ = std::min(groupSize_, kernelWorkGroupLimit(k, device.id));
    std::size_t scanLimit = kernelWorkGroupLimit(scanKernel_.get(), device.id);
    if (!onePassScan_) {
        scanLimit = std::min(scanLimit, kernelWorkGroupLimit(scanTileSumsKernel_.get(), device.id));
        groupSize_ = std::min(groupSize_, kernelWorkGroupLimit(addTileStartsKernel_.get(), device.id));
    }
    scanGroupSize_ = scanGroupSize(device, scanLimit, maxScanGroupSize, kScanItems);
    tileLength_ = scanGroupSize_ * kScanItems;

    counts_ = createBuffer(context, cellCount * sizeof(cl_uint), "cell counts");
    nextCounts_ = createBuffer(context, cellCount * sizeof(cl_uint), "next cell counts");
    cells_ = createBuffer(context, cellCount * sizeof(GridCell), "grid cells");
    cellOrder_ = createBuffer(context, particleCount * sizeof(cl_uint), "slots in cell order");
    cellOf_ = createBuffer(context, particleCount * sizeof(cl_uint), "cell of each particle");
    rankInCell_ = createBuffer(context, particleCount * sizeof(cl_uint), "rank in cell");
    cellCount_ = cellCount;
    scanStatus_ = createBuffer(context, (1 + tiles(cellCount)) * sizeof(cl_uint), "scan status");
    nextScanStatus_ = createBuffer(context, (1 + tiles(cellCount)) * sizeof(cl_uint), "next scan status");
}

bool DeviceGrid::holds(GridGeometry geometry, std::size_t particleCount) const {
    return room_ >= particleCount && countKernel_.get() && geometry.cols == geometry_.cols &&
           geometry.rows == geometry_.rows && geometry.cellsPerLengthX == geometry_.cellsPerLengthX &&
           geometry.cellsPerLengthY == geometry_.cellsPerLengthY;
}

void DeviceGrid::count(cl_command_queue queue, cl_mem state) {
    enqueueZero(queue, scanStatus_.get(), (1 + tiles(cellCount_)) * sizeof(cl_uint), "scan status");
    enqueueZero(queue, counts_.get(), cellCount_ * sizeof(cl_uint), "cell counts");
    setKernelArgs(countKernel_.get(), state, cl_uint(particleCount_), geometry_, counts_.get(), cellOf_.get(),
                  rankInCell_.get());
    enqueue1d(queue, countKernel_.get(), particleCount_, groupSize_, "countCells", profiler_);
}

void DeviceGrid::build(cl_command_queue queue, cl_mem ids, cl_mem sortedIds, cl_mem halt, const Gather& gather) {
    onePassScan_ ? scanInOnePass(queue, halt) : scanInLaunches(queue, halt);
    setKernelArgs(scatterKernel_.get(), halt, cellOf_.get(), rankInCell_.get(), cells_.get(), cl_uint(particleCount_),
                  ids, cellOrder_.get(), sortedIds);
    enqueue1d(queue, scatterKernel_.get(), particleCount_, groupSize_, "scatterToCells", profiler_);
    setKernelArgs(sortKernel_.get(), halt, cells_.get(), cl_uint(cellCount_), cellOrder_.get(), sortedIds,
                  nextCounts_.get(), gather.state, gather.gathered, cellOf_.get());
    enqueue1d(queue, sortKernel_.get(), cellCount_, groupSize_, "sortCellSegments", profiler_);
}

void DeviceGrid::resetScan(cl_command_queue queue) {
    for (cl_mem status : {scanStatus_.get(), nextScanStatus_.get()})
        enqueueZero(queue, status, (1 + tiles(cellCount_)) * sizeof(cl_uint), "scan status");
}

void DeviceGrid::scanInOnePass(cl_command_queue queue, cl_mem halt) {
    setKernelArgs(scanKernel_.get(), halt, counts_.get(), cl_uint(cellCount_), cells_.get(), scanStatus_.get(),
                  nextScanStatus_.get());
    setLocalArg(scanKernel_.get(), 6, scanTileBytes(scanGroupSize_, kScanItems));
    setLocalArg(scanKernel_.get(), 7, scanRunBytes(scanGroupSize_));
    enqueue1d(queue, scanKernel_.get(), tiles(cellCount_) * scanGroupSize_, scanGroupSize_, "scanCountsIntoCells",
              profiler_);
    std::swap(scanStatus_, nextScanStatus_);
}

// The tiles' sums go to scanStatus_, which the one-pass scan would use.
void DeviceGrid::scanInLaunches(cl_command_queue queue, cl_mem halt) {
    const std::size_t tileBytes = scanTileBytes(scanGroupSize_, kScanItems), runBytes = scanRunBytes(scanGroupSize_);
    setKernelArgs(scanKernel_.get(), halt, counts_.get(), cl_uint(cellCount_), cells_.get(), scanStatus_.get());
    setLocalArg(scanKernel_.get(), 5, tileBytes);
    setLocalArg(scanKernel_.get(), 6, runBytes);
    enqueue1d(queue, scanKernel_.get(), tiles(cellCount_) * scanGroupSize_, scanGroupSize_, "scanTiles", profiler_);
    setKernelArgs(scanTileSumsKernel_.get(), halt, scanStatus_.get(), cl_uint(tiles(cellCount_)));
    setLocalArg(scanTileSumsKernel_.get(), 3, tileBytes);
    setLocalArg(scanTileSumsKernel_.get(), 4, runBytes);
    enqueue1d(queue, scanTileSumsKernel_.get(), scanGroupSize_, scanGroupSize_, "scanTileSums", profiler_);
    setKernelArgs(addTileStartsKernel_.get(), halt, cells_.get(), cl_uint(cellCount_), scanStatus_.get(),
                  cl_uint(tileLength_));
    enqueue1d(queue, addTileStartsKernel_.get(), cellCount_, groupSize_, "addTileStarts", profiler_);
}

Grid DeviceGrid::read(cl_command_queue queue, cl_mem sortedIds) const {
    Grid grid;
    grid.geometry = geometry_;
    grid.cells.resize(cellCount_);
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
