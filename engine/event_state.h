// What the event-driven scheme (--collisions events) holds between events,
// in double: enough for a checkpoint to continue a run bit for bit. Each
// disk keeps its position and velocity at its own time (it is moved only
// when it takes part in an event) and its one scheduled event; the calendar
// and the cell lists are rebuilt from these, deterministically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/scene.h"

namespace carom {

// The scheduled event of a disk (EventDiskState::event): >= 0 is a
// collision with that disk; the negative codes are the rest.
constexpr std::int32_t kEventNone = -1;      // nothing will happen to it
constexpr std::int32_t kEventWallLeft = -2;  // walls: left, right, bottom, top
constexpr std::int32_t kEventWallRight = -3;
constexpr std::int32_t kEventWallBottom = -4;
constexpr std::int32_t kEventWallTop = -5;
constexpr std::int32_t kEventCrossLeft = -6;   // it leaves its cell to the left, right,
constexpr std::int32_t kEventCrossRight = -7;  //   below or above
constexpr std::int32_t kEventCrossDown = -8;
constexpr std::int32_t kEventCrossUp = -9;
constexpr std::int32_t kEventLowestCode = kEventCrossUp;

struct EventDiskState {
    double x = 0, y = 0;                  // centre at `time` [length]; periodic boxes keep it in its cell's image
    double vx = 0, vy = 0;                // velocity at `time` [length/time]
    double time = 0;                      // the time its position and velocity hold [time, since the state's origin]
    double eventTime = 0;                 // when its scheduled event happens [time]; infinite for kEventNone
    std::int32_t event = kEventNone;      // what happens then (codes above)
    std::uint32_t partnerCollisions = 0;  // a collision: the partner's `collisions` when it was
                                          //   scheduled (the event is stale once that changes)
    std::uint32_t collisions = 0;         // how often its velocity changed (collisions, walls), mod 2^32
    std::uint32_t cell = 0;               // its cell, row * columns + column (cells at least one
                                          //   largest diameter wide, EventDrivenBackend::cells())
};

struct EventEngineState {
    double time = 0;                    // the current time [time, since the state's origin]
    std::vector<EventDiskState> disks;  // in particle id order
};

// What is wrong with a state whatever the grid: values not finite, times
// out of order (0 <= a disk's time <= the state's <= its event's; no event
// exactly at +infinity), event codes that name no kind of event and no other
// disk, walls in a periodic box. Empty when nothing is. The engine's
// restore() adds what needs the grid (cells, crossings at the box's edge).
std::string eventStateProblem(const EventEngineState& state, Boundary boundary);

}  // namespace carom
