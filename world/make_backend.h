// The backend factory: the one place that knows every Backend class.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "backends/backend.h"

namespace carom {

// Creates the backend `def.kind` for the world; throws Error for an unknown
// kind or device, or when OpenCL is unavailable.
std::unique_ptr<Backend> makeBackend(const WorldDef& world);
// The same on `engine`, whatever world.engine says.
inline std::unique_ptr<Backend> makeBackend(const EngineDef& engine, const WorldDef& world) {
    return makeBackend(onEngine(world, engine));
}

// The backend kinds this build offers, for messages and tests.
std::vector<std::string> availableBackends();

}  // namespace carom
