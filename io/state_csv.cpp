#include <carom/io.h>
#include "io/state_csv.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#if __has_include(<unistd.h>)
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

#include <carom/files.h>
#include <carom/world.h>
#include "engine/text_format.h"

namespace carom {
namespace {

const char* const kHeader = "id,x,y,vx,vy,mass,radius";
const char* const kColumns[] = {"id", "x", "y", "vx", "vy", "mass", "radius"};
constexpr int kColumnCount = 7;
// A row of seven floats in their longest spelling is under 200 bytes; the
// cap stops a file without newlines (/dev/zero, a binary) from filling memory.
constexpr std::size_t kMaxLineBytes = 4096;

std::string trim(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return "";
    return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// Spreadsheet programs often start a CSV with a UTF-8 byte order mark.
void skipByteOrderMark(std::string& line) {
    if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
}

class Reader {
public:
    explicit Reader(const std::string& path) : path_(path) {}

    [[noreturn]] void fail(std::size_t line, const std::string& what) const {
        throw Error(path_ + ":" + std::to_string(line) + ": " + what);
    }

    float number(std::size_t line, int column, const std::string& text) const {
        // strtof reads the C locale's decimal point: carom never changes the locale.
        char* end = nullptr;
        errno = 0;
        const float value = std::strtof(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size())
            fail(line, std::string("column '") + kColumns[column] + "': '" + io::printable(text) + "' is not a number");
        if (errno == ERANGE && std::isinf(value))
            fail(line,
                 std::string("column '") + kColumns[column] + "': " + io::printable(text) + " is out of float range");
        if (errno == ERANGE && value == 0.0f)  // it would read as 0 without a word
            fail(line, std::string("column '") + kColumns[column] + "': " + io::printable(text) +
                           " is too small for a float (the smallest above 0 is 1.4e-45); write 0 for zero");
        return value;
    }

    // Reads the next line into `line`, without its newline; false at the end
    // of the input. Refuses a line longer than kMaxLineBytes before storing more.
    bool nextLine(std::istream& in, std::string& line, std::size_t lineNumber) {
        in.getline(buffer_, sizeof buffer_);
        const auto got = static_cast<std::size_t>(in.gcount());
        if (in.bad()) throw Error("reading state file '" + path_ + "' failed");
        if (in.fail() && !in.eof() && got > 0)
            fail(lineNumber, "line longer than " + std::to_string(kMaxLineBytes) +
                                 " bytes; a state file's lines are at most " + std::to_string(kMaxLineBytes) +
                                 " bytes (is it a state CSV?)");
        if (got == 0 && in.fail()) return false;
        line.assign(buffer_, in.eof() ? got : got - 1);  // getline counted the newline it took
        return true;
    }

    std::uint64_t id(std::size_t line, const std::string& text) const {
        if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos)
            fail(line, "column 'id': '" + io::printable(text) + "' is not a particle id (an integer >= 0)");
        return std::stoull(text);
    }

private:
    std::string path_;
    char buffer_[kMaxLineBytes + 1];  // a line and the terminating zero getline writes
};

}  // namespace

#if __has_include(<unistd.h>)
namespace {

// Reads a file descriptor, which it closes. A read error throws, which the
// istream turns into badbit: the reader then reports it, never a short file.
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

// A FIFO nobody writes to would block open() for ever: it is opened
// without blocking, and read once data arrives (or its writer closes it)
// within kFifoWaitSeconds. A pipe from process substitution, <(...), has
// its writer running already.
constexpr int kFifoWaitSeconds = 10;

std::vector<Disk> readFifo(const std::string& path, std::uint64_t availableBytes) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK);
    if (fd < 0) throw Error("cannot read state file '" + path + "': " + std::strerror(errno));
    DescriptorBuffer buffer(fd);
    pollfd waiting{fd, POLLIN, 0};
    int ready;
    do ready = ::poll(&waiting, 1, kFifoWaitSeconds * 1000);
    while (ready < 0 && errno == EINTR);
    if (ready == 0)
        throw Error("state file '" + path + "' is a FIFO (named pipe) that no program wrote to within " +
                    std::to_string(kFifoWaitSeconds) + " s; start the program that writes it, or give a regular file");
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::istream in(&buffer);
    return parseStateCsv(in, path, availableBytes);
}

}  // namespace
#endif

std::vector<Disk> readStateCsv(const std::string& path, std::uint64_t availableBytes) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error))
        throw Error("cannot read state file '" + path + "': it is a directory");
#if __has_include(<unistd.h>)
    struct stat info {};
    if (stat(path.c_str(), &info) == 0 && S_ISFIFO(info.st_mode)) return readFifo(path, availableBytes);
#endif
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read state file '" + path + "': " + std::strerror(errno));
    return parseStateCsv(in, path, availableBytes);
}

std::vector<Disk> parseStateCsv(std::istream& in, const std::string& path, std::uint64_t availableBytes) {
    Reader reader(path);
    std::string line;
    std::size_t lineNumber = 1;
    if (!reader.nextLine(in, line, lineNumber))
        reader.fail(1, std::string("empty file; expected the header '") + kHeader + "'");
    skipByteOrderMark(line);
    if (trim(line) != kHeader)
        reader.fail(1, "header is '" + io::printable(trim(line)) + "'; expected '" + kHeader + "'");

    struct Row {
        std::uint64_t id;
        std::size_t line;
        Disk disk;
    };
    std::vector<Row> rows;
    const std::string where = path + ": particle rows";
    while (reader.nextLine(in, line, lineNumber + 1)) {
        ++lineNumber;
        if (trim(line).empty()) continue;
        std::vector<std::string> fields;
        std::stringstream split(line);
        for (std::string field; std::getline(split, field, ',');) fields.push_back(trim(field));
        if (!line.empty() && line.back() == ',') fields.emplace_back();
        if (fields.size() != kColumnCount)
            reader.fail(lineNumber, "expected " + std::to_string(kColumnCount) + " columns (" + kHeader + "), found " +
                                        std::to_string(fields.size()));
        requireRoomFor(rows.size() + 1, where, availableBytes);  // before the row is stored
        Row row{reader.id(lineNumber, fields[0]), lineNumber, Disk{}};
        Disk& d = row.disk;
        d.position.x = reader.number(lineNumber, 1, fields[1]);
        d.position.y = reader.number(lineNumber, 2, fields[2]);
        d.velocity.x = reader.number(lineNumber, 3, fields[3]);
        d.velocity.y = reader.number(lineNumber, 4, fields[4]);
        d.mass = reader.number(lineNumber, 5, fields[5]);
        d.radius = reader.number(lineNumber, 6, fields[6]);
        rows.push_back(row);
    }
    if (in.bad()) throw Error("reading state file '" + path + "' failed");
    if (rows.empty()) reader.fail(lineNumber, "no particle rows after the header");

    std::vector<Disk> disks(rows.size());
    std::vector<std::size_t> seenOnLine(rows.size(), 0);
    for (const Row& row : rows) {
        if (row.id >= rows.size())
            reader.fail(row.line, "id " + std::to_string(row.id) + " is out of range: with " +
                                      std::to_string(rows.size()) + " rows the ids must be 0.." +
                                      std::to_string(rows.size() - 1));
        if (seenOnLine[row.id] != 0)
            reader.fail(row.line, "duplicate id " + std::to_string(row.id) + " (first on line " +
                                      std::to_string(seenOnLine[row.id]) + ")");
        seenOnLine[row.id] = row.line;
        disks[row.id] = row.disk;
    }
    return disks;
}

void writeStateCsv(const std::string& path, const std::vector<Disk>& disks) {
    // Checked before the file is opened: nothing is written of a state that would not read back.
    if (disks.empty())
        throw Error("state file '" + path + "': 0 disks; allowed: at least 1 (a state file holds a world's disks)");
    for (std::size_t i = 0; i < disks.size(); ++i) {
        const Disk& d = disks[i];
        const float values[] = {d.position.x, d.position.y, d.velocity.x, d.velocity.y, d.mass, d.radius};
        for (int column = 0; column < 6; ++column)
            if (!std::isfinite(values[column])) {
                std::string value;
                appendNumber(value, values[column]);
                throw Error("state file '" + path + "': disk " + std::to_string(i) + "'s " + kColumns[column + 1] +
                            " is " + value + "; allowed: finite numbers");
            }
    }
    io::AtomicFile file(path);
    file.append(std::string(kHeader) + '\n');
    std::string row;
    for (std::size_t i = 0; i < disks.size(); ++i) {
        const Disk& d = disks[i];
        row.clear();
        appendNumber(row, i);
        for (float value : {d.position.x, d.position.y, d.velocity.x, d.velocity.y, d.mass, d.radius}) {
            row += ',';
            appendNumber(row, value);
        }
        row += '\n';
        file.append(row);
    }
    file.commit();
}

}  // namespace carom
