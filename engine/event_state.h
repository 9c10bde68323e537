// The checks of the event-driven scheme's exact state (carom/types.h
// EventEngineState), which a snapshot and a checkpoint hold so that a run
// continues bit for bit.
#pragma once

#include <string>

#include <carom/types.h>

namespace carom {

// What is wrong with a state whatever the grid: values not finite, times
// out of order (0 <= a disk's time <= the state's <= its event's; no event
// exactly at +infinity), event codes that name no kind of event and no other
// disk, walls in a periodic box. Empty when nothing is. The engine's
// restoreState() adds what needs the grid (cells, crossings at the box's edge).
std::string eventStateProblem(const EventEngineState& state, Boundary boundary);

// What is wrong with where `snapshot` holds an events state: it must hold
// one exactly with CollisionScheme::Events, with a state per disk. Empty
// when nothing is.
std::string eventStatePlaceProblem(const Snapshot& snapshot);

}  // namespace carom
