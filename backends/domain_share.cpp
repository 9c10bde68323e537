#include "backends/domain_share.h"

#include <algorithm>
#include <utility>

#include "engine/parallel.h"
#include "kernels/physics.h"

namespace carom {

void DomainDisks::resize(std::size_t n) {
    ids.resize(n);
    particles.resize(n);
    tallies.resize(n);
    images.resize(n);
}

int DomainMap::ownerOf(float2 position) const {
    const int column = carom_cell_coord(position.x, grid.cellsPerLengthX, grid.cols);
    const int row = carom_cell_coord(position.y, grid.cellsPerLengthY, grid.rows);
    return domainOfRow[std::size_t(row)] * domainsX + domainOfColumn[std::size_t(column)];
}

void HostDomainShare::load(const DomainDisks& own, const DomainMap& map, int rank) {
    map_ = map;
    rank_ = rank;
    const std::size_t n = own.ids.size();
    share_.particles = own.particles;
    share_.tallies.assign(n, ContactTally{});
    share_.lastRounds.clear();
    ids_ = own.ids;
    stayed_.resize(n);
    for (std::size_t k = 0; k < n; ++k) stayed_[k] = k;
    stayedImages_ = own.images;
}

void HostDomainShare::near(const std::vector<unsigned char>& nearColumns, const std::vector<unsigned char>& nearRows,
                           std::vector<std::uint32_t>& ids, std::vector<Particle>& particles) {
    const GridGeometry& g = map_.grid;
    const std::size_t stayed = stayed_.size();
    scratch_.resize(stayed);
    parallelFor(stayed, [&](std::size_t k) {
        const float2 at = share_.particles[stayed_[k]].position;
        scratch_[k] = nearColumns[std::size_t(carom_cell_coord(at.x, g.cellsPerLengthX, g.cols))] ||
                      nearRows[std::size_t(carom_cell_coord(at.y, g.cellsPerLengthY, g.rows))];
    });
    for (std::size_t k = 0; k < stayed; ++k)
        if (scratch_[k]) {
            ids.push_back(ids_[stayed_[k]]);
            particles.push_back(share_.particles[stayed_[k]]);
        }
}

// Three runs in id order, merged: the disks that stayed, those that came,
// the copies. A disk's slot is its place in its run plus how many disks of
// the other two have lower ids (counted by bisection); an own disk's place
// among the own ones, its place plus those of the other own run.
void HostDomainShare::mergeNext(const DomainDisks& arrived, const std::vector<std::uint32_t>& copyIds,
                                const std::vector<Particle>& copies) {
    const auto belowStayed = [&](std::uint32_t id) {
        return std::size_t(
            std::partition_point(stayed_.begin(), stayed_.end(), [&](std::size_t s) { return ids_[s] < id; }) -
            stayed_.begin());
    };
    const auto below = [](const std::vector<std::uint32_t>& ids, std::uint32_t id) {
        return std::size_t(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
    };
    const std::size_t stayed = stayed_.size(), came = arrived.ids.size(), copied = copyIds.size();
    const std::size_t total = stayed + came + copied;
    next_.particles.resize(total);
    next_.tallies.resize(total);
    nextIds_.resize(total);
    nextOwn_.resize(stayed + came);
    nextImages_.resize(stayed + came);
    // The stayed disks in blocks, each counting from a bisection onwards.
    parallelBlocks(stayed, [&](std::size_t first, std::size_t end) {
        if (first == end) return;
        std::size_t a = below(arrived.ids, ids_[stayed_[first]]), c = below(copyIds, ids_[stayed_[first]]);
        for (std::size_t k = first; k < end; ++k) {
            const std::size_t from = stayed_[k];
            const std::uint32_t id = ids_[from];
            while (a < came && arrived.ids[a] < id) ++a;
            while (c < copied && copyIds[c] < id) ++c;
            const std::size_t own = k + a, s = own + c;
            next_.particles[s] = share_.particles[from];
            next_.tallies[s] = share_.tallies[from];
            nextIds_[s] = id;
            nextOwn_[own] = s;
            nextImages_[own] = stayedImages_[k];
        }
    });
    for (std::size_t j = 0; j < came; ++j) {
        const std::uint32_t id = arrived.ids[j];
        const std::size_t own = j + belowStayed(id), s = own + below(copyIds, id);
        next_.particles[s] = arrived.particles[j];
        next_.tallies[s] = arrived.tallies[j];
        nextIds_[s] = id;
        nextOwn_[own] = s;
        nextImages_[own] = arrived.images[j];
    }
    parallelFor(copied, [&](std::size_t c) {
        const std::uint32_t id = copyIds[c];
        const std::size_t s = c + belowStayed(id) + below(arrived.ids, id);
        next_.particles[s] = copies[c];
        next_.tallies[s] = ContactTally{};
        nextIds_[s] = id;
    });
}

unsigned int HostDomainShare::stepNext(const Backend& whole, float dt) { return engine_->stepShare(next_, whole, dt); }

DomainShare::Kept HostDomainShare::keepNext() {
    // The stepped share holds the own disks from now on: nothing is copied back.
    std::swap(share_, next_);
    ids_.swap(nextIds_);
    stayed_.swap(nextOwn_);
    stayedImages_.swap(nextImages_);
    // Maxima and minima: exact whichever thread takes which disk.
    const bool rounds = !share_.lastRounds.empty();
    std::vector<Kept> kept(static_cast<std::size_t>(parallelThreads()));
    parallelFor(stayed_.size(), [&](std::size_t k) {
        const std::size_t s = stayed_[k];
        Kept& mine = kept[std::size_t(threadNumber())];
        if (rounds) mine.lastRound = std::max(mine.lastRound, share_.lastRounds[s]);
        if (!carom_is_finite(share_.particles[s])) mine.nonFinite = std::min(mine.nonFinite, ids_[s]);
    });
    Kept all;
    for (const Kept& mine : kept) {
        all.lastRound = std::max(all.lastRound, mine.lastRound);
        all.nonFinite = std::min(all.nonFinite, mine.nonFinite);
    }
    return all;
}

void HostDomainShare::takeLeavers(DomainDisks& leavers) {
    const std::size_t stayed = stayed_.size();
    owners_.resize(stayed);
    parallelFor(stayed, [&](std::size_t k) { owners_[k] = map_.ownerOf(share_.particles[stayed_[k]].position); });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < stayed; ++k) {
        const std::size_t s = stayed_[k];
        if (owners_[k] == rank_) {  // stays: its slot and image move up over those that left
            stayed_[kept] = s;
            stayedImages_[kept++] = stayedImages_[k];
            continue;
        }
        leavers.ids.push_back(ids_[s]);
        leavers.particles.push_back(share_.particles[s]);
        leavers.tallies.push_back(share_.tallies[s]);
        leavers.images.push_back(stayedImages_[k]);
    }
    stayed_.resize(kept);
    stayedImages_.resize(kept);
}

DomainDisks HostDomainShare::own() const {
    DomainDisks own;
    own.resize(stayed_.size());
    parallelFor(stayed_.size(), [&](std::size_t k) {
        const std::size_t s = stayed_[k];
        own.ids[k] = ids_[s];
        own.particles[k] = share_.particles[s];
        own.tallies[k] = share_.tallies[s];
        own.images[k] = stayedImages_[k];
    });
    return own;
}

float HostDomainShare::maxSpeedSquared() {
    std::vector<float> largest(std::size_t(parallelThreads()), 0.0f);
    parallelFor(stayed_.size(), [&](std::size_t k) {
        const float2 v = share_.particles[stayed_[k]].velocity;
        const std::size_t t = std::size_t(threadNumber());
        largest[t] = std::max(largest[t], v.x * v.x + v.y * v.y);
    });
    return *std::max_element(largest.begin(), largest.end());
}

void HostDomainShare::clearTallies() {
    parallelFor(stayed_.size(),
                [&](std::size_t k) { carom::clearTallies(&share_.tallies[stayed_[k]], 1, &stayedImages_[k]); });
}

}  // namespace carom
