#include <carom/io.h>
#include "io/state_csv.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <carom/files.h>
#include <carom/world.h>
#include "engine/text_format.h"

namespace carom {
namespace {

const char* const kWhat = "state file";
const char* const kHeader = "id,x,y,vx,vy,mass,radius";
const char* const kColumns[] = {"id", "x", "y", "vx", "vy", "mass", "radius"};
constexpr int kColumnCount = 7;

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
        try {
            return io::parseFloat(text);
        } catch (const Error& e) {
            fail(line, std::string("column '") + kColumns[column] + "': " + e.what());
        }
    }

    std::uint64_t id(std::size_t line, const std::string& text) const {
        if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos)
            fail(line, "column 'id': '" + io::printable(text) + "' is not a particle id (an integer >= 0)");
        return std::stoull(text);
    }

private:
    std::string path_;
};

}  // namespace

std::vector<Disk> readStateCsv(const std::string& path, std::uint64_t availableBytes) {
    io::TextFile file(path, kWhat);
    return parseStateCsv(file.stream(), path, availableBytes);
}

std::vector<Disk> parseStateCsv(std::istream& in, const std::string& path, std::uint64_t availableBytes) {
    Reader reader(path);
    io::TextLines lines(in, path, kWhat);
    std::string line;
    if (!lines.next(line)) reader.fail(1, std::string("empty file; expected the header '") + kHeader + "'");
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
    while (lines.next(line)) {
        const std::size_t lineNumber = lines.number();
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
    if (rows.empty()) reader.fail(std::max<std::size_t>(lines.number(), 1), "no particle rows after the header");

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

void writeStateCsv(const std::string& path, const DiskBlocks& disks) {
    // Checked before the file is opened: nothing is written of a state that would not read back.
    if (disks.empty())
        throw Error("state file '" + path + "': 0 disks; allowed: at least 1 (a state file holds a world's disks)");
    disks.forEach([&](std::size_t i, const Disk& d) {
        const float values[] = {d.position.x, d.position.y, d.velocity.x, d.velocity.y, d.mass, d.radius};
        for (int column = 0; column < 6; ++column)
            if (!std::isfinite(values[column])) {
                std::string value;
                appendNumber(value, values[column]);
                throw Error("state file '" + path + "': disk " + std::to_string(i) + "'s " + kColumns[column + 1] +
                            " is " + value + "; allowed: finite numbers");
            }
    });
    io::AtomicFile file(path);
    file.append(std::string(kHeader) + '\n');
    std::string row;
    disks.forEach([&](std::size_t i, const Disk& d) {
        row.clear();
        appendNumber(row, i);
        for (float value : {d.position.x, d.position.y, d.velocity.x, d.velocity.y, d.mass, d.radius}) {
            row += ',';
            appendNumber(row, value);
        }
        row += '\n';
        file.append(row);
    });
    file.commit();
}

}  // namespace carom
