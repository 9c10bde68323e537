#include "io/output_paths.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>

#include "engine/scene.h"

namespace carom {
namespace fs = std::filesystem;

bool hasContent(const std::string& path) {
    std::error_code error;
    return fs::is_regular_file(path, error) && fs::file_size(path, error) > 0 && !error;
}

std::ifstream openRegularFile(const std::string& path, const std::string& what, std::streamoff& size) {
    std::error_code error;
    if (!fs::is_regular_file(path, error))
        throw Error("cannot read " + what + " '" + path +
                    "': " + (fs::exists(path, error) ? "not a regular file" : "no such file"));
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error("cannot read " + what + " '" + path + "': " + std::strerror(errno));
    size = in.tellg();
    in.seekg(0);
    return in;
}

LinesFromEnd::LinesFromEnd(const std::string& path) : in_(path, std::ios::binary), path_(path) {
    if (!in_) throw Error("cannot read '" + path + "': " + std::strerror(errno));
    in_.seekg(0, std::ios::end);
    unread_ = in_.tellg();
    if (unread_ > 0) {
        in_.seekg(unread_ - 1);
        if (in_.get() == '\n') --unread_;
    } else {
        done_ = true;
    }
}

bool LinesFromEnd::previous(std::string& line) {
    constexpr std::streamoff kBlockBytes = 1 << 14;
    if (done_) return false;
    for (;;) {
        const std::size_t newline = pending_.rfind('\n');
        if (newline != std::string::npos) {
            line.assign(pending_, newline + 1);
            offset_ = unread_ + std::streamoff(newline) + 1;
            pending_.resize(newline);
            return true;
        }
        if (unread_ == 0) {
            line = std::move(pending_);
            pending_.clear();
            offset_ = 0;
            done_ = true;
            return true;
        }
        if (std::streamoff(pending_.size()) > kMaxLineBytes)
            throw Error("'" + path_ + "' has a line longer than " + std::to_string(kMaxLineBytes) +
                        " bytes, which no carom file has");
        const std::streamoff block = std::min(unread_, kBlockBytes);
        unread_ -= block;
        std::string text(static_cast<std::size_t>(block), '\0');
        in_.seekg(unread_);
        if (!in_.read(text.data(), block)) throw Error("reading '" + path_ + "' failed");
        pending_.insert(0, text);
    }
}

bool parseStep(const std::string& text, std::uint64_t& step) {
    const char* end = text.data() + text.size();
    const std::from_chars_result parsed = std::from_chars(text.data(), end, step);
    return !text.empty() && parsed.ec == std::errc() && parsed.ptr == end;
}

void refuseToAppend(const std::string& path, const std::string& why) {
    throw Error("cannot append to '" + path + "': " + why + "; write to another file, or remove it to start anew");
}

void requireAppendable(const std::string& path, const char* item, std::uint64_t last, const Resumed& resumed) {
    const std::string at = std::string("its last ") + item + " is at step " + std::to_string(last);
    if (last > resumed.step)
        refuseToAppend(path, at + ", after " + resumed.name + "'s step " + std::to_string(resumed.step) +
                                 ", so the resumed run would repeat steps");
    if (resumed.every == 0) return;
    const std::uint64_t sample = resumed.step - resumed.step % resumed.every;
    if (last < sample)
        refuseToAppend(path, at + ", but sampling every " + std::to_string(resumed.every) + " steps up to " +
                                 resumed.name + "'s step " + std::to_string(resumed.step) + " reaches step " +
                                 std::to_string(sample) +
                                 ", so the samples in between would be missing (was it written by this run?)");
}

}  // namespace carom
