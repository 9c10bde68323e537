#include <carom/io.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#if __has_include(<unistd.h>) && !defined(_WIN32)
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#define CAROM_POSIX_FILES 1
#endif

#include <carom/types.h>

namespace carom::io {
namespace {

#ifdef CAROM_POSIX_FILES
// Reads a file descriptor, which it closes. A read error throws, which the
// istream turns into badbit: the readers then report it, never a short file.
class DescriptorBuffer : public std::streambuf {
public:
    explicit DescriptorBuffer(int fd) : fd_(fd) {}
    ~DescriptorBuffer() override { ::close(fd_); }
    DescriptorBuffer(const DescriptorBuffer&) = delete;
    DescriptorBuffer& operator=(const DescriptorBuffer&) = delete;

protected:
    int_type underflow() override {
        ssize_t got;
        do got = ::read(fd_, buffer_, sizeof buffer_);
        while (got < 0 && errno == EINTR);
        if (got < 0) throw Error(std::strerror(errno));
        if (got == 0) return traits_type::eof();
        setg(buffer_, buffer_, buffer_ + got);
        return traits_type::to_int_type(buffer_[0]);
    }

private:
    int fd_;
    char buffer_[1 << 16];
};

// Opened without blocking, so that a FIFO nobody writes to cannot block
// open() for ever: it is read once data arrives (or its writer closes it)
// within kFifoWaitSeconds. A pipe from process substitution, <(...), has
// its writer running already.
std::unique_ptr<std::streambuf> openText(const std::string& path, const std::string& what) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw Error("cannot read " + what + " '" + path + "': " + std::strerror(errno));
    auto buffer = std::make_unique<DescriptorBuffer>(fd);
    struct stat info {};
    if (::fstat(fd, &info) != 0) throw Error("cannot read " + what + " '" + path + "': " + std::strerror(errno));
    if (S_ISDIR(info.st_mode)) throw Error("cannot read " + what + " '" + path + "': it is a directory");
    if (S_ISFIFO(info.st_mode)) {
        pollfd waiting{fd, POLLIN, 0};
        int ready;
        do ready = ::poll(&waiting, 1, kFifoWaitSeconds * 1000);
        while (ready < 0 && errno == EINTR);
        if (ready == 0)
            throw Error(what + " '" + path + "' is a FIFO (named pipe) that no program wrote to within " +
                        std::to_string(kFifoWaitSeconds) +
                        " s; start the program that writes it, or give a regular file");
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return buffer;
}
#else
std::unique_ptr<std::streambuf> openText(const std::string& path, const std::string& what) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error))
        throw Error("cannot read " + what + " '" + path + "': it is a directory");
    auto buffer = std::make_unique<std::filebuf>();
    if (!buffer->open(path, std::ios::in | std::ios::binary))
        throw Error("cannot read " + what + " '" + path + "': " + std::strerror(errno));
    return buffer;
}
#endif

[[noreturn]] void refuseNul(const std::string& where, const std::string& what) {
    throw Error(where + ": a NUL byte, which no text file has (is it a " + what + "?)");
}

}  // namespace

TextFile::TextFile(const std::string& path, const std::string& what)
    : path_(path), what_(what), buffer_(openText(path, what)), in_(buffer_.get()) {}

TextFile::~TextFile() = default;

std::string TextFile::readAll(std::size_t maxBytes) {
    std::string text;
    char block[1 << 16];
    while (in_.read(block, sizeof block) || in_.gcount() > 0) {
        const auto got = static_cast<std::size_t>(in_.gcount());
        if (text.size() + got > maxBytes)
            throw Error(what_ + " '" + path_ + "' has more than " + std::to_string(maxBytes) + " bytes; a " + what_ +
                        " is at most " + std::to_string(maxBytes) + " bytes");
        if (std::memchr(block, '\0', got)) refuseNul(what_ + " '" + path_ + "'", what_);
        text.append(block, got);
    }
    if (in_.bad()) throw Error("reading " + what_ + " '" + path_ + "' failed");
    return text;
}

TextLines::TextLines(std::istream& in, std::string path, std::string what)
    : in_(in), path_(std::move(path)), what_(std::move(what)) {}

bool TextLines::next(std::string& line) {
    in_.getline(buffer_, sizeof buffer_);
    const auto got = static_cast<std::size_t>(in_.gcount());
    if (in_.bad()) throw Error("reading '" + path_ + "' failed");
    const std::string where = path_ + ":" + std::to_string(number_ + 1);
    if (in_.fail() && !in_.eof() && got > 0)
        throw Error(where + ": line longer than " + std::to_string(kMaxTextLineBytes) + " bytes; in a " + what_ +
                    " lines are at most " + std::to_string(kMaxTextLineBytes) + " bytes (is it a " + what_ + "?)");
    if (got == 0 && in_.fail()) return false;
    ++number_;
    line.assign(buffer_, in_.eof() ? got : got - 1);  // getline counted the newline it took
    if (line.find('\0') != std::string::npos) refuseNul(where, what_);
    return true;
}

}  // namespace carom::io
