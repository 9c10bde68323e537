#include "app/number_options.h"

#include <cmath>

#include <carom/io.h>

#include <carom/types.h>

namespace carom::app {
namespace {

// A CLI11 validator that runs `check` on the option's text (which it may
// rewrite) and refuses the value with the message of the Error it throws.
template <class Check>
CLI::Validator refusingErrors(Check check) {
    return CLI::Validator(
        [check](std::string& text) {
            try {
                check(text);
                return std::string();
            } catch (const Error& e) {
                return std::string(e.what());
            }
        },
        "");
}

}  // namespace

CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max) {
    return refusingErrors([min, max](std::string& text) {
        text = std::to_string(io::parseWholeNumber(text, min, max));  // no leading 0 for CLI11 to read as octal
    });
}

std::uint64_t parseParticleCount(const std::string& text, std::uint64_t min, std::uint64_t max) {
    double value = NAN;
    try {
        value = io::parseRealNumber(text);
    } catch (const Error&) {  // refused below, with the range
    }
    const std::string allowed = io::wholeNumbersAllowed(min, max) + ", such as 1000 or 1.6e7";
    if (!std::isfinite(value) || value != std::floor(value))
        throw Error("'" + io::printable(text) + "' is not a number of particles; " + allowed);
    if (value < double(min) || value > double(max))
        throw Error("'" + io::printable(text) + "' is out of range; " + allowed);
    return std::uint64_t(value);
}

CLI::Validator particleCount(std::uint64_t min, std::uint64_t max) {
    return refusingErrors([min, max](std::string& text) { text = std::to_string(parseParticleCount(text, min, max)); });
}

CLI::Validator realNumber() {
    // CLI11 reads the text through a long double, which could round twice: it gets the float's exact text.
    return refusingErrors([](std::string& text) { text = io::shortestText(io::parseFloat(text)); });
}

}  // namespace carom::app
