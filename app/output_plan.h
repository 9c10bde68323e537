// The files a subcommand reads and writes (run, view, bench, validate),
// checked together before any work, so that no output is lost to another,
// replaces an input, or fails only after the work is done.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

namespace carom::app {

// `option` (a file option) refuses an empty name, naming the option, instead
// of taking it as "not given".
CLI::Option* fileOption(CLI::Option* option);

class OutputPlan {
public:
    // A file the command reads, named by `option` (or a scene file's key).
    void input(std::string option, std::string path);
    // A file the command writes.
    void output(std::string option, std::string path);
    // A folder the command writes files into, created if missing; `writes`
    // says whether a file name is one of those it writes there.
    void outputFolder(std::string option, std::string path, std::function<bool(const std::string&)> writes);
    // The output `output` may be the input `input`, which is read whole
    // before it is replaced (a resumed run's checkpoint).
    void allowReplacing(std::string input, std::string output);

    // Refuses, naming the options and paths: two outputs that are one file
    // under any spelling (symlinks, hard links, bind mounts, "./") but a
    // character device, an output named as another's temporary file, an
    // output that would replace an input or a file of a folder output, an
    // output that is the regular file standard output or error goes to, a
    // folder output that is a file, and an output whose folder is missing or
    // cannot be written.
    void check() const;

private:
    struct Named {
        std::string option, path;
    };
    struct Folder {
        std::string option, path;
        std::function<bool(const std::string&)> writes;
    };
    void checkOutput(const Named& output) const;
    void checkFolder(const Folder& folder) const;
    void checkPlace(const Named& output) const;

    std::vector<Named> inputs_, outputs_;
    std::vector<Folder> folders_;
    std::vector<std::pair<std::string, std::string>> replaceable_;  // (input, output) options
};

// Creates a folder output (and the folders above it); Error naming `option`.
void createFolder(const std::string& option, const std::string& path);

}  // namespace carom::app
