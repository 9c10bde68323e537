// carom/files.h: files written whole, never over one another (target
// carom::io, which carom's own writers use).
//
// Output files that are either complete or absent: written to a temporary
// name beside the target and renamed into place by commit(). If the writer
// is destroyed without commit() (an error, an exception), the temporary file
// is removed and the target is untouched. A crash leaves at most the
// temporary file, never a half-written target; commit() syncs the file and
// its folder to the disk, so neither can a power loss.
//
// A symlink is followed: the temporary file goes beside its target, which
// is replaced, and the link stays a link. A FIFO or a device (/dev/null, a
// terminal) is written directly, with no temporary name: it is never
// replaced by a regular file (isSpecialFile).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace carom::io {

/// What an AtomicFile does with a regular file already at its path.
enum class Existing {
    Replace,  ///< start empty; commit() replaces it
    Append,   ///< start from a copy of it; commit() replaces it with the copy and what was appended
};

class AtomicFile {
public:
    /// Opens the temporary file (with Existing::Append, a copy of an existing
    /// regular file at `path`), or a special file directly; throws Error if it
    /// cannot (so a bad output path is refused before any work is done).
    explicit AtomicFile(std::string path, Existing existing = Existing::Replace);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return stream_; }

    /// Writes `text`; throws Error at once if the write fails (a full disk
    /// stops a long run then, not at its end).
    void append(std::string_view text);

    /// Flushes, checks that every write succeeded, syncs the file to the
    /// disk and renames it into place (replacing the target, on every
    /// platform), then syncs the folder. A special file is flushed only.
    void commit();

    const std::string& path() const { return path_; }

    /// Whether the file starts with an existing file's content (Existing::Append
    /// and a non-empty regular file was there).
    bool continues() const { return continues_; }

private:
    [[noreturn]] void failWrite(int error) const;

    std::string path_;           ///< as given, for messages
    std::string target_;         ///< path_ with its symlinks followed: what commit() replaces
    std::string temporaryPath_;  ///< empty for a special file, written directly
    std::ofstream stream_;
    bool continues_ = false;
    bool committed_ = false;
};

/// `path` with its symlinks followed to the file they name (which may not
/// exist yet); `path` itself when it is no symlink. Throws Error on a loop.
std::filesystem::path followSymlinks(const std::string& path);

/// Whether `path` (through symlinks) exists and is neither a regular file
/// nor a directory: a FIFO, a device or a socket, which carom writes directly.
bool isSpecialFile(const std::string& path);

/// The name an output is written to before it is renamed onto `path`: the
/// target's name + ".partial"; empty for a special file (no temporary).
std::string temporaryPath(const std::string& path);

/// Whether two paths name one file: the same absolute path once symlinks,
/// "." and ".." are resolved, or (for existing files) the same file through
/// hard links or case-insensitive names.
bool sameFile(const std::string& a, const std::string& b);

}  // namespace carom::io
