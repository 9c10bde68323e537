// libFuzzer harness: any bytes as a scene file are either a scene or a
// carom::Error, never a crash, a hang or another exception. Scenes small
// enough are also placed, which runs the lattice and overlap checks.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <carom/io.h>

#include "engine/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const carom::SceneFileDef scene =
            carom::io::parseSceneFile(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml");
        std::uint64_t particles = scene.disks.size();
        for (const carom::GroupDef& group : scene.groups) particles += group.count;
        if (particles <= 2000) carom::makeInitialState(scene);
    } catch (const carom::Error&) {
    }
    return 0;
}
