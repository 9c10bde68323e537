#include "engine/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "engine/carom.h"

namespace carom {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temporaryPath_(path_ + ".partial") {
    if (path_.empty()) throw Error("an output file name is empty");
    std::error_code ignored;
    if (std::filesystem::is_directory(path_, ignored))
        throw Error("cannot write '" + path_ + "': it is a directory");
    stream_.open(temporaryPath_, std::ios::binary | std::ios::trunc);
    if (!stream_)
        throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    stream_.close();
    std::remove(temporaryPath_.c_str());
}

void AtomicFile::failWrite() const {
    throw Error("writing '" + path_ + "' failed (disk full?); the previous file, if any, is unchanged");
}

void AtomicFile::append(std::string_view text) {
    stream_.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!stream_) failWrite();
}

void AtomicFile::commit() {
    if (committed_) return;
    stream_.flush();
    const bool written = static_cast<bool>(stream_);
    stream_.close();
    if (!written || stream_.fail()) failWrite();
    // std::filesystem::rename replaces an existing target on Windows too,
    // where std::rename refuses.
    std::error_code error;
    std::filesystem::rename(temporaryPath_, path_, error);
    if (error)
        throw Error("cannot rename '" + temporaryPath_ + "' to '" + path_ + "': " + error.message());
    committed_ = true;
}

}  // namespace carom
