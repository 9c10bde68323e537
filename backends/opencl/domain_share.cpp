#include "backends/opencl/domain_share.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>

#include "backends/opencl/grid.h"

namespace carom {

using namespace opencl;

namespace {

// The work-group of the kernels that take one disk per work-item, at most.
constexpr std::size_t kGroupSize = 256;

}  // namespace

struct OpenClDomainShare::Kernels {
    Kernel scanOwnTiles, scanTileSums, mergeOwn, placeIncoming, keepStepped, findLeavers, findNear, packListed,
        ownMaxSpeedSquared, clearShareTallies;
    Buffer running;  // scanTileSums' halt words: running, the grid built (kernels/params.h)
    std::size_t groupSize = kGroupSize, scanGroupSize = 1, tileLength = 0;
};

OpenClDomainShare::OpenClDomainShare(OpenClResidentBackend& engine)
    : engine_(&engine), context_(engine.context()), queue_(engine.queue()) {
    auto k = std::make_shared<Kernels>();
    const cl_program program = engine.program();
    const DeviceInfo& device = engine.deviceInfo();
    k->scanOwnTiles = createKernel(program, "scanOwnTiles");
    k->scanTileSums = createKernel(program, "scanTileSums");
    k->mergeOwn = createKernel(program, "mergeOwn");
    k->placeIncoming = createKernel(program, "placeIncoming");
    k->keepStepped = createKernel(program, "keepStepped");
    k->findLeavers = createKernel(program, "findLeavers");
    k->findNear = createKernel(program, "findNear");
    k->packListed = createKernel(program, "packListed");
    k->ownMaxSpeedSquared = createKernel(program, "ownMaxSpeedSquared");
    k->clearShareTallies = createKernel(program, "clearShareTallies");
    for (const Kernel* kernel : {&k->mergeOwn, &k->placeIncoming, &k->keepStepped, &k->findLeavers, &k->findNear,
                                 &k->packListed, &k->ownMaxSpeedSquared, &k->clearShareTallies})
        k->groupSize = std::min(k->groupSize, kernelWorkGroupLimit(kernel->get(), device.id));
    const std::size_t scanLimit = std::min(kernelWorkGroupLimit(k->scanOwnTiles.get(), device.id),
                                           kernelWorkGroupLimit(k->scanTileSums.get(), device.id));
    k->scanGroupSize = DeviceGrid::scanGroupSize(device, scanLimit, kGroupSize, DeviceGrid::kScanItems);
    k->tileLength = k->scanGroupSize * DeviceGrid::kScanItems;
    k->running = createBuffer(context_, 2 * sizeof(cl_uint), "running");
    const cl_uint running[2] = {CAROM_RUNNING, 0};
    check(clEnqueueWriteBuffer(queue_, k->running.get(), CL_TRUE, 0, sizeof running, running, 0, nullptr, nullptr),
          "clEnqueueWriteBuffer(running)");
    kernels_ = std::move(k);
}

void OpenClDomainShare::fit(Array& array, std::size_t bytes, const char* what) const {
    if (array.get() && array.bytes >= bytes) return;
    array.buffer.reset();  // first: the device may not hold both
    array.bytes = std::max<std::size_t>(bytes + bytes / 4, 64);
    array.buffer = createBuffer(context_, array.bytes, what);
}

void OpenClDomainShare::fit(Disks& disks, std::size_t count) const {
    fit(disks.particles, count * sizeof(Particle), "a share's disks");
    fit(disks.tallies, count * sizeof(ContactTally), "a share's tallies");
    fit(disks.images, count * sizeof(Image), "a share's images");
    fit(disks.ids, count * sizeof(cl_uint), "a share's ids");
    fit(disks.own, count * sizeof(cl_uint), "a share's own marks");
}

template <class T>
void OpenClDomainShare::write(Array& array, const std::vector<T>& values, std::size_t offset, const char* what) const {
    if (values.empty()) return;
    check(clEnqueueWriteBuffer(queue_, array.get(), CL_TRUE, offset * sizeof(T), values.size() * sizeof(T),
                               values.data(), 0, nullptr, nullptr),
          what);
}

template <class T>
void OpenClDomainShare::read(const Array& array, std::vector<T>& values, std::size_t count, const char* what) const {
    values.resize(count);
    if (count == 0) return;
    check(clEnqueueReadBuffer(queue_, array.get(), CL_TRUE, 0, count * sizeof(T), values.data(), 0, nullptr, nullptr),
          what);
}

void OpenClDomainShare::load(const DomainDisks& own, const DomainMap& map, int rank) {
    map_ = map;
    rank_ = rank;
    fit(domainOfColumn_, map.domainOfColumn.size() * sizeof(int), "the domains of the cell columns");
    fit(domainOfRow_, map.domainOfRow.size() * sizeof(int), "the domains of the cell rows");
    write(domainOfColumn_, map.domainOfColumn, 0, "clEnqueueWriteBuffer(the domains of the cell columns)");
    write(domainOfRow_, map.domainOfRow, 0, "clEnqueueWriteBuffer(the domains of the cell rows)");
    const std::size_t n = own.ids.size();
    fit(held_, n);
    held_.count = ownCount_ = n;
    write(held_.particles, own.particles, 0, "clEnqueueWriteBuffer(a share's disks)");
    write(held_.ids, own.ids, 0, "clEnqueueWriteBuffer(a share's ids)");
    write(held_.images, own.images, 0, "clEnqueueWriteBuffer(a share's images)");
    if (n > 0) {
        const cl_uint one = 1;
        check(
            clEnqueueFillBuffer(queue_, held_.own.get(), &one, sizeof one, 0, n * sizeof(cl_uint), 0, nullptr, nullptr),
            "clEnqueueFillBuffer(a share's own marks)");
        enqueueZero(queue_, held_.tallies.get(), n * sizeof(ContactTally), "a share's tallies");
    }
    fit(list_, (1 + n) * sizeof(cl_uint), "a list of a share's slots");
    next_.count = 0;
}

std::size_t OpenClDomainShare::listSlots(cl_kernel kernel) {
    enqueueZero(queue_, list_.get(), sizeof(cl_uint), "a list of a share's slots");
    enqueue1d(queue_, kernel, held_.count, kernels_->groupSize, "a share's slots");
    cl_uint listed = 0;
    check(clEnqueueReadBuffer(queue_, list_.get(), CL_TRUE, 0, sizeof listed, &listed, 0, nullptr, nullptr),
          "clEnqueueReadBuffer(a list of a share's slots)");
    return listed;
}

void OpenClDomainShare::readListed(std::size_t listed, bool tallies, DomainDisks& out) {
    out.resize(0);
    if (listed == 0) return;
    fit(packedIds_, listed * sizeof(cl_uint), "listed ids");
    fit(packedParticles_, listed * sizeof(Particle), "listed disks");
    if (tallies) {
        fit(packedTallies_, listed * sizeof(ContactTally), "listed tallies");
        fit(packedImages_, listed * sizeof(Image), "listed images");
    }
    setKernelArgs(kernels_->packListed.get(), list_.get(), cl_uint(listed), held_.particles.get(), held_.tallies.get(),
                  held_.images.get(), held_.ids.get(), packedIds_.get(), packedParticles_.get(),
                  tallies ? packedTallies_.get() : cl_mem{}, tallies ? packedImages_.get() : cl_mem{});
    enqueue1d(queue_, kernels_->packListed.get(), listed, kernels_->groupSize, "packListed");
    read(packedIds_, out.ids, listed, "clEnqueueReadBuffer(listed ids)");
    read(packedParticles_, out.particles, listed, "clEnqueueReadBuffer(listed disks)");
    if (!tallies) return;
    read(packedTallies_, out.tallies, listed, "clEnqueueReadBuffer(listed tallies)");
    read(packedImages_, out.images, listed, "clEnqueueReadBuffer(listed images)");
}

void OpenClDomainShare::near(const std::vector<unsigned char>& nearColumns, const std::vector<unsigned char>& nearRows,
                             std::vector<std::uint32_t>& ids, std::vector<Particle>& particles) {
    if (held_.count == 0) return;
    fit(nearColumns_, nearColumns.size(), "the cell columns near another domain");
    fit(nearRows_, nearRows.size(), "the cell rows near another domain");
    write(nearColumns_, nearColumns, 0, "clEnqueueWriteBuffer(the cell columns near another domain)");
    write(nearRows_, nearRows, 0, "clEnqueueWriteBuffer(the cell rows near another domain)");
    setKernelArgs(kernels_->findNear.get(), held_.particles.get(), held_.own.get(), cl_uint(held_.count), map_.grid,
                  nearColumns_.get(), nearRows_.get(), list_.get());
    readListed(listSlots(kernels_->findNear.get()), false, packed_);
    ids.insert(ids.end(), packed_.ids.begin(), packed_.ids.end());
    particles.insert(particles.end(), packed_.particles.begin(), packed_.particles.end());
}

void OpenClDomainShare::mergeNext(const DomainDisks& arrived, const std::vector<std::uint32_t>& copyIds,
                                  const std::vector<Particle>& copies) {
    const Kernels& k = *kernels_;
    const std::size_t came = arrived.ids.size(), copied = copyIds.size(), incoming = came + copied;
    const std::size_t total = ownCount_ + incoming;
    fit(next_, total);
    next_.count = total;
    nextOwnCount_ = ownCount_ + came;
    if (incoming > 0) {
        fit(incoming_, incoming * sizeof(Particle), "incoming disks");
        fit(incomingIds_, incoming * sizeof(cl_uint), "incoming ids");
        fit(incomingTallies_, came * sizeof(ContactTally), "incoming tallies");
        fit(incomingImages_, came * sizeof(Image), "incoming images");
        write(incoming_, arrived.particles, 0, "clEnqueueWriteBuffer(incoming disks)");
        write(incoming_, copies, came, "clEnqueueWriteBuffer(incoming disks)");
        write(incomingIds_, arrived.ids, 0, "clEnqueueWriteBuffer(incoming ids)");
        write(incomingIds_, copyIds, came, "clEnqueueWriteBuffer(incoming ids)");
        write(incomingTallies_, arrived.tallies, 0, "clEnqueueWriteBuffer(incoming tallies)");
        write(incomingImages_, arrived.images, 0, "clEnqueueWriteBuffer(incoming images)");
    }
    const std::size_t count = held_.count;
    if (count > 0) {  // each held slot's place among the own disks: the scan of held_.own
        const std::size_t tiles = (count + k.tileLength - 1) / k.tileLength;
        fit(ownRanks_, count * sizeof(cl_uint), "own ranks");
        fit(tileStarts_, tiles * sizeof(cl_uint), "own tile starts");
        const std::size_t tileBytes = DeviceGrid::scanTileBytes(k.scanGroupSize, DeviceGrid::kScanItems);
        const std::size_t runBytes = DeviceGrid::scanRunBytes(k.scanGroupSize);
        setKernelArgs(k.scanOwnTiles.get(), held_.own.get(), cl_uint(count), ownRanks_.get(), tileStarts_.get());
        setLocalArg(k.scanOwnTiles.get(), 4, tileBytes);
        setLocalArg(k.scanOwnTiles.get(), 5, runBytes);
        enqueue1d(queue_, k.scanOwnTiles.get(), tiles * k.scanGroupSize, k.scanGroupSize, "scanOwnTiles");
        setKernelArgs(k.scanTileSums.get(), k.running.get(), tileStarts_.get(), cl_uint(tiles));
        setLocalArg(k.scanTileSums.get(), 3, tileBytes);
        setLocalArg(k.scanTileSums.get(), 4, runBytes);
        enqueue1d(queue_, k.scanTileSums.get(), k.scanGroupSize, k.scanGroupSize, "scanTileSums");
        setKernelArgs(k.mergeOwn.get(), held_.particles.get(), held_.tallies.get(), held_.images.get(), held_.ids.get(),
                      held_.own.get(), cl_uint(count), ownRanks_.get(), tileStarts_.get(), cl_uint(k.tileLength),
                      incomingIds_.get(), cl_uint(came), cl_uint(copied), next_.particles.get(), next_.tallies.get(),
                      next_.images.get(), next_.ids.get(), next_.own.get());
        enqueue1d(queue_, k.mergeOwn.get(), count, k.groupSize, "mergeOwn");
    }
    if (incoming > 0) {
        setKernelArgs(k.placeIncoming.get(), incoming_.get(), incomingTallies_.get(), incomingImages_.get(),
                      incomingIds_.get(), cl_uint(came), cl_uint(copied), held_.ids.get(), cl_uint(count),
                      ownRanks_.get(), tileStarts_.get(), cl_uint(k.tileLength), cl_uint(ownCount_),
                      next_.particles.get(), next_.tallies.get(), next_.images.get(), next_.ids.get(), next_.own.get());
        enqueue1d(queue_, k.placeIncoming.get(), incoming, k.groupSize, "placeIncoming");
    }
}

unsigned int OpenClDomainShare::stepNext(const Backend& whole, float dt) {
    if (next_.count == 0) return 0;
    return engine_->stepDeviceShare(next_.particles.get(), next_.tallies.get(), next_.count, whole, dt);
}

DomainShare::Kept OpenClDomainShare::keepNext() {
    Kept kept;
    if (next_.count > 0) {  // stepNext stepped it on the engine
        const OpenClResidentBackend::SteppedShare stepped = engine_->steppedShare();
        cl_uint record[2] = {0, std::numeric_limits<cl_uint>::max()};
        fit(record_, sizeof record, "a share's record");
        check(clEnqueueWriteBuffer(queue_, record_.get(), CL_TRUE, 0, sizeof record, record, 0, nullptr, nullptr),
              "clEnqueueWriteBuffer(a share's record)");
        setKernelArgs(kernels_->keepStepped.get(), stepped.state, stepped.slotIds, cl_uint(next_.count), stepped.lists,
                      stepped.marksWord, stepped.epoch, next_.ids.get(), next_.own.get(), next_.particles.get(),
                      record_.get());
        enqueue1d(queue_, kernels_->keepStepped.get(), next_.count, kernels_->groupSize, "keepStepped");
        enqueueCopy(queue_, stepped.tallies, next_.tallies.get(), next_.count * sizeof(ContactTally),
                    "a share's tallies");
        check(clEnqueueReadBuffer(queue_, record_.get(), CL_TRUE, 0, sizeof record, record, 0, nullptr, nullptr),
              "clEnqueueReadBuffer(a share's record)");
        kept.lastRound = record[0];
        kept.nonFinite = record[1];
    }
    std::swap(held_, next_);
    ownCount_ = nextOwnCount_;
    fit(list_, (1 + held_.count) * sizeof(cl_uint), "a list of a share's slots");
    return kept;
}

void OpenClDomainShare::takeLeavers(DomainDisks& leavers) {
    if (held_.count == 0) return;
    setKernelArgs(kernels_->findLeavers.get(), held_.particles.get(), held_.own.get(), cl_uint(held_.count), map_.grid,
                  domainOfColumn_.get(), domainOfRow_.get(), cl_int(map_.domainsX), cl_int(rank_), list_.get());
    const std::size_t listed = listSlots(kernels_->findLeavers.get());
    ownCount_ -= listed;
    readListed(listed, true, packed_);
    leavers.ids.insert(leavers.ids.end(), packed_.ids.begin(), packed_.ids.end());
    leavers.particles.insert(leavers.particles.end(), packed_.particles.begin(), packed_.particles.end());
    leavers.tallies.insert(leavers.tallies.end(), packed_.tallies.begin(), packed_.tallies.end());
    leavers.images.insert(leavers.images.end(), packed_.images.begin(), packed_.images.end());
}

DomainDisks OpenClDomainShare::own() const {
    DomainDisks all, own;
    std::vector<cl_uint> marks;
    const std::size_t n = held_.count;
    read(held_.ids, all.ids, n, "clEnqueueReadBuffer(a share's ids)");
    read(held_.particles, all.particles, n, "clEnqueueReadBuffer(a share's disks)");
    read(held_.tallies, all.tallies, n, "clEnqueueReadBuffer(a share's tallies)");
    read(held_.images, all.images, n, "clEnqueueReadBuffer(a share's images)");
    read(held_.own, marks, n, "clEnqueueReadBuffer(a share's own marks)");
    own.resize(ownCount_);
    std::size_t j = 0;
    for (std::size_t k = 0; k < n; ++k)
        if (marks[k]) {
            own.ids[j] = all.ids[k];
            own.particles[j] = all.particles[k];
            own.tallies[j] = all.tallies[k];
            own.images[j++] = all.images[k];
        }
    return own;
}

float OpenClDomainShare::maxSpeedSquared() {
    if (held_.count == 0) return 0.0f;
    cl_uint largest = 0;  // the bits of 0.0f
    fit(record_, 2 * sizeof(cl_uint), "a share's record");
    check(clEnqueueWriteBuffer(queue_, record_.get(), CL_TRUE, 0, sizeof largest, &largest, 0, nullptr, nullptr),
          "clEnqueueWriteBuffer(a share's record)");
    setKernelArgs(kernels_->ownMaxSpeedSquared.get(), held_.particles.get(), held_.own.get(), cl_uint(held_.count),
                  record_.get());
    enqueue1d(queue_, kernels_->ownMaxSpeedSquared.get(), held_.count, kernels_->groupSize, "ownMaxSpeedSquared");
    check(clEnqueueReadBuffer(queue_, record_.get(), CL_TRUE, 0, sizeof largest, &largest, 0, nullptr, nullptr),
          "clEnqueueReadBuffer(a share's record)");
    float speedSquared = 0.0f;
    std::memcpy(&speedSquared, &largest, sizeof speedSquared);
    return speedSquared;
}

void OpenClDomainShare::clearTallies() {
    if (held_.count == 0) return;
    setKernelArgs(kernels_->clearShareTallies.get(), held_.tallies.get(), held_.images.get(), held_.own.get(),
                  cl_uint(held_.count));
    enqueue1d(queue_, kernels_->clearShareTallies.get(), held_.count, kernels_->groupSize, "clearShareTallies");
}

OpenClDomainShare::OpenClDomainShare(const OpenClDomainShare& from, const char* what)
    : engine_(from.engine_),
      context_(from.context_),
      queue_(from.queue_),
      kernels_(from.kernels_),
      map_(from.map_),
      rank_(from.rank_),
      ownCount_(from.ownCount_) {
    const std::size_t n = from.held_.count;
    fit(held_, n);
    held_.count = n;
    const auto copy = [&](const Array& source, Array& target, std::size_t bytes) {
        if (bytes > 0) enqueueCopy(queue_, source.get(), target.get(), bytes, what);
    };
    copy(from.held_.particles, held_.particles, n * sizeof(Particle));
    copy(from.held_.tallies, held_.tallies, n * sizeof(ContactTally));
    copy(from.held_.images, held_.images, n * sizeof(Image));
    copy(from.held_.ids, held_.ids, n * sizeof(cl_uint));
    copy(from.held_.own, held_.own, n * sizeof(cl_uint));
    fit(domainOfColumn_, map_.domainOfColumn.size() * sizeof(int), "the domains of the cell columns");
    fit(domainOfRow_, map_.domainOfRow.size() * sizeof(int), "the domains of the cell rows");
    copy(from.domainOfColumn_, domainOfColumn_, map_.domainOfColumn.size() * sizeof(int));
    copy(from.domainOfRow_, domainOfRow_, map_.domainOfRow.size() * sizeof(int));
    fit(list_, (1 + n) * sizeof(cl_uint), "a list of a share's slots");
}

std::unique_ptr<DomainShare> OpenClDomainShare::clone() const {
    return std::unique_ptr<DomainShare>(new OpenClDomainShare(*this, "a copy of a share"));
}

}  // namespace carom
