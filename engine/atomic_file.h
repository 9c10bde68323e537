// Output files that are either complete or absent: written to a temporary
// name beside the target and renamed into place by commit(). If the writer
// is destroyed without commit() (an error, an exception), the temporary file
// is removed and the target is untouched.
#pragma once

#include <fstream>
#include <string>

namespace carom {

class AtomicFile {
public:
    // Opens the temporary file; throws Error if it cannot be created (so a
    // bad output path is refused before any work is done).
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return stream_; }

    // Flushes, checks that every write succeeded, and renames into place.
    void commit();

private:
    std::string path_;
    std::string temporaryPath_;
    std::ofstream stream_;
    bool committed_ = false;
};

}  // namespace carom
