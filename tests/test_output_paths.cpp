// Where outputs go: symlinks, special files, one file under two names
// (engine/output_paths.h, atomic_file.h).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "engine/atomic_file.h"
#include "engine/output_paths.h"
#include "support.h"

using namespace carom;
namespace fs = std::filesystem;

namespace {

std::string contents(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

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

TEST_CASE("output paths: one file under two names") {
    const Folder folder("same-file");
    const std::string a = (folder.path / "a.csv").string();
    CHECK(sameFile(a, (folder.path / "." / "a.csv").string()));
    CHECK(sameFile(a, (folder.path / "sub" / ".." / "a.csv").string()));  // before either exists
    CHECK_FALSE(sameFile(a, (folder.path / "b.csv").string()));
    write(a, "a");
    fs::create_hard_link(a, folder.path / "hard.csv");
    CHECK(sameFile(a, (folder.path / "hard.csv").string()));
    fs::create_symlink("a.csv", folder.path / "link.csv");
    CHECK(sameFile(a, (folder.path / "link.csv").string()));
    fs::create_symlink("new.csv", folder.path / "dangling.csv");  // names a file still to be written
    CHECK(sameFile((folder.path / "new.csv").string(), (folder.path / "dangling.csv").string()));

    // The temporary name is beside the link's target; a device has none.
    CHECK(fs::path(temporaryPath((folder.path / "link.csv").string())) == folder.path / "a.csv.partial");
    CHECK(temporaryPath(a) == a + ".partial");
    if (fs::exists("/dev/null")) {
        CHECK(isSpecialFile("/dev/null"));
        CHECK(temporaryPath("/dev/null").empty());
    }
    CHECK_FALSE(isSpecialFile(a));

    fs::create_symlink("loop2", folder.path / "loop1");
    fs::create_symlink("loop1", folder.path / "loop2");
    CHECK_THROWS_WITH_AS(followSymlinks((folder.path / "loop1").string()),
                         doctest::Contains("too many levels of symbolic links"), Error);
}

TEST_CASE("atomic files: a symlink stays a link to the new file") {
    const Folder folder("symlink-output");
    fs::create_directories(folder.path / "data");
    write(folder.path / "data" / "target.csv", "old");
    fs::create_symlink(fs::path("data") / "target.csv", folder.path / "link.csv");
    {
        AtomicFile file((folder.path / "link.csv").string());
        file.append("new");
        CHECK(fs::exists(folder.path / "data" / "target.csv.partial"));
        file.commit();
    }
    CHECK(fs::is_symlink(folder.path / "link.csv"));
    CHECK(contents(folder.path / "data" / "target.csv") == "new");
    CHECK_FALSE(fs::exists(folder.path / "data" / "target.csv.partial"));
}

TEST_CASE("atomic files: commit syncs and renames, here and in another folder") {
    // That fsync is called cannot be observed from here (it takes a power
    // loss); this checks that the synced commit still puts the file in place.
    const Folder folder("synced");
    for (const fs::path& path : {fs::path("synced-here.txt"), folder.path / "there.txt"}) {
        {
            AtomicFile file(path.string());
            file.append("complete");
            file.commit();
        }
        CHECK(contents(path) == "complete");
        CHECK_FALSE(fs::exists(path.string() + ".partial"));
    }
    fs::remove("synced-here.txt");
}

#ifdef __linux__
TEST_CASE("atomic files: a device is written directly and its write errors reported") {
    if (!fs::exists("/dev/full") || !fs::exists("/dev/null")) {
        MESSAGE("no /dev/full or /dev/null here: nothing to test");
        return;
    }
    {
        AtomicFile file("/dev/null");
        file.append("discarded");
        file.commit();
    }
    AtomicFile file("/dev/full");
    CHECK_THROWS_WITH_AS(
        [&] {
            file.append(std::string(1 << 20, 'x'));
            file.commit();
        }(),
        doctest::Contains("writing '/dev/full' failed: No space left on device"), Error);
    CHECK(fs::is_character_file("/dev/full"));
    CHECK(fs::is_character_file("/dev/null"));
}
#endif
