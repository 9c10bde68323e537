// Option values that were renamed: the old name still works, with a notice.
#pragma once

#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

namespace carom::app {

// A CLI11 transform that reads `old`, a value of `option` under its former
// name, as `now`, and says so in one line on stderr.
inline CLI::Validator renamedValue(const std::string& option, const std::string& old, const std::string& now) {
    return CLI::Validator(
        [option, old, now](std::string& text) {
            if (text == old) {
                std::cerr << "carom: " << option << ' ' << old << " is now called " << now
                          << "; the old name still works, for now\n";
                text = now;
            }
            return std::string();
        },
        "");
}

}  // namespace carom::app
