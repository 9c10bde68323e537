#include "engine/output_paths.h"

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

bool sameFile(const std::string& a, const std::string& b) {
    if (resolved(a) == resolved(b)) return true;
    std::error_code error;  // set (and the result false) unless both exist
    return fs::equivalent(a, b, error);
}

}  // namespace carom
