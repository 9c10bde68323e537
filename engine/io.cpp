// carom::io (include/carom/io.h): the file readers and writers, on the public types.
#include <carom/io.h>

#include "backends/event_driven_backend.h"
#include "engine/checkpoint.h"
#include "engine/disk_conversion.h"
#include "engine/scene_file.h"
#include "engine/state_csv.h"
#include "engine/world_impl.h"

namespace carom::io {

SceneFile loadScene(const std::string& path) {
    const carom::SceneFile scene = readSceneFile(path);
    InitialState state = makeInitialState(scene);
    SceneFile loaded;
    loaded.world = scene.world;
    loaded.world.width = state.width;
    loaded.world.height = state.height;
    loaded.disks = disksOf(state.particles);
    loaded.steps = scene.steps;
    return loaded;
}

std::vector<Disk> readState(const std::string& path) { return disksOf(readStateCsv(path)); }

void writeState(const std::string& path, const std::vector<Disk>& disks) {
    writeStateCsv(path, particlesOf(disks.data(), disks.size()));
}

void saveCheckpoint(const std::string& path, const World& world) {
    auto& impl = WorldAccess::of(world);
    if (world.diskCount() == 0) throw Error("saveCheckpoint '" + path + "': the world has no disks yet");
    Checkpoint c;
    c.world = impl.def;
    c.step = impl.step;
    c.time = world.time();
    c.collisions = world.collisionCount();
    c.particles = impl.current();
    if (auto* events = dynamic_cast<const EventDrivenBackend*>(impl.backend.get())) c.events = events->saveState();
    writeCheckpoint(path, c);
}

World loadCheckpoint(const std::string& path, const WorldDef& def) {
    Checkpoint c = readCheckpoint(path);
    WorldDef resumed = c.world;
    resumed.engine = def.engine;
    resumed.device = def.device;
    resumed.maxTravel = def.maxTravel;
    World world(resumed);
    auto& impl = WorldAccess::of(world);
    impl.start(std::move(c.particles), c.step, c.time, c.collisions);
    if (c.events) {
        try {
            dynamic_cast<EventDrivenBackend&>(*impl.backend).restore(*c.events);
        } catch (const Error& e) {
            throw Error("checkpoint '" + path + "': " + e.what());
        }
        impl.stateCurrent = false;  // the float projection of the restored exact state
    }
    return world;
}

}  // namespace carom::io
