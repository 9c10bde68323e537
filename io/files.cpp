// carom/files.h: AtomicFile and the paths it writes through.
#include <carom/files.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <system_error>
#include <thread>
#include <vector>

#if __has_include(<unistd.h>) && !defined(_WIN32)
#include <fcntl.h>
#include <unistd.h>
#define CAROM_POSIX_FILES 1
#endif

#include "engine/scene.h"
#include "io/output_paths.h"

namespace carom::io {
namespace fs = std::filesystem;

namespace {

// As POSIX's SYMLOOP_MAX on Linux: a longer chain is a loop.
constexpr int kMaxSymlinks = 40;

// The absolute path with symlinks (also in the folders above), "." and ".."
// resolved; its missing tail, if any, kept as written.
fs::path resolved(const std::string& path) {
    std::error_code error;
    const fs::path absolute = fs::absolute(followSymlinks(path), error);
    if (error) return fs::path(path).lexically_normal();
    const fs::path canonical = fs::weakly_canonical(absolute, error);
    return error ? absolute.lexically_normal() : canonical;
}

// Flushes what the system holds of `path` (a file's data, a folder's
// entries) to the disk, so that a power loss after a rename leaves either
// the old or the new file under the final name, never an empty one. Returns
// false, with errno set, if it could not.
bool syncToDisk(const fs::path& path) {
#if __has_include(<unistd.h>) && !defined(_WIN32)
    const int descriptor = ::open(path.c_str(), O_RDONLY);
    if (descriptor < 0) return false;
    const bool synced = ::fsync(descriptor) == 0;
    const int error = errno;
    ::close(descriptor);
    errno = error;
    return synced;
#else
    // Windows: the std::ofstream is closed and _commit needs a descriptor
    // open for writing; NTFS journals the rename. Nothing more to do here.
    (void)path;
    return true;
#endif
}

// The temporary files not yet committed or removed, for removeTemporaryFiles()
// in a signal handler: fixed slots, each claimed with an atomic state, so
// the handler neither allocates nor waits.
struct TemporarySlot {
    std::atomic<int> state{0};  // kFree, kClaimed (being filled) or kHeld
    char path[4096];
};
constexpr int kFree = 0, kClaimed = 1, kHeld = 2;
static_assert(std::atomic<int>::is_always_lock_free);
TemporarySlot temporarySlots[64];

// The slot now holding `path`, -1 when none is free or the path too long
// (its file is then removed by the AtomicFile alone, not by a handler).
int registerTemporary(const std::string& path) {
    if (path.size() >= sizeof TemporarySlot::path) return -1;
    for (int i = 0; i < int(std::size(temporarySlots)); ++i) {
        int free = kFree;
        if (!temporarySlots[i].state.compare_exchange_strong(free, kClaimed)) continue;
        std::memcpy(temporarySlots[i].path, path.c_str(), path.size() + 1);
        temporarySlots[i].state.store(kHeld);
        return i;
    }
    return -1;
}

std::atomic<bool> waitsInterrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

// Six letters or digits, different for each call in a process and unlikely
// to repeat across processes (its time and address differ).
std::string uniqueTag() {
    static std::atomic<std::uint64_t> counter{0};
    std::uint64_t x = std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count()) ^
                      (reinterpret_cast<std::uintptr_t>(&counter) << 16) ^
                      (counter.fetch_add(1) * 0x9E3779B97F4A7C15ull);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;  // splitmix64's mixing
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    std::string tag;
    for (int i = 0; i < 6; ++i, x /= 36) tag += "0123456789abcdefghijklmnopqrstuvwxyz"[x % 36];
    return tag;
}

// Creates `path`, empty, if no file has that name; false (errno set) if one has.
bool createExclusively(const std::string& path) {
#ifdef CAROM_POSIX_FILES
    const int descriptor = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (descriptor < 0) return false;
    ::close(descriptor);
    return true;
#else
    std::FILE* file = std::fopen(path.c_str(), "wbx");
    if (!file) return false;
    std::fclose(file);
    return true;
#endif
}

// The folder a path's file is in and its name, symlinks followed.
struct Place {
    fs::path folder, name;
};

Place placeOf(const std::string& path) {
    const fs::path where = resolved(path);
    return {where.parent_path(), where.filename()};
}

// The same folder: the same path, or the same device and inode (a bind
// mount, a symlinked folder).
bool sameFolder(const fs::path& a, const fs::path& b) {
    std::error_code error;
    return a == b || fs::equivalent(a, b, error);
}

}  // namespace

fs::path followSymlinks(const std::string& path) {
    fs::path target = path;
    for (int links = 0;; ++links) {
        std::error_code error;
        if (!fs::is_symlink(fs::symlink_status(target, error))) return target;
        if (links == kMaxSymlinks) throw Error("'" + path + "': too many levels of symbolic links");
        const fs::path next = fs::read_symlink(target, error);
        if (error) throw Error("cannot follow the symbolic link '" + target.string() + "': " + error.message());
        target = next.is_absolute() ? next : target.parent_path() / next;
    }
}

bool isSpecialFile(const std::string& path) {
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    return fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

bool isTemporaryName(const std::string& name, const std::string& path) {
    const Place candidate = placeOf(name), output = placeOf(path);
    const std::string n = candidate.name.string(), target = output.name.string(), suffix = ".partial";
    const bool shaped = n.size() > target.size() + suffix.size() &&
                        n.compare(0, target.size() + 1, target + ".") == 0 &&
                        n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0;
    return (shaped || n == target + suffix) && sameFolder(candidate.folder, output.folder);
}

bool sameFile(const std::string& a, const std::string& b) {
    std::error_code error;
    if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
    const Place pa = placeOf(a), pb = placeOf(b);
    return pa.name == pb.name && sameFolder(pa.folder, pb.folder);
}

void interruptWaits() noexcept { waitsInterrupted.store(true); }

void removeTemporaryFiles() noexcept {
    for (TemporarySlot& slot : temporarySlots) {
        if (slot.state.load() != kHeld) continue;
#ifdef CAROM_POSIX_FILES
        ::unlink(slot.path);
#else
        std::remove(slot.path);
#endif
    }
}

AtomicFile::AtomicFile(std::string path, Existing existing) : path_(std::move(path)) {
    if (path_.empty()) throw Error("an output file name is empty");
    std::error_code error;
    if (fs::is_directory(path_, error)) throw Error("cannot write '" + path_ + "': it is a directory");
    if (isSpecialFile(path_)) {  // a FIFO or a device: written in place, never replaced
        openSpecialFile();
        return;
    }
    target_ = followSymlinks(path_).string();
    for (int attempt = 0; temporaryPath_.empty(); ++attempt) {
        const std::string name = target_ + "." + uniqueTag() + ".partial";
        if (createExclusively(name)) {
            temporaryPath_ = name;
        } else if (errno != EEXIST || attempt == 100) {
            throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
        }
    }
    registered_ = registerTemporary(temporaryPath_);
    try {
        stream_.open(temporaryPath_, std::ios::binary | std::ios::trunc);
        if (!stream_) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
        continues_ = existing == Existing::Append && hasContent(target_);
        if (continues_) copyTarget();
    } catch (...) {
        removeTemporary();
        throw;
    }
}

AtomicFile::~AtomicFile() {
    if (!committed_) removeTemporary();
}

void AtomicFile::removeTemporary() noexcept {
    stream_.close();
    if (temporaryPath_.empty()) return;
    std::remove(temporaryPath_.c_str());
    if (registered_ >= 0) temporarySlots[registered_].state.store(kFree);
    registered_ = -1;
}

// A FIFO with no reader yet is waited for in short sleeps, so that a stop
// signal (interruptWaits) ends the wait; once a reader is there the FIFO is
// opened again, blocking, through the descriptor that holds it open (a
// reader never sees the end of its input in between).
void AtomicFile::openSpecialFile() {
#ifdef __linux__
    std::error_code error;
    if (fs::is_fifo(path_, error)) {
        for (;;) {
            const int descriptor = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
            if (descriptor >= 0) {
                stream_.open("/proc/self/fd/" + std::to_string(descriptor), std::ios::binary);
                ::close(descriptor);
                break;  // without /proc, opened below
            }
            if (errno != ENXIO) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
            if (waitsInterrupted.load())
                throw Error("cannot write '" + path_ + "': no reader opened the FIFO before carom was asked to stop");
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
#endif
    if (!stream_.is_open()) stream_.open(path_, std::ios::binary);
    if (!stream_) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
}

// Copies the existing target into the temporary file, which a resumed run
// then appends to. A failure (a full disk) names its reason and leaves the
// target as it was; the caller removes the partial copy.
void AtomicFile::copyTarget() {
    std::ifstream in(target_, std::ios::binary);
    if (!in) throw Error("cannot append to '" + path_ + "': cannot read it: " + std::strerror(errno));
    std::vector<char> block(std::size_t(1) << 20);
    for (;;) {
        in.read(block.data(), std::streamsize(block.size()));
        const std::streamsize count = in.gcount();
        if (count == 0) break;
        errno = 0;
        stream_.write(block.data(), count);
        if (count < std::streamsize(block.size())) stream_.flush();  // the last block: its write errors now
        if (!stream_) {
            const int reason = errno;
            throw Error("cannot append to '" + path_ + "': copying it to '" + temporaryPath_ + "' failed: " +
                        (reason ? std::strerror(reason) : "write error (disk full?)") + "; the file is unchanged");
        }
    }
    if (in.bad()) throw Error("cannot append to '" + path_ + "': reading it failed");
}

// The reason is errno when the failed write set it (a full disk, a quota, a
// file size limit); the stream does not promise to.
void AtomicFile::failWrite(int error) const {
    const std::string reason = error ? std::strerror(error) : "write error (disk full?)";
    if (temporaryPath_.empty()) throw Error("writing '" + path_ + "' failed: " + reason);
    throw Error("writing '" + path_ + "' failed: " + reason + "; the previous file, if any, is unchanged");
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
        if (!syncToDisk(temporaryPath_))
            throw Error("writing '" + path_ + "' failed: syncing it to the disk: " + std::strerror(errno) +
                        "; the previous file, if any, is unchanged");
        // std::filesystem::rename replaces an existing target on Windows too,
        // where std::rename refuses.
        std::error_code error;
        fs::rename(temporaryPath_, target_, error);
        if (error) throw Error("cannot rename '" + temporaryPath_ + "' to '" + target_ + "': " + error.message());
        if (registered_ >= 0) temporarySlots[registered_].state.store(kFree);
        registered_ = -1;
        // The file is in place now; a folder that cannot be synced (some file
        // systems refuse) leaves it as safe as a plain rename would.
        const fs::path folder = fs::path(target_).parent_path();
        syncToDisk(folder.empty() ? fs::path(".") : folder);
    }
    committed_ = true;
}

}  // namespace carom::io
