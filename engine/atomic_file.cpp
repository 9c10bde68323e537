#include "engine/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "engine/carom.h"

namespace carom {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temporaryPath_(path_ + ".partial") {
    stream_.open(temporaryPath_, std::ios::binary | std::ios::trunc);
    if (!stream_)
        throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    stream_.close();
    std::remove(temporaryPath_.c_str());
}

void AtomicFile::commit() {
    stream_.flush();
    const bool written = static_cast<bool>(stream_);
    stream_.close();
    if (!written || stream_.fail())
        throw Error("writing '" + path_ + "' failed (disk full?); the previous file, if any, is unchanged");
    if (std::rename(temporaryPath_.c_str(), path_.c_str()) != 0)
        throw Error("cannot rename '" + temporaryPath_ + "' to '" + path_ + "': " + std::strerror(errno));
    committed_ = true;
}

}  // namespace carom
