// carom: 2D elastic disk collisions, on the CPU or an OpenCL device.
//
// The whole public API: carom/types.h (definitions and limits),
// carom/world.h (World), carom/random.h (the generator behind makeScene)
// and carom/version.h. Files (scene files, state CSV, checkpoints,
// trajectories, statistics) are in carom/io.h, a separate library (carom::io).
#pragma once

#include <carom/random.h>
#include <carom/types.h>
#include <carom/version.h>
#include <carom/world.h>
