#include "engine/observables.h"

namespace carom {

double temperature(const std::vector<Particle>& particles, Boundary boundary) {
    double kinetic = 0.0, mass = 0.0, px = 0.0, py = 0.0;
    for (const Particle& p : particles) {
        const double vx = p.velocity.x, vy = p.velocity.y;
        kinetic += 0.5 * p.mass * (vx * vx + vy * vy);
        mass += p.mass;
        px += p.mass * vx;
        py += p.mass * vy;
    }
    const double n = double(particles.size());
    if (boundary == Boundary::Walls) return n > 0 ? kinetic / n : 0.0;
    // Periodic: the centre-of-mass motion is conserved, so it is not heat.
    if (n < 2) return 0.0;
    return centreOfMassFrameKinetic(kinetic, {px, py}, mass) / (n - 1.0);
}

Thermodynamics thermodynamics(const ContactTotals& contacts, double kT, std::size_t particleCount,
                              const WorldDef& world) {
    Thermodynamics t;
    t.temperature = kT;
    const double n = double(particleCount);
    const double area = double(world.width) * world.height;
    const double time = contacts.time;
    if (n == 0 || !(time > 0)) return t;
    t.collisionRate = double(contacts.collisions) / (n * time);
    // P A = E_kin + virial / (2 t), with the thermal kinetic energy: in a
    // periodic box the centre of mass takes one of the N degree-of-freedom
    // pairs (temperature() divides by N - 1 there), so E_kin = (N - 1) kT.
    const double thermalPairs = world.boundary == Boundary::Periodic ? n - 1.0 : n;
    t.virialPressure = (thermalPairs * kT + contacts.virial / (2.0 * time)) / area;
    if (kT > 0) t.virialZ = t.virialPressure * area / (n * kT);
    if (world.boundary == Boundary::Walls) {
        const double lengths[4] = {world.height, world.height, world.width, world.width};
        double impulse = 0.0;
        for (int w = 0; w < 4; ++w) {
            t.wallPressure[w] = contacts.wallImpulse[w] / (time * lengths[w]);
            impulse += contacts.wallImpulse[w];
        }
        t.wallPressureMean = impulse / (time * 2.0 * (double(world.width) + world.height));
        if (kT > 0) t.wallZ = t.wallPressureMean * area / (n * kT);
    }
    return t;
}

}  // namespace carom
