// carom/files.h: files written whole, never over one another (target
// carom::io, which carom's own writers use).
//
// Output files that are either complete or absent: written to a temporary
// name beside the target (TARGET.XXXXXX.partial, unique: two writers of one
// target never share it) and renamed into place by commit(). If the writer
// is destroyed without commit() (an error, an exception), the temporary file
// is removed and the target is untouched. A crash leaves at most the
// temporary file, never a half-written target; commit() syncs the file and
// its folder to the disk, so neither can a power loss.
//
// A symlink is followed: the temporary file goes beside its target, which
// is replaced, and the link stays a link. A FIFO or a device (/dev/null, a
// terminal) is written directly, with no temporary name: it is never
// replaced by a regular file (isSpecialFile). Opening a FIFO waits for its
// reader until interruptWaits() is called.
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
    /// cannot (so a bad output path is refused before any work is done),
    /// removing what it had created.
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
    /// The unique name written before commit(); empty for a special file.
    const std::string& temporaryPath() const { return temporaryPath_; }

    /// Whether the file starts with an existing file's content (Existing::Append
    /// and a non-empty regular file was there).
    bool continues() const { return continues_; }

private:
    [[noreturn]] void failWrite(int error) const;
    void openSpecialFile();
    void copyTarget();
    void removeTemporary() noexcept;

    std::string path_;           ///< as given, for messages
    std::string target_;         ///< path_ with its symlinks followed: what commit() replaces
    std::string temporaryPath_;  ///< empty for a special file, written directly
    std::ofstream stream_;
    bool continues_ = false;
    bool committed_ = false;
    int registered_ = -1;  ///< its slot among the temporaries removeTemporaryFiles() removes, -1 for none
};

/// `path` with its symlinks followed to the file they name (which may not
/// exist yet); `path` itself when it is no symlink. Throws Error on a loop.
std::filesystem::path followSymlinks(const std::string& path);

/// Whether `path` (through symlinks) exists and is neither a regular file
/// nor a directory: a FIFO, a device or a socket, which carom writes directly.
bool isSpecialFile(const std::string& path);

/// Whether `name` has the form of a temporary name of the output `path`:
/// beside its target (symlinks followed), the target's name + ".XXXXXX.partial"
/// (or + ".partial"), so that no output is written where another's temporary
/// file would be taken for it.
bool isTemporaryName(const std::string& name, const std::string& path);

/// Whether two paths name one file: for existing files the same file (device
/// and inode: through hard links, bind mounts or case-insensitive names);
/// otherwise the same name in the same folder (the folder compared by device
/// and inode), or the same absolute path once symlinks, "." and ".." are
/// resolved.
bool sameFile(const std::string& a, const std::string& b);

/// For a program's signal handler (async-signal-safe): from now on, opening
/// a FIFO output that has no reader fails at once with Error instead of
/// waiting for one.
void interruptWaits() noexcept;

/// For a program's signal handler that ends the program at once
/// (async-signal-safe): removes the temporary file of every AtomicFile not yet
/// committed, so that no partial file is left behind.
void removeTemporaryFiles() noexcept;

}  // namespace carom::io
