#include "engine/diagnostics.h"

#include <algorithm>
#include <cmath>

#include "engine/grid.h"

namespace carom {

Diagnostics measureMotion(const std::vector<Particle>& particles, const WorldDef& world) {
    Diagnostics d;
    for (const Particle& p : particles) {
        const double vx = p.velocity.x, vy = p.velocity.y;
        d.kineticEnergy += 0.5 * p.mass * (vx * vx + vy * vy);
        d.momentum[0] += p.mass * vx;
        d.momentum[1] += p.mass * vy;
        d.potentialEnergy -= p.mass * (double(world.gravity.x) * p.position.x + double(world.gravity.y) * p.position.y);
        const float2 x = p.position;
        const bool inside = x.x >= 0.0f && x.x <= world.width && x.y >= 0.0f && x.y <= world.height;
        if (!inside) ++d.escaped;  // also counts NaN
    }
    return d;
}

Overlaps findOverlaps(const std::vector<Particle>& particles, const WorldDef& world) {
    Overlaps found;
    float maxRadius = 0.0f;
    for (const Particle& p : particles) maxRadius = std::max(maxRadius, p.radius);

    Grid grid;
    grid.geometry = gridGeometryFor(world.width, world.height, maxRadius, particles.size(), world.boundary);
    buildGrid(particles.data(), particles.size(), grid);
    const bool periodic = world.boundary == Boundary::Periodic;
    const CaromBox box = caromBoxOf(world);
    // The separation along one axis, to the nearest image in a periodic box.
    const auto separation = [&](double d, double extent) {
        if (!periodic) return d;
        return d - extent * std::round(d / extent);
    };
    forEachOverlappingPair(particles.data(), particles.size(), grid, box, [&](std::uint32_t i, std::uint32_t j) {
        const Particle& a = particles[i];
        const Particle& b = particles[j];
        const double distance = std::hypot(separation(double(a.position.x) - b.position.x, world.width),
                                           separation(double(a.position.y) - b.position.y, world.height));
        const double overlap = double(a.radius) + b.radius - distance;
        ++found.pairs;
        if (overlap > found.deepest) {
            found.deepest = overlap;
            found.deepestPair = {i, j};
        }
        if (distance == 0.0 && found.coincident++ == 0) found.coincidentPair = {i, j};
    });
    return found;
}

Diagnostics measure(const std::vector<Particle>& particles, const WorldDef& world) {
    Diagnostics d = measureMotion(particles, world);
    d.maxOverlap = findOverlaps(particles, world).deepest;
    return d;
}

}  // namespace carom
