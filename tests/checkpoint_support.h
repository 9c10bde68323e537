// Helpers for the checkpoint tests: a state whose every field matters, and
// changes to a checkpoint's bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/checkpoint.h"
#include "support.h"

namespace carom::test {

struct Scenario {
    WorldDef world;
    std::vector<Particle> particles;
};

// `particles` polydisperse disks of unequal masses, moving, in a walled box
// at packing 0.4, with time step `dt`.
inline Scenario polydisperseDisks(std::uint32_t particles, float dt) {
    SceneDef scene;
    scene.particles = particles;
    scene.packing = 0.4f;
    scene.radiusMin = 0.5f;
    scene.radiusMax = 1.2f;
    scene.massMin = 0.5f;
    scene.massMax = 4.0f;
    scene.speed = 1.5f;
    const InitialState s = makeInitialState(scene);
    return Scenario{box(s.width, s.height, dt), s.particles};
}

// decodeCheckpoint's refusal of `bytes` (named "c.ckpt"); empty when it reads them.
inline std::string errorOf(const std::string& bytes) {
    try {
        decodeCheckpoint(bytes, "c.ckpt");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

inline void putU32(std::string& bytes, std::size_t offset, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>(v >> (8 * i));
}

// Rewrites the trailing checksum, as if the bytes had been written so.
inline void reseal(std::string& bytes) {
    const std::size_t checked = bytes.size() - 4;
    putU32(bytes, checked, crc32(reinterpret_cast<const unsigned char*>(bytes.data()), checked));
}

// A current checkpoint of `particles` disks as version `version` (2 or 3)
// wrote it: without the images (version 4's), resealed.
inline std::string asVersion(std::string bytes, std::uint32_t version, std::size_t particles) {
    bytes.erase(76 + 24 * particles, 8 * particles);
    putU32(bytes, 12, version);
    reseal(bytes);
    return bytes;
}

}  // namespace carom::test
