#include "backends/decomposed.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "engine/parallel.h"
#include "kernels/physics.h"

namespace carom {

namespace {

// The deepest halo a pairwise substep needs: 2R + 3 cells at the most rounds.
constexpr int kMaxPairwiseHalo = 2 * int(kMaxPairwiseRounds) + 3;
// A pairwise substep's first halo: exact for up to 4 rounds, more than most
// substeps take below close packing.
constexpr int kFirstPairwiseHalo = 2 * 4 + 3;

// A record of a halo copy and of a disk handed on, packed by bytes.
constexpr std::size_t kCopyBytes = sizeof(std::uint32_t) + sizeof(Particle);
constexpr std::size_t kMigrantBytes = kCopyBytes + sizeof(ContactTally) + sizeof(Image);

template <class T>
unsigned char* put(unsigned char* out, const T& value) {
    std::memcpy(out, &value, sizeof value);
    return out + sizeof value;
}

template <class T>
const unsigned char* take(const unsigned char* in, T& value) {
    std::memcpy(&value, in, sizeof value);
    return in + sizeof value;
}

// An MPI type of `bytes` bytes, freed with the object.
class RecordType {
public:
    explicit RecordType(std::size_t bytes) {
        MPI_Type_contiguous(static_cast<int>(bytes), MPI_BYTE, &type_);
        MPI_Type_commit(&type_);
    }
    ~RecordType() { MPI_Type_free(&type_); }
    RecordType(const RecordType&) = delete;
    RecordType& operator=(const RecordType&) = delete;
    operator MPI_Datatype() const { return type_; }

private:
    MPI_Datatype type_;
};

// Each count of `bytes` (records here) fits an int, as MPI's counts must.
int countOf(std::size_t records) {
    if (records > std::size_t(std::numeric_limits<int>::max()))
        throw Error("a message of " + std::to_string(records) +
                    " disks between two processes; allowed: up to 2^31 - 1 (use more processes)");
    return static_cast<int>(records);
}

// Adds the seconds since it was made to `total` when it ends.
class Timed {
public:
    explicit Timed(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
    ~Timed() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
    Timed(const Timed&) = delete;
    Timed& operator=(const Timed&) = delete;

private:
    double& total_;
    std::chrono::steady_clock::time_point start_;
};

// Sends out[q] (records of `bytes` bytes) to process q, counted in `costs`;
// returns what every process sent here, in rank order, and in `counts` how
// many records each.
std::vector<unsigned char> exchange(MPI_Comm comm, const std::vector<std::vector<unsigned char>>& out,
                                    std::size_t bytes, std::vector<int>& counts, DecompositionCosts& costs) {
    const int size = static_cast<int>(out.size());
    for (const auto& message : out)  // this process sends itself nothing
        if (!message.empty()) {
            ++costs.messages;
            costs.bytes += message.size();
        }
    std::vector<int> sendCounts(std::size_t(size), 0), sendStarts(std::size_t(size), 0),
        receiveStarts(std::size_t(size), 0);
    counts.assign(std::size_t(size), 0);
    std::vector<unsigned char> sent;
    for (int q = 0; q < size; ++q) {
        sendStarts[std::size_t(q)] = countOf(sent.size() / bytes);
        sendCounts[std::size_t(q)] = countOf(out[std::size_t(q)].size() / bytes);
        sent.insert(sent.end(), out[std::size_t(q)].begin(), out[std::size_t(q)].end());
    }
    MPI_Alltoall(sendCounts.data(), 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
    std::size_t total = 0;
    for (int q = 0; q < size; ++q) {
        receiveStarts[std::size_t(q)] = countOf(total);
        total += std::size_t(counts[std::size_t(q)]);
    }
    std::vector<unsigned char> received(total * bytes);
    const RecordType type(bytes);
    MPI_Alltoallv(sent.data(), sendCounts.data(), sendStarts.data(), type, received.data(), counts.data(),
                  receiveStarts.data(), type, comm);
    return received;
}

// Gathers every process's `mine` (in rank order) on every process, counted in `costs`.
template <class T>
std::vector<T> gatherAll(MPI_Comm comm, const std::vector<T>& mine, DecompositionCosts& costs) {
    Timed timed(costs.gatherSeconds);
    int size = 1;
    MPI_Comm_size(comm, &size);
    costs.messages += std::uint64_t(size - 1);
    costs.bytes += std::uint64_t(size - 1) * mine.size() * sizeof(T);
    std::vector<int> counts(std::size_t(size), 0), starts(std::size_t(size), 0);
    const int count = countOf(mine.size());
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
    std::size_t total = 0;
    for (int q = 0; q < size; ++q) {
        starts[std::size_t(q)] = countOf(total);
        total += std::size_t(counts[std::size_t(q)]);
    }
    std::vector<T> all(total);
    const RecordType type(sizeof(T));
    MPI_Allgatherv(mine.data(), count, type, all.data(), counts.data(), starts.data(), type, comm);
    return all;
}

// The first cell of each of `domains` domains over `cells` cells, and one past the last.
std::vector<int> domainStarts(int cells, int domains) {
    std::vector<int> starts(std::size_t(domains) + 1);
    for (int d = 0; d <= domains; ++d) starts[std::size_t(d)] = static_cast<int>(std::int64_t(d) * cells / domains);
    return starts;
}

// For each cell of a line of `cells`, the domains whose cells widened by
// `halo` on each side (around the box where it is periodic) hold it.
std::vector<std::vector<int>> domainsWithin(const std::vector<int>& starts, int halo, bool periodic) {
    const int cells = starts.back(), domains = static_cast<int>(starts.size()) - 1;
    std::vector<std::vector<int>> within(std::size_t(cells), std::vector<int>{});
    for (int d = 0; d < domains; ++d) {
        int first = starts[std::size_t(d)] - halo, end = starts[std::size_t(d) + 1] + halo;
        if (!periodic) {  // no cells beyond the walls
            first = std::max(first, 0);
            end = std::min(end, cells);
        } else if (end - first >= cells) {  // around the box: each cell once
            first = 0;
            end = cells;
        }
        for (int c = first; c < end; ++c) within[std::size_t((c % cells + cells) % cells)].push_back(d);
    }
    return within;
}

// FNV-1a over bytes, continuing from `hash`.
std::uint64_t hashBytes(const void* data, std::size_t bytes, std::uint64_t hash) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
    return hash;
}

}  // namespace

std::shared_ptr<const Decomposition> makeDecomposition(const DecompositionDef& def) {
    return std::make_shared<const Decomposition>(def);
}

Decomposition::Decomposition(const DecompositionDef& def)
    : domainsX_(def.domainsX), domainsY_(def.domainsY), gather_(def.gather) {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) throw Error("a decomposition before MPI_Init; allowed: after MPI_Init, before MPI_Finalize");
    if (def.communicator == MPI_COMM_NULL) throw Error("DecompositionDef::communicator is MPI_COMM_NULL");
    int inter = 0;
    MPI_Comm_test_inter(def.communicator, &inter);
    if (inter) throw Error("DecompositionDef::communicator is an inter-communicator; allowed: an intra-communicator");
    MPI_Comm_size(def.communicator, &size_);
    MPI_Comm_rank(def.communicator, &rank_);
    const bool chosen = domainsX_ == 0 && domainsY_ == 0;
    if (!chosen && (domainsX_ < 1 || domainsY_ < 1 || std::int64_t(domainsX_) * domainsY_ != size_))
        throw Error("domains " + std::to_string(domainsX_) + " x " + std::to_string(domainsY_) + " for " +
                    std::to_string(size_) + " processes; allowed: two positive numbers whose product is " +
                    std::to_string(size_) + ", or 0 x 0 (chosen from the box)");
    MPI_Comm_dup(def.communicator, &communicator_);
    MPI_Comm node;
    MPI_Comm_split_type(communicator_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &nodeRank_);
    MPI_Comm_free(&node);
}

void requireEveryProcess(const Decomposition& decomposition, const std::string& failure) {
    const MPI_Comm comm = decomposition.communicator();
    const int size = decomposition.size();
    int first = failure.empty() ? size : decomposition.rank();
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first == size) return;
    std::string message = failure;
    unsigned long long length = message.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, first, comm);
    message.resize(std::size_t(length));
    MPI_Bcast(message.data(), int(length), MPI_CHAR, first, comm);
    throw Error("process " + std::to_string(first) + " of " + std::to_string(size) + ": " + message);
}

Decomposition::~Decomposition() {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (!finalised) MPI_Comm_free(&communicator_);
}

std::array<int, 2> Decomposition::domainsFor(float width, float height) const {
    if (domainsX_ > 0) return {domainsX_, domainsY_};
    // The domains nearest to squares: the least |log of a domain's aspect|.
    std::array<int, 2> best{size_, 1};
    double bestAspect = HUGE_VAL;
    for (int x = 1; x <= size_; ++x) {
        if (size_ % x != 0) continue;
        const double aspect = std::fabs(std::log((double(width) / x) / (double(height) / (size_ / x))));
        if (aspect < bestAspect) {
            bestAspect = aspect;
            best = {x, size_ / x};
        }
    }
    return best;
}

DecomposedBackend::DecomposedBackend(const WorldDef& world, std::unique_ptr<Backend> engine,
                                     std::unique_ptr<DomainShare> share)
    : Backend(world),
      decomposition_(world.decomposition),
      comm_(decomposition_->communicator()),
      engine_(std::move(engine)),
      held_(std::move(share)) {}

std::string DecomposedBackend::device() const {
    return engine_->device() + ", process " + std::to_string(decomposition_->rank()) + " of " +
           std::to_string(decomposition_->size()) + " (" + std::to_string(map_.domainsX) + " x " +
           std::to_string(domainsY_) + " domains)";
}

void DecomposedBackend::requireSameInput(const std::vector<Particle>& particles) const {
    std::uint64_t hash = 14695981039346656037ull;
    const WorldDef& w = world_;
    for (float value : {w.width, w.height, w.dt, w.gravity.x, w.gravity.y, w.maxTravel, w.skin})
        hash = hashBytes(&value, sizeof value, hash);
    for (int value : {int(w.boundary), int(w.collisions), int(w.engine)}) hash = hashBytes(&value, sizeof value, hash);
    const std::uint64_t count = particles.size();
    hash = hashBytes(&count, sizeof count, hash);
    hash = hashBytes(particles.data(), particles.size() * sizeof(Particle), hash);
    hash = hashBytes(images_.data(), images_.size() * sizeof(Image), hash);
    std::uint64_t lowest = hash, highest = hash;
    MPI_Allreduce(&hash, &lowest, 1, MPI_UINT64_T, MPI_MIN, comm_);
    MPI_Allreduce(&hash, &highest, 1, MPI_UINT64_T, MPI_MAX, comm_);
    if (lowest != highest)
        throw Error("the processes were given different worlds or disks (this one " + std::to_string(particles.size()) +
                    " disks); allowed: the same WorldDef and disks on every process");
}

void DecomposedBackend::load(const std::vector<Particle>& particles) {
    requireSameInput(particles);
    const GridGeometry& g = grid_.geometry;
    const auto domains = decomposition_->domainsFor(world_.width, world_.height);
    if (domains[0] > g.cols || domains[1] > g.rows)
        throw Error("domains " + std::to_string(domains[0]) + " x " + std::to_string(domains[1]) + " on a grid of " +
                    std::to_string(g.cols) + " x " + std::to_string(g.rows) +
                    " cells (each at least a disk diameter wide); allowed: at most one domain per cell across and "
                    "up (fewer processes, or more disks)");
    map_.grid = g;
    map_.domainsX = domains[0];
    domainsY_ = domains[1];
    columnStarts_ = domainStarts(g.cols, map_.domainsX);
    rowStarts_ = domainStarts(g.rows, domainsY_);
    map_.domainOfColumn.assign(std::size_t(g.cols), 0);
    map_.domainOfRow.assign(std::size_t(g.rows), 0);
    for (int d = 0; d < map_.domainsX; ++d)
        for (int c = columnStarts_[std::size_t(d)]; c < columnStarts_[std::size_t(d) + 1]; ++c)
            map_.domainOfColumn[std::size_t(c)] = d;
    for (int d = 0; d < domainsY_; ++d)
        for (int r = rowStarts_[std::size_t(d)]; r < rowStarts_[std::size_t(d) + 1]; ++r)
            map_.domainOfRow[std::size_t(r)] = d;
    const int rank = decomposition_->rank();
    DomainDisks own;
    for (std::size_t i = 0; i < particles.size(); ++i)
        if (map_.ownerOf(particles[i].position) == rank) {
            own.ids.push_back(static_cast<std::uint32_t>(i));
            own.particles.push_back(particles[i]);
            own.images.push_back(images_[i]);
        }
    own.tallies.assign(own.ids.size(), ContactTally{});
    held_->load(own, map_, rank);
    arrived_.resize(0);
    stepStart_.reset();
    halo_ = world_.collisions == CollisionScheme::Pairwise ? kFirstPairwiseHalo : 1;
    costs_ = DecompositionCosts{};
    imagesCurrent_ = true;  // images_ holds setParticles' images
    undrainedCurrent_ = true;
    undrained_ = TallySums{};
}

void DecomposedBackend::mergeShare(int halo) {
    const int size = decomposition_->size(), rank = decomposition_->rank();
    const bool periodic = world_.boundary == Boundary::Periodic;
    const auto columns = domainsWithin(columnStarts_, halo, periodic);
    const auto rows = domainsWithin(rowStarts_, halo, periodic);
    const GridGeometry& g = grid_.geometry;
    // Copies of the own disks within another domain's halo: those whose
    // cell's column or row lies within more domains' halos than their own.
    std::vector<unsigned char> nearColumns(columns.size()), nearRows(rows.size());
    for (std::size_t c = 0; c < columns.size(); ++c) nearColumns[c] = columns[c].size() > 1;
    for (std::size_t r = 0; r < rows.size(); ++r) nearRows[r] = rows[r].size() > 1;
    std::vector<std::uint32_t> nearIds;
    std::vector<Particle> nearParticles;
    held_->near(nearColumns, nearRows, nearIds, nearParticles);
    std::vector<std::vector<unsigned char>> out(std::size_t(size), std::vector<unsigned char>{});
    const auto copy = [&](std::uint32_t id, const Particle& p) {
        const int column = carom_cell_coord(p.position.x, g.cellsPerLengthX, g.cols);
        const int row = carom_cell_coord(p.position.y, g.cellsPerLengthY, g.rows);
        for (int dy : rows[std::size_t(row)])
            for (int dx : columns[std::size_t(column)]) {
                const int q = dy * map_.domainsX + dx;
                if (q == rank) continue;
                auto& buffer = out[std::size_t(q)];
                buffer.resize(buffer.size() + kCopyBytes);
                put(put(buffer.data() + buffer.size() - kCopyBytes, id), p);
            }
    };
    for (std::size_t k = 0; k < nearIds.size(); ++k) copy(nearIds[k], nearParticles[k]);
    for (std::size_t j = 0; j < arrived_.ids.size(); ++j) copy(arrived_.ids[j], arrived_.particles[j]);
    std::vector<int> counts;
    const std::vector<unsigned char> received = exchange(comm_, out, kCopyBytes, counts, costs_);
    const std::size_t copies = received.size() / kCopyBytes;
    costs_.haloCopies += copies;
    std::vector<std::uint32_t> copyIds(copies);
    std::vector<Particle> copyParticles(copies);
    const unsigned char* in = received.data();
    for (std::size_t j = 0; j < copies; ++j) in = take(take(in, copyIds[j]), copyParticles[j]);
    std::vector<std::size_t> order(copies);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return copyIds[x] < copyIds[y]; });
    std::vector<std::uint32_t> sortedIds(copies);
    std::vector<Particle> sortedCopies(copies);
    for (std::size_t c = 0; c < copies; ++c) {
        sortedIds[c] = copyIds[order[c]];
        sortedCopies[c] = copyParticles[order[c]];
    }
    held_->mergeNext(arrived_, sortedIds, sortedCopies);
}

bool DecomposedBackend::substep(std::uint64_t substep, float dt) {
    const bool pairwise = world_.collisions == CollisionScheme::Pairwise;
    imagesCurrent_ = undrainedCurrent_ = false;
    for (;;) {
        {
            Timed timed(costs_.exchangeSeconds);
            mergeShare(halo_);
        }
        unsigned int rounds = 0;
        {
            Timed timed(costs_.computeSeconds);
            rounds = held_->stepNext(*this, dt);
        }
        if (pairwise) {
            {
                Timed timed(costs_.agreementSeconds);
                MPI_Allreduce(MPI_IN_PLACE, &rounds, 1, MPI_UNSIGNED, MPI_MAX, comm_);
            }
            const int needed = std::min(2 * int(rounds) + 3, kMaxPairwiseHalo);
            if (needed > halo_) {  // not deep enough: again from the same start, which held_ keeps
                halo_ = needed;
                ++costs_.retakenSubsteps;
                continue;
            }
            // One round's slack for the next substep.
            halo_ = std::min(needed + 2, kMaxPairwiseHalo);
        }
        ++costs_.substeps;
        DomainShare::Kept kept;
        {
            Timed timed(costs_.computeSeconds);
            kept = held_->keepNext();
        }
        arrived_.resize(0);
        {
            Timed timed(costs_.agreementSeconds);
            if (pairwise) MPI_Allreduce(MPI_IN_PLACE, &kept.lastRound, 1, MPI_UNSIGNED, MPI_MAX, comm_);
            MPI_Allreduce(MPI_IN_PLACE, &kept.nonFinite, 1, MPI_UINT32_T, MPI_MIN, comm_);
        }
        if (pairwise) recordRounds(kept.lastRound);
        if (kept.nonFinite != std::numeric_limits<std::uint32_t>::max()) {
            recordNonFinite(substep, kept.nonFinite);
            return false;
        }
        Timed timed(costs_.migrationSeconds);
        migrate();
        return true;
    }
}

void DecomposedBackend::migrate() {
    const int size = decomposition_->size();
    DomainDisks leavers;
    held_->takeLeavers(leavers);
    std::vector<std::vector<unsigned char>> out(std::size_t(size), std::vector<unsigned char>{});
    for (std::size_t j = 0; j < leavers.ids.size(); ++j) {
        auto& buffer = out[std::size_t(map_.ownerOf(leavers.particles[j].position))];
        buffer.resize(buffer.size() + kMigrantBytes);
        put(put(put(put(buffer.data() + buffer.size() - kMigrantBytes, leavers.ids[j]), leavers.particles[j]),
                leavers.tallies[j]),
            leavers.images[j]);
    }
    costs_.migrants += leavers.ids.size();
    std::vector<int> counts;
    const std::vector<unsigned char> received = exchange(comm_, out, kMigrantBytes, counts, costs_);
    const std::size_t arrivals = received.size() / kMigrantBytes;
    DomainDisks came;
    came.resize(arrivals);
    const unsigned char* in = received.data();
    for (std::size_t j = 0; j < arrivals; ++j)
        in = take(take(take(take(in, came.ids[j]), came.particles[j]), came.tallies[j]), came.images[j]);
    std::vector<std::size_t> order(arrivals);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return came.ids[x] < came.ids[y]; });
    arrived_.resize(arrivals);
    for (std::size_t j = 0; j < arrivals; ++j) {
        const std::size_t k = order[j];
        arrived_.ids[j] = came.ids[k];
        arrived_.particles[j] = came.particles[k];
        arrived_.tallies[j] = came.tallies[k];
        arrived_.images[j] = came.images[k];
    }
}

DomainDisks DecomposedBackend::ownDisks() const {
    DomainDisks own = held_->own();
    const std::size_t held = own.ids.size();
    own.resize(held + arrived_.ids.size());
    std::copy(arrived_.ids.begin(), arrived_.ids.end(), own.ids.begin() + std::ptrdiff_t(held));
    std::copy(arrived_.particles.begin(), arrived_.particles.end(), own.particles.begin() + std::ptrdiff_t(held));
    std::copy(arrived_.tallies.begin(), arrived_.tallies.end(), own.tallies.begin() + std::ptrdiff_t(held));
    std::copy(arrived_.images.begin(), arrived_.images.end(), own.images.begin() + std::ptrdiff_t(held));
    return own;
}

std::uint64_t DecomposedBackend::advance(std::uint64_t substeps, float dt) {
    for (std::uint64_t s = 0; s < substeps; ++s) {
        if (stopHere()) return s;
        if (!substep(substepsTaken() + s, dt)) return s + 1;
    }
    return substeps;
}

bool DecomposedBackend::agreedStop(bool stop) {
    int any = stop ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_LOR, comm_);
    return any != 0;
}

void DecomposedBackend::keepStepStart() {
    stepStart_ = held_->clone();
    stepStartArrived_ = arrived_;
}

void DecomposedBackend::returnToStepStart() {
    held_ = stepStart_->clone();
    arrived_ = stepStartArrived_;
    imagesCurrent_ = undrainedCurrent_ = false;
}

float DecomposedBackend::maxSpeedSquared() {
    float all =
        std::max(held_->maxSpeedSquared(), maxSpeedSquaredOf(arrived_.particles.data(), arrived_.particles.size()));
    MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_FLOAT, MPI_MAX, comm_);
    return all;
}

TallySums DecomposedBackend::undrainedSums() {
    if (!undrainedCurrent_) {
        undrained_ = TallySums{};
        const DomainDisks own = ownDisks();
        const TallySums mine = sumTallies(own.tallies.data(), own.tallies.size());
        for (const TallySums& sums : gatherAll(comm_, std::vector<TallySums>{mine}, costs_)) undrained_.add(sums);
        undrainedCurrent_ = true;
    }
    return undrained_;
}

void DecomposedBackend::addUndrained(ContactTotals& totals) { undrainedSums().addTo(totals); }

void DecomposedBackend::drainTallies(ContactTotals& totals) {
    undrainedSums().addTo(totals);
    held_->clearTallies();
    clearTallies(arrived_.tallies.data(), arrived_.tallies.size(), arrived_.images.data());
    undrained_ = TallySums{};
    undrainedCurrent_ = true;
}

void DecomposedBackend::readParticles(std::vector<Particle>& particles) {
    const DomainDisks own = ownDisks();
    const std::vector<std::uint32_t> ids = gatherAll(comm_, own.ids, costs_);
    const std::vector<Particle> all = gatherAll(comm_, own.particles, costs_);
    particles.resize(all.size());
    parallelFor(all.size(), [&](std::size_t k) { particles[ids[k]] = all[k]; });
}

void DecomposedBackend::readOwnDisks(std::vector<std::uint32_t>& ids, std::vector<Particle>& particles,
                                     std::vector<Image>& images) {
    DomainDisks own = ownDisks();
    addWraps(own.images.data(), own.tallies.data(), own.images.size());  // the wraps not yet drained
    std::vector<std::size_t> order(own.ids.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    // Two runs in id order: the disks that stayed, then those that came.
    std::inplace_merge(order.begin(), order.begin() + std::ptrdiff_t(held_->ownCount()), order.end(),
                       [&](std::size_t a, std::size_t b) { return own.ids[a] < own.ids[b]; });
    ids.resize(order.size());
    particles.resize(order.size());
    images.resize(order.size());
    parallelFor(order.size(), [&](std::size_t k) {
        ids[k] = own.ids[order[k]];
        particles[k] = own.particles[order[k]];
        images[k] = own.images[order[k]];
    });
}

std::vector<Image> DecomposedBackend::images() {
    if (!imagesCurrent_) {
        DomainDisks own = ownDisks();
        addWraps(own.images.data(), own.tallies.data(), own.images.size());  // the wraps not yet drained
        const std::vector<std::uint32_t> ids = gatherAll(comm_, own.ids, costs_);
        const std::vector<Image> all = gatherAll(comm_, own.images, costs_);
        parallelFor(all.size(), [&](std::size_t k) { images_[ids[k]] = all[k]; });
        imagesCurrent_ = true;
    }
    return images_;
}

}  // namespace carom
