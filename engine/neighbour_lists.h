// Neighbour lists with a skin (Verlet lists, as HOOMD-blue and LAMMPS keep
// them), for the pairwise scheme on the CPU: each disk lists the disks whose
// centres lie within its contact distance plus the skin, ascending by id.
// While no disk has moved more than a share of the skin since the lists were
// built, they hold every pair that can meet within a substep, and a substep
// searches them instead of building the grid and searching its 3 x 3 cells.
// The pairwise scheme's earliest events are minima over the candidates, so
// a search over the lists gives what a search over the grid gives, bit for
// bit (kernels/pairwise.h, CaromNeighbours).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/grid.h"
#include "kernels/pairwise.h"

namespace carom {

class NeighbourLists {
public:
    // The skin: `asked` (WorldDef::skin) where it is > 0; else, for disks of
    // largest radius `maxRadius` that travel less than `travel` a substep
    // (Backend's grid allowance), half a diameter, and room for the
    // substep's travel besides.
    static float skinFor(float asked, float maxRadius, float travel);
    // The grid lists of this skin are built from, for `count` disks of
    // largest radius `maxRadius`: cells widened by the skin, whose 3 x 3
    // hold every disk within reach; none where the box is too small for
    // cells that wide (a periodic box under 3 of them a side).
    static std::optional<GridGeometry> gridFor(CaromBox box, float maxRadius, std::size_t count, float skin);

    // A build runs in phases, each shared by a team of threads (the same
    // lists, bit for bit, whoever runs what): begin (one thread), the
    // grid's phases (grid(), builder()), collect for every disk, sum (one
    // thread), place for every chunk. begin returns false, and nothing is
    // built, where gridFor has no grid or the disks are too many.
    bool begin(const Particle* particles, std::size_t count, float maxRadius, float skin, CaromBox box, int threads,
               std::size_t chunk);
    // Every phase at once, on a team of `threads` (outside a substep: the
    // benchmark's profile times it so).
    bool build(const Particle* particles, std::size_t count, float maxRadius, float skin, CaromBox box, int threads);
    Grid& grid() { return grid_; }
    GridBuilder& builder() { return builder_; }
    // Disk i's list, ascending, into the scratch of its chunk (disks
    // [c * chunk, (c + 1) * chunk), which one thread collects in order).
    void collect(std::size_t i);
    // Where each disk's list starts.
    void sum();
    std::size_t chunks() const { return chunkLists_.size(); }
    // Chunk c's lists into place; once every chunk is, the lists are built
    // (unless sum found them too long for 32-bit offsets).
    void place(std::size_t c);

    // Whether the lists built last still hold every pair that can meet in a
    // substep in which no disk travels `travel` or more, after the disks
    // moved at most sqrt(maxDisplacementSquared) since the build (carom_lists_cover).
    bool hold(float maxDisplacementSquared, float travel) const {
        return built_ && carom_lists_cover(skin_, maxDisplacementSquared, travel);
    }
    void clear() { built_ = false; }
    bool built() const { return built_; }

    // Disk i's list: list()[starts()[i] .. starts()[i + 1]).
    const std::uint32_t* starts() const { return starts_.data(); }
    const std::uint32_t* list() const { return list_.data(); }
    // How far disk i at `position` is from where the build found it, squared
    // (to the nearest image in a periodic box).
    float displacementSquared(std::size_t i, Vec2 position) const {
        return carom_displacement_squared(position, origins_[i], box_);
    }

private:
    bool built_ = false, fits_ = false;
    float skin_ = 0.0f;
    CaromBox box_{};
    const Particle* particles_ = nullptr;  // those being built for
    std::size_t count_ = 0, chunk_ = 1;
    Grid grid_;
    GridBuilder builder_;
    std::vector<std::uint32_t> starts_, list_;
    std::vector<std::vector<std::uint32_t>> chunkLists_;  // collect's scratch
    std::vector<Vec2> origins_;                           // the positions at the build, by id
};

}  // namespace carom
