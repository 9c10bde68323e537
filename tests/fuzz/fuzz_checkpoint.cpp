// libFuzzer harness: any bytes as a checkpoint are either a valid checkpoint
// or a carom::Error, never a crash or another exception; a valid one of the
// current version encodes back to exactly the same bytes, and an older one
// to a current-version file that decodes to the same checkpoint.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/checkpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        const carom::Snapshot snapshot = carom::decodeCheckpoint(bytes, "fuzz.ckpt");
        const std::string encoded = carom::encodeCheckpoint(snapshot);
        const bool currentVersion = data[12] == carom::kCheckpointVersion;  // decoded: at least 16 bytes
        if (currentVersion ? encoded != bytes
                           : carom::encodeCheckpoint(carom::decodeCheckpoint(encoded, "fuzz.ckpt")) != encoded)
            std::abort();
    } catch (const carom::Error&) {
    }
    return 0;
}
