#include "app/number_options.h"

#include "engine/carom.h"
#include "engine/number_text.h"

namespace carom::app {

CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max) {
    return CLI::Validator(
        [min, max](std::string& text) {
            try {
                text = std::to_string(parseWholeNumber(text, min, max));  // no leading 0 for CLI11 to read as octal
                return std::string();
            } catch (const Error& e) {
                return std::string(e.what());
            }
        },
        "");
}

CLI::Validator realNumber() {
    return CLI::Validator(
        [](std::string& text) {
            try {
                parseRealNumber(text);
                return std::string();
            } catch (const Error& e) {
                return std::string(e.what());
            }
        },
        "");
}

}  // namespace carom::app
