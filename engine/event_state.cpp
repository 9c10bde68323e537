#include "engine/event_state.h"

#include <cmath>
#include <cstdint>
#include <utility>

#include "engine/text_format.h"

namespace carom {

std::string eventStateProblem(const EventEngineState& state, Boundary boundary) {
    std::string problem;
    auto number = [&problem](const char* name, double value) {
        problem += name;
        problem += ' ';
        appendNumber(problem, value);
    };
    if (!std::isfinite(state.time) || state.time < 0) {
        number("events state: time", state.time);
        return problem + " must be a finite number >= 0";
    }
    const std::int64_t count = static_cast<std::int64_t>(state.disks.size());
    for (std::int64_t i = 0; i < count; ++i) {
        const EventDiskState& d = state.disks[i];
        problem = "events state: disk " + std::to_string(i) + ": ";
        const std::pair<const char*, double> values[] = {
            {"x", d.x}, {"y", d.y}, {"vx", d.vx}, {"vy", d.vy}, {"time", d.time}};
        for (const auto& [name, value] : values)
            if (!std::isfinite(value)) {
                number(name, value);
                return problem + " must be finite";
            }
        if (d.event < kEventLowestCode || d.event >= count) {
            problem += "event code " + std::to_string(d.event) +
                       " is unknown; allowed: " + std::to_string(kEventLowestCode) +
                       " to -1 (kinds of event) or a partner id from 0 to " + std::to_string(count - 1);
            return problem;
        }
        if (d.event == i)
            return problem + "its event is a collision with itself (event code " + std::to_string(i) + ")";
        if (boundary == Boundary::Periodic && d.event <= kEventWallLeft && d.event >= kEventWallTop)
            return problem + "event code " + std::to_string(d.event) + " is a wall bounce, but the box is periodic";
        const bool none = d.event == kEventNone;
        if (none ? d.eventTime != HUGE_VAL : !std::isfinite(d.eventTime)) {
            number("event time", d.eventTime);
            return problem + (none ? " must be +infinity for event code -1 (no event)"
                                   : " must be finite for event code " + std::to_string(d.event));
        }
        if (!(d.time >= 0 && d.time <= state.time)) {
            number("time", d.time);
            problem += " must lie in [0, the state's time ";
            appendNumber(problem, state.time);
            return problem + "]";
        }
        if (!(d.eventTime >= state.time)) {
            number("event time", d.eventTime);
            problem += " is before the state's time ";
            appendNumber(problem, state.time);
            return problem;
        }
    }
    return {};
}

std::string eventStatePlaceProblem(const Snapshot& s) {
    const bool events = s.world.collisions == CollisionScheme::Events;
    if (events == s.events.has_value() && (!events || s.events->disks.size() == s.disks.size())) return {};
    return std::string("a snapshot holds the engine's state exactly with the events scheme (here ") +
           collisionSchemeName(s.world.collisions) + ", " +
           (s.events ? std::to_string(s.events->disks.size()) + " disks in the state" : "no state") + ", " +
           std::to_string(s.disks.size()) + " particles)";
}

}  // namespace carom
