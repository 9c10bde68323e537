#include "engine/output_paths.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>

#include "engine/carom.h"

namespace carom {
namespace fs = std::filesystem;

namespace {

// As POSIX's SYMLOOP_MAX on Linux: a longer chain is a loop.
constexpr int kMaxSymlinks = 40;

// The absolute path with symlinks (also in the folders above), "." and ".."
// resolved; its missing tail, if any, kept as written.
fs::path resolved(const std::string& path) {
    std::error_code error;
    const fs::path absolute = fs::absolute(followSymlinks(path), error);
    if (error) return fs::path(path).lexically_normal();
    const fs::path canonical = fs::weakly_canonical(absolute, error);
    return error ? absolute.lexically_normal() : canonical;
}

}  // namespace

fs::path followSymlinks(const std::string& path) {
    fs::path target = path;
    for (int links = 0;; ++links) {
        std::error_code error;
        if (!fs::is_symlink(fs::symlink_status(target, error))) return target;
        if (links == kMaxSymlinks) throw Error("'" + path + "': too many levels of symbolic links");
        const fs::path next = fs::read_symlink(target, error);
        if (error) throw Error("cannot follow the symbolic link '" + target.string() + "': " + error.message());
        target = next.is_absolute() ? next : target.parent_path() / next;
    }
}

bool isSpecialFile(const std::string& path) {
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    return fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

std::string temporaryPath(const std::string& path) {
    if (isSpecialFile(path)) return "";
    return followSymlinks(path).string() + ".partial";
}

bool hasContent(const std::string& path) {
    std::error_code error;
    return fs::is_regular_file(path, error) && fs::file_size(path, error) > 0 && !error;
}

bool sameFile(const std::string& a, const std::string& b) {
    if (resolved(a) == resolved(b)) return true;
    std::error_code error;  // set (and the result false) unless both exist
    return fs::equivalent(a, b, error);
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
    constexpr std::streamoff kBlockBytes = 1 << 16;
    if (done_) return false;
    for (;;) {
        const std::size_t newline = pending_.rfind('\n');
        if (newline != std::string::npos) {
            line.assign(pending_, newline + 1);
            pending_.resize(newline);
            return true;
        }
        if (unread_ == 0) {
            line = std::move(pending_);
            pending_.clear();
            done_ = true;
            return true;
        }
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

void requireAppendable(const std::string& path, const char* item, std::uint64_t last, std::uint64_t resumedAt) {
    if (last > resumedAt)
        refuseToAppend(path, std::string("its last ") + item + " is at step " + std::to_string(last) +
                                 ", after the checkpoint's step " + std::to_string(resumedAt) +
                                 ", so the resumed run would repeat steps");
}

}  // namespace carom
