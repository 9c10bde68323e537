// libFuzzer harness: any bytes as a state CSV are either particles or a
// carom::Error, never a crash or another exception.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "io/state_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        carom::parseStateCsv(in, "fuzz.csv");
    } catch (const carom::Error&) {
    }
    return 0;
}
