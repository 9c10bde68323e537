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
#include <carom/types.h>
#include <string>
#include <vector>

namespace carom {

// Whether `path` (through symlinks) is a regular file with something in it.
bool hasContent(const std::string& path);

// Opens `path`, a regular file, to be read in binary from its start, and
// sets `size` to its size; throws Error "cannot read WHAT 'PATH': ..." when
// it is missing, a directory or a device, or cannot be opened.
std::ifstream openRegularFile(const std::string& path, const std::string& what, std::streamoff& size);

// Longer than any line carom writes in a trajectory or statistics file: a
// longer one is refused at once, not read whole.
constexpr std::streamoff kMaxLineBytes = std::streamoff(1) << 16;

// The lines of a file from its last to its first, reading backwards in
// blocks, so the end of a large trajectory is found without reading it all.
// A line longer than kMaxLineBytes is refused (Error), so that a file of one
// huge line takes as long as a block to refuse.
class LinesFromEnd {
public:
    // Throws Error if `path` cannot be read.
    explicit LinesFromEnd(const std::string& path);

    // The previous line, without its '\n' (a final '\n' ends the last line,
    // it does not start an empty one); false before the first line.
    bool previous(std::string& line);

    // Where the line previous() returned last starts in the file.
    std::streamoff offset() const { return offset_; }

private:
    std::ifstream in_;
    std::string path_;
    std::streamoff unread_ = 0;  // bytes [0, unread_) are not in pending_ yet
    std::string pending_;        // read, not yet returned: the text just before what previous() returned
    std::streamoff offset_ = 0;
    bool done_ = false;
};

// The integer that `text` is exactly (digits only), if it fits in 64 bits.
bool parseStep(const std::string& text, std::uint64_t& step);

// Throws Error: `path` cannot be continued by a resumed run, `why`.
[[noreturn]] void refuseToAppend(const std::string& path, const std::string& why);

// The checkpoint a run resumes from, which the files it appends to must
// lead up to.
struct Resumed {
    std::uint64_t step = 0;               // the checkpoint's
    double time = 0.0;                    // its simulated time
    std::uint64_t collisions = 0;         // its collision count
    std::uint64_t every = 0;              // the run's steps between samples; 0: not known (any sample up to `step`)
    std::vector<Disk> disks;              // its disks, in id order
    WorldDef world;                       // its box, boundary, ...
    std::string name = "the checkpoint";  // what refusals call it ("the world" for a world of the API)
};

// Throws Error unless an output whose last `item` ("frame", "row") is at
// step `last` can take the samples of a run resumed from `resumed`:
// appended, they must not repeat a step, nor leave out one (with `every`
// known, `last` is at or after the last multiple of it up to the checkpoint).
void requireAppendable(const std::string& path, const char* item, std::uint64_t last, const Resumed& resumed);

}  // namespace carom
