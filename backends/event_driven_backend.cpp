#include "backends/event_driven_backend.h"

// Placeholder so the tree builds while the engine is written (replaced by the next commit).
namespace carom {
EventDrivenBackend::EventDrivenBackend(const WorldDef& world) : Backend(world) {}
std::string EventDrivenBackend::device() const { return "CPU, one thread, double precision"; }
void EventDrivenBackend::readParticles(std::vector<Particle>&) { throw Error("events: not yet"); }
std::vector<ExactDisk> EventDrivenBackend::exactState() const { throw Error("events: not yet"); }
double EventDrivenBackend::kineticEnergy() const { throw Error("events: not yet"); }
double EventDrivenBackend::totalEnergy() const { throw Error("events: not yet"); }
EventEngineState EventDrivenBackend::saveState() const { throw Error("events: not yet"); }
void EventDrivenBackend::restore(const EventEngineState&) { throw Error("events: not yet"); }
void EventDrivenBackend::load(std::vector<Particle>) { throw Error("events: not yet"); }
void EventDrivenBackend::advance(std::uint64_t, float) { throw Error("events: not yet"); }
float EventDrivenBackend::maxSpeedSquared() { throw Error("events: not yet"); }
void EventDrivenBackend::drainTallies(ContactTotals&) {}
void EventDrivenBackend::motionChanged() {}
}  // namespace carom
