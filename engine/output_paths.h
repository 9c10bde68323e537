// Where an output file really goes.
//
// An output path may be a symlink (carom writes its target and the link
// stays a link), a special file such as a FIFO or a character device
// (written directly: a device node is never replaced by a regular file), or
// a regular file or a new name (written to PATH.partial beside the target,
// then renamed onto it: see engine/atomic_file.h).
#pragma once

#include <filesystem>
#include <string>

namespace carom {

// `path` with its symlinks followed to the file they name (which may not
// exist yet); `path` itself when it is no symlink. Throws Error on a loop.
std::filesystem::path followSymlinks(const std::string& path);

// Whether `path` (through symlinks) exists and is neither a regular file
// nor a directory: a FIFO, a device or a socket, which carom writes directly.
bool isSpecialFile(const std::string& path);

// The name an output is written to before it is renamed onto `path`: the
// target's name + ".partial"; empty for a special file (no temporary).
std::string temporaryPath(const std::string& path);

// Whether two paths name one file: the same absolute path once symlinks,
// "." and ".." are resolved, or (for existing files) the same file through
// hard links or case-insensitive names.
bool sameFile(const std::string& a, const std::string& b);

}  // namespace carom
