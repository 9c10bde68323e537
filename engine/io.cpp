// carom::io (include/carom/io.h): the file readers and writers, on the public types.
#include <carom/io.h>

#include "engine/disk_conversion.h"
#include "engine/scene_file.h"
#include "engine/state_csv.h"

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

}  // namespace carom::io
