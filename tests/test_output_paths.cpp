// Where outputs go (symlinks, special files, one file under two names) and
// how a resumed run continues them (carom/files.h, io/output_paths.h).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#ifdef __linux__
#include <sys/stat.h>
#include <unistd.h>
#endif

#include <carom/files.h>
#include "io/output_paths.h"
#include "io/stats.h"
#include "support.h"

using namespace carom;
namespace fs = std::filesystem;

namespace {

std::string contents(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::vector<std::string> linesFromEnd(const std::string& text) {
    write("lines.txt", text);
    LinesFromEnd lines("lines.txt");
    std::vector<std::string> result;
    for (std::string line; lines.previous(line);) result.push_back(line);
    fs::remove("lines.txt");
    return result;
}

// The temporary files (NAME.XXXXXX.partial) left in `folder`.
std::vector<std::string> partialFiles(const fs::path& folder) {
    std::vector<std::string> found;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder.empty() ? fs::path(".") : folder))
        if (entry.path().extension() == ".partial") found.push_back(entry.path().string());
    return found;
}

// A fresh folder for one test case, removed at its end.
struct Folder {
    explicit Folder(const std::string& name) : path(name) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~Folder() { fs::remove_all(path); }
    fs::path path;
};

}  // namespace

TEST_CASE("output paths: lines read from the end") {
    CHECK(linesFromEnd("") == std::vector<std::string>{});
    CHECK(linesFromEnd("\n") == std::vector<std::string>{""});
    CHECK(linesFromEnd("a\nb\n") == std::vector<std::string>{"b", "a"});
    CHECK(linesFromEnd("a\nb") == std::vector<std::string>{"b", "a"});
    CHECK(linesFromEnd("a\n\nb\n") == std::vector<std::string>{"b", "", "a"});
    const std::string longLine(60000, 'x');  // over several blocks
    CHECK(linesFromEnd("first\n" + longLine + "\nlast\n") == std::vector<std::string>{"last", longLine, "first"});

    // A line longer than any carom writes is refused after a block or two,
    // not read whole (a file of one huge line took minutes).
    const std::string huge(std::size_t(kMaxLineBytes) * 4, 'x');
    CHECK_THROWS_WITH_AS(linesFromEnd("first\n" + huge), doctest::Contains("has a line longer than 65536 bytes"),
                         Error);

    std::uint64_t step = 0;
    CHECK((parseStep("18446744073709551615", step) && step == 18446744073709551615u));
    for (const char* bad : {"", "-1", "+1", "1.5", "18446744073709551616", "1 ", "x"})
        CHECK_MESSAGE(!parseStep(bad, step), bad);
}

TEST_CASE("output paths: one file under two names") {
    const Folder folder("same-file");
    const std::string a = (folder.path / "a.csv").string();
    CHECK(io::sameFile(a, (folder.path / "." / "a.csv").string()));
    CHECK(io::sameFile(a, (folder.path / "sub" / ".." / "a.csv").string()));  // before either exists
    CHECK_FALSE(io::sameFile(a, (folder.path / "b.csv").string()));
    write(a, "a");
    fs::create_hard_link(a, folder.path / "hard.csv");
    CHECK(io::sameFile(a, (folder.path / "hard.csv").string()));
    fs::create_symlink("a.csv", folder.path / "link.csv");
    CHECK(io::sameFile(a, (folder.path / "link.csv").string()));
    fs::create_symlink("new.csv", folder.path / "dangling.csv");  // names a file still to be written
    CHECK(io::sameFile((folder.path / "new.csv").string(), (folder.path / "dangling.csv").string()));

    // A temporary name is beside the link's target; a device has none.
    for (const std::string& output : {(folder.path / "link.csv").string(), a}) {
        CHECK(io::isTemporaryName((folder.path / "a.csv.x1y2z3.partial").string(), output));
        CHECK(io::isTemporaryName((folder.path / "a.csv.partial").string(), output));
        CHECK_FALSE(io::isTemporaryName((folder.path / "a.csv.partial.txt").string(), output));
        CHECK_FALSE(io::isTemporaryName((folder.path / "b.csv.x1y2z3.partial").string(), output));
    }
    CHECK_FALSE(
        io::isTemporaryName((folder.path / "link.csv.x1y2z3.partial").string(), (folder.path / "link.csv").string()));
    if (fs::exists("/dev/null")) {
        CHECK(io::isSpecialFile("/dev/null"));
        io::AtomicFile null("/dev/null");
        CHECK(null.temporaryPath().empty());
    }
    CHECK_FALSE(io::isSpecialFile(a));

    fs::create_symlink("loop2", folder.path / "loop1");
    fs::create_symlink("loop1", folder.path / "loop2");
    CHECK_THROWS_WITH_AS(io::followSymlinks((folder.path / "loop1").string()),
                         doctest::Contains("too many levels of symbolic links"), Error);
}

TEST_CASE("output paths: one file through a symlinked folder, before it exists") {
    // `alias` is another name of the folder `real`: outputs there are one
    // file although neither exists yet (a bind mount of `real` is the same
    // case, tested by outputs.same_file_through_a_bind_mount where it may be made).
    const Folder folder("same-folder");
    fs::create_directories(folder.path / "real");
    fs::create_directory_symlink("real", folder.path / "alias");
    const std::string real = (folder.path / "real" / "c.ckpt").string();
    CHECK(io::sameFile(real, (folder.path / "alias" / "c.ckpt").string()));
    CHECK_FALSE(io::sameFile(real, (folder.path / "alias" / "d.ckpt").string()));
    CHECK(io::isTemporaryName((folder.path / "alias" / "c.ckpt.abc123.partial").string(), real));
}

TEST_CASE("atomic files: two writers of one file never share a temporary file") {
    // Two runs with one --checkpoint: each commit puts its own writer's
    // content in place (a shared temporary name mixed them up).
    const Folder folder("two-writers");
    const std::string path = (folder.path / "c.ckpt").string();
    io::AtomicFile first(path), second(path);
    CHECK(first.temporaryPath() != second.temporaryPath());
    first.append("first");
    second.append("second");
    first.commit();
    CHECK(contents(path) == "first");
    second.commit();
    CHECK(contents(path) == "second");
    CHECK(partialFiles(folder.path).empty());
}

TEST_CASE("atomic files: a symlink stays a link to the new file") {
    const Folder folder("symlink-output");
    fs::create_directories(folder.path / "data");
    write(folder.path / "data" / "target.csv", "old");
    fs::create_symlink(fs::path("data") / "target.csv", folder.path / "link.csv");
    {
        io::AtomicFile file((folder.path / "link.csv").string());
        file.append("new");
        CHECK(partialFiles(folder.path / "data") == std::vector<std::string>{file.temporaryPath()});
        CHECK(fs::path(file.temporaryPath()).filename().string().rfind("target.csv.", 0) == 0);
        file.commit();
    }
    CHECK(fs::is_symlink(folder.path / "link.csv"));
    CHECK(contents(folder.path / "data" / "target.csv") == "new");
    CHECK(partialFiles(folder.path / "data").empty());
}

TEST_CASE("atomic files: appending is atomic too") {
    const Folder folder("append");
    const std::string path = (folder.path / "s.txt").string();
    write(path, "old\n");
    {
        io::AtomicFile file(path, io::Existing::Append);
        CHECK(file.continues());
        file.append("new\n");
    }  // destroyed without commit: the original is untouched
    CHECK(contents(path) == "old\n");
    CHECK(partialFiles(folder.path).empty());
    {
        io::AtomicFile file(path, io::Existing::Append);
        file.append("new\n");
        file.commit();
    }
    CHECK(contents(path) == "old\nnew\n");
    CHECK(partialFiles(folder.path).empty());
    {
        io::AtomicFile file((folder.path / "absent.txt").string(), io::Existing::Append);
        CHECK_FALSE(file.continues());
    }
}

TEST_CASE("atomic files: commit syncs and renames, here and in another folder") {
    // That fsync comes before the rename is checked by outputs.synced_before_rename
    // (a preloaded spy); this checks that the synced commit puts the file in place.
    const Folder folder("synced");
    for (const fs::path& path : {fs::path("synced-here.txt"), folder.path / "there.txt"}) {
        {
            io::AtomicFile file(path.string());
            file.append("complete");
            file.commit();
        }
        CHECK(contents(path) == "complete");
        CHECK(partialFiles(path.parent_path()).empty());
    }
    fs::remove("synced-here.txt");
}

#ifdef __linux__
namespace {

// A character device to write to: the system's `device` when this process
// cannot replace it, else (as root) a private node of the same device, so a
// regression cannot replace the system's; empty when neither is possible.
std::string deviceNode(const std::string& device, const fs::path& folder) {
    struct stat status {};
    if (::stat(device.c_str(), &status) != 0) return "";
    if (::geteuid() != 0) return device;
    const fs::path node = folder / fs::path(device).filename();
    return ::mknod(node.c_str(), S_IFCHR | 0666, status.st_rdev) == 0 ? node.string() : "";
}

}  // namespace

TEST_CASE("atomic files: a device is written directly and its write errors reported") {
    const Folder folder("devices");
    const std::string null = deviceNode("/dev/null", folder.path), full = deviceNode("/dev/full", folder.path);
    if (null.empty() || full.empty()) {
        MESSAGE("no /dev/full or /dev/null to write here: nothing to test");
        return;
    }
    {
        io::AtomicFile file(null);
        file.append("discarded");
        file.commit();
    }
    io::AtomicFile file(full);
    const std::string message = "writing '" + full + "' failed: No space left on device";
    CHECK_THROWS_WITH_AS(
        [&] {
            file.append(std::string(1 << 20, 'x'));
            file.commit();
        }(),
        doctest::Contains(message.c_str()), Error);
    CHECK(fs::is_character_file(full));
    CHECK(fs::is_character_file(null));
}
#endif

namespace {

// A checkpoint at `step`, at time step / 100, before any collision.
Resumed resumedAt(std::uint64_t step) {
    Resumed resumed;
    resumed.step = step;
    resumed.time = double(step) / 100;
    return resumed;
}

}  // namespace

TEST_CASE("statistics: a resumed run appends after the rows already there") {
    const Folder folder("stats-append");
    const std::string path = (folder.path / "s.csv").string();
    const std::string header = "step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped\n";
    const Diagnostics d{};
    {
        const Resumed resumed = resumedAt(100);
        StatsWriter stats(path, &resumed);  // no file yet: created with its header
        stats.write(200, 2.0, d, 0);
        stats.commit();
    }
    CHECK(contents(path).rfind(header + "200,", 0) == 0);
    {
        const Resumed resumed = resumedAt(200);
        StatsWriter stats(path, &resumed);
        stats.write(300, 3.0, d, 0);
        stats.commit();
    }
    CHECK(contents(path).find("\n200,") < contents(path).find("\n300,"));
    const Resumed at250 = resumedAt(250), at0 = resumedAt(0);
    CHECK_THROWS_WITH_AS(StatsWriter(path, &at250),
                         doctest::Contains("its last row is at step 300, after the checkpoint's step 250"), Error);
    write(path, header);  // no rows yet
    CHECK_NOTHROW(StatsWriter(path, &at0));
    write(path, "id,x,y\n0,1,2\n");
    CHECK_THROWS_WITH_AS(StatsWriter(path, &at0), doctest::Contains("its header is 'id,x,y'"), Error);
}
