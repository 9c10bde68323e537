// carom/files.h: AtomicFile and the paths it writes through.
#include <carom/files.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#if __has_include(<unistd.h>) && !defined(_WIN32)
#include <fcntl.h>
#include <unistd.h>
#endif

#include "engine/scene.h"
#include "io/output_paths.h"

namespace carom::io {
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

// Flushes what the system holds of `path` (a file's data, a folder's
// entries) to the disk, so that a power loss after a rename leaves either
// the old or the new file under the final name, never an empty one. Returns
// false, with errno set, if it could not.
bool syncToDisk(const fs::path& path) {
#if __has_include(<unistd.h>) && !defined(_WIN32)
    const int descriptor = ::open(path.c_str(), O_RDONLY);
    if (descriptor < 0) return false;
    const bool synced = ::fsync(descriptor) == 0;
    const int error = errno;
    ::close(descriptor);
    errno = error;
    return synced;
#else
    // Windows: the std::ofstream is closed and _commit needs a descriptor
    // open for writing; NTFS journals the rename. Nothing more to do here.
    (void)path;
    return true;
#endif
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

AtomicFile::AtomicFile(std::string path, Existing existing) : path_(std::move(path)) {
    if (path_.empty()) throw Error("an output file name is empty");
    std::error_code error;
    if (fs::is_directory(path_, error)) throw Error("cannot write '" + path_ + "': it is a directory");
    temporaryPath_ = temporaryPath(path_);
    if (temporaryPath_.empty()) {  // a FIFO or a device: written in place, never replaced
        stream_.open(path_, std::ios::binary);
        if (!stream_) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
        return;
    }
    target_ = followSymlinks(path_).string();
    continues_ = existing == Existing::Append && hasContent(target_);
    if (continues_ && !fs::copy_file(target_, temporaryPath_, fs::copy_options::overwrite_existing, error))
        throw Error("cannot write '" + path_ + "': copying it to '" + temporaryPath_ + "' failed: " + error.message());
    stream_.open(temporaryPath_, std::ios::binary | (continues_ ? std::ios::app : std::ios::trunc));
    if (!stream_) {
        const int openError = errno;
        if (continues_) std::remove(temporaryPath_.c_str());
        throw Error("cannot write '" + path_ + "': " + std::strerror(openError));
    }
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    stream_.close();
    if (!temporaryPath_.empty()) std::remove(temporaryPath_.c_str());
}

// The reason is errno when the failed write set it (a full disk, a quota, a
// file size limit); the stream does not promise to.
void AtomicFile::failWrite(int error) const {
    const std::string reason = error ? std::strerror(error) : "write error (disk full?)";
    if (temporaryPath_.empty()) throw Error("writing '" + path_ + "' failed: " + reason);
    throw Error("writing '" + path_ + "' failed: " + reason + "; the previous file, if any, is unchanged");
}

void AtomicFile::append(std::string_view text) {
    errno = 0;
    stream_.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!stream_) failWrite(errno);
}

void AtomicFile::commit() {
    if (committed_) return;
    errno = 0;
    stream_.flush();
    const bool written = static_cast<bool>(stream_);
    stream_.close();
    if (!written || stream_.fail()) failWrite(errno);
    if (!temporaryPath_.empty()) {
        if (!syncToDisk(temporaryPath_))
            throw Error("writing '" + path_ + "' failed: syncing it to the disk: " + std::strerror(errno) +
                        "; the previous file, if any, is unchanged");
        // std::filesystem::rename replaces an existing target on Windows too,
        // where std::rename refuses.
        std::error_code error;
        fs::rename(temporaryPath_, target_, error);
        if (error) throw Error("cannot rename '" + temporaryPath_ + "' to '" + target_ + "': " + error.message());
        // The file is in place now; a folder that cannot be synced (some file
        // systems refuse) leaves it as safe as a plain rename would.
        const fs::path folder = fs::path(target_).parent_path();
        syncToDisk(folder.empty() ? fs::path(".") : folder);
    }
    committed_ = true;
}

}  // namespace carom::io
