// libFuzzer harness: any bytes as a checkpoint are either a valid checkpoint
// or a carom::Error, never a crash or another exception; a valid one encodes
// back to exactly the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/checkpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        const carom::Checkpoint checkpoint = carom::decodeCheckpoint(bytes, "fuzz.ckpt");
        if (carom::encodeCheckpoint(checkpoint) != bytes) std::abort();
    } catch (const carom::Error&) {
    }
    return 0;
}
