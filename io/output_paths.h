// Where an output file really goes, and what an existing one already holds.
//
// An output path may be a symlink (carom writes its target and the link
// stays a link), a special file such as a FIFO or a character device
// (written directly: a device node is never replaced by a regular file), or
// a regular file or a new name (written to PATH.partial beside the target,
// then renamed onto it: see include/carom/files.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>

#include <carom/files.h>
#include <string>

namespace carom {

// Whether `path` (through symlinks) is a regular file with something in it.
bool hasContent(const std::string& path);

// Opens `path`, a regular file, to be read in binary from its start, and
// sets `size` to its size; throws Error "cannot read WHAT 'PATH': ..." when
// it is missing, a directory or a device, or cannot be opened.
std::ifstream openRegularFile(const std::string& path, const std::string& what, std::streamoff& size);

// The lines of a file from its last to its first, reading backwards in
// blocks, so the end of a large trajectory is found without reading it all.
class LinesFromEnd {
public:
    // Throws Error if `path` cannot be read.
    explicit LinesFromEnd(const std::string& path);

    // The previous line, without its '\n' (a final '\n' ends the last line,
    // it does not start an empty one); false before the first line.
    bool previous(std::string& line);

private:
    std::ifstream in_;
    std::string path_;
    std::streamoff unread_ = 0;  // bytes [0, unread_) are not in pending_ yet
    std::string pending_;        // read, not yet returned: the text just before what previous() returned
    bool done_ = false;
};

// The integer that `text` is exactly (digits only), if it fits in 64 bits.
bool parseStep(const std::string& text, std::uint64_t& step);

// Throws Error: `path` cannot be continued by a resumed run, `why`.
[[noreturn]] void refuseToAppend(const std::string& path, const std::string& why);

// Throws Error unless an output whose last `item` ("frame", "row") is at
// step `last` can take the samples of a run resumed from a checkpoint at
// step `resumedAt`: appended, they must not repeat a step.
void requireAppendable(const std::string& path, const char* item, std::uint64_t last, std::uint64_t resumedAt);

}  // namespace carom
