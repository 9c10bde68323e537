#include "engine/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "engine/carom.h"
#include "engine/output_paths.h"

namespace carom {
namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
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
    stream_.open(temporaryPath_, std::ios::binary | std::ios::trunc);
    if (!stream_) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    stream_.close();
    if (!temporaryPath_.empty()) std::remove(temporaryPath_.c_str());
}

void AtomicFile::failWrite(int error) const {
    if (temporaryPath_.empty())
        throw Error("writing '" + path_ + "' failed: " + (error ? std::strerror(error) : "write error"));
    throw Error("writing '" + path_ + "' failed (disk full?); the previous file, if any, is unchanged");
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
        // std::filesystem::rename replaces an existing target on Windows too,
        // where std::rename refuses.
        std::error_code error;
        fs::rename(temporaryPath_, target_, error);
        if (error)
            throw Error("cannot rename '" + temporaryPath_ + "' to '" + target_ + "': " + error.message());
    }
    committed_ = true;
}

}  // namespace carom
