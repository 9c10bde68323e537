#include "app/output_plan.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#if __has_include(<unistd.h>) && !defined(_WIN32)
#include <sys/stat.h>
#include <unistd.h>
#define CAROM_POSIX_FILES 1
#endif

#include <carom/carom.h>
#include <carom/files.h>

namespace carom::app {
namespace fs = std::filesystem;

namespace {

std::string quoted(const std::string& option, const std::string& path) { return option + " '" + path + "'"; }

// The folder `path`'s file goes in (its symlinks followed) and its name.
fs::path folderOf(const std::string& path) {
    const fs::path folder = fs::absolute(io::followSymlinks(path)).parent_path();
    return folder.empty() ? fs::path(".") : folder;
}

// Whether `path` is a file `folder` holds whose name `writes` claims.
bool writtenIn(const std::string& path, const std::string& folder,
               const std::function<bool(const std::string&)>& writes) {
    return writes(io::followSymlinks(path).filename().string()) && io::sameFile(folderOf(path).string(), folder);
}

// "standard output" or "standard error" when `path` is the regular file one
// of them goes to (`> file`), which replacing would take from under carom's
// own messages; null otherwise (a terminal or a pipe is written directly).
const char* standardStreamOf(const std::string& path) {
#ifdef CAROM_POSIX_FILES
    struct stat file {};
    if (::stat(path.c_str(), &file) != 0 || !S_ISREG(file.st_mode)) return nullptr;
    for (const auto& [descriptor, name] : {std::pair{1, "standard output"}, std::pair{2, "standard error"}}) {
        struct stat stream {};
        if (::fstat(descriptor, &stream) == 0 && stream.st_dev == file.st_dev && stream.st_ino == file.st_ino)
            return name;
    }
#else
    (void)path;
#endif
    return nullptr;
}

// Whether carom may create and write files in `folder`, or in the first
// folder above it that exists (where it would be created): errno's reason
// in `why` if not.
bool writableFolder(fs::path folder, std::string& why) {
    std::error_code error;
    folder = fs::absolute(folder, error);
    while (!fs::exists(folder, error) && folder.has_relative_path()) folder = folder.parent_path();
    if (!fs::is_directory(folder, error)) {
        why = "'" + folder.string() + "' is not a folder";
        return false;
    }
#ifdef CAROM_POSIX_FILES
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        why = "cannot write in '" + folder.string() + "': " + std::strerror(errno);
        return false;
    }
#endif
    return true;
}

}  // namespace

CLI::Option* fileOption(CLI::Option* option) {
    return option->check([](const std::string& path) {
        return path.empty() ? std::string("an empty file name; give a path, or leave the option out") : "";
    });
}

void OutputPlan::input(std::string option, std::string path) {
    inputs_.push_back({std::move(option), std::move(path)});
}

void OutputPlan::output(std::string option, std::string path) {
    outputs_.push_back({std::move(option), std::move(path)});
}

void OutputPlan::outputFolder(std::string option, std::string path, std::function<bool(const std::string&)> writes) {
    folders_.push_back({std::move(option), std::move(path), std::move(writes)});
}

void OutputPlan::allowReplacing(std::string input, std::string output) {
    replaceable_.emplace_back(std::move(input), std::move(output));
}

void OutputPlan::check() const {
    for (const Named& output : outputs_) checkOutput(output);
    for (const Folder& folder : folders_) checkFolder(folder);
    for (const Named& output : outputs_) checkPlace(output);
    // Last, as they create (and remove) a file: every output can be written.
    for (const Named& output : outputs_) {
        if (io::isSpecialFile(output.path)) continue;  // opening a FIFO would wait for its reader
        try {
            io::AtomicFile probe(output.path);
        } catch (const Error& e) {
            throw Error(output.option + ": " + e.what());
        }
    }
}

void OutputPlan::checkOutput(const Named& a) const {
    std::error_code error;
    if (fs::is_directory(a.path, error))
        throw Error(quoted(a.option, a.path) + " is a folder; give the name of a file");
    // Outputs may share a character device (/dev/null): nothing is written over there.
    const bool device = fs::is_character_file(io::followSymlinks(a.path), error);
    for (const Named& b : outputs_) {
        if (&a < &b && !device && io::sameFile(a.path, b.path))
            throw Error(a.option + " and " + b.option + " name the same file ('" + a.path + "' and '" + b.path +
                        "'); give each output its own file");
        if (&a != &b && !io::isSpecialFile(a.path) && io::isTemporaryName(b.path, a.path))
            throw Error(quoted(b.option, b.path) + " is a temporary name of " + quoted(a.option, a.path) +
                        " (written to NAME.XXXXXX.partial beside it first, then renamed); give " + b.option +
                        " another name");
    }
    for (const Named& input : inputs_) {
        const bool allowed = std::find(replaceable_.begin(), replaceable_.end(), std::pair{input.option, a.option}) !=
                             replaceable_.end();
        if (!allowed && io::sameFile(a.path, input.path))
            throw Error(quoted(a.option, a.path) + " would overwrite the input " + quoted(input.option, input.path) +
                        "; write the output to another file");
    }
    for (const Folder& f : folders_) {
        if (io::sameFile(a.path, f.path))
            throw Error(a.option + " and " + f.option + " name the same file ('" + a.path + "' and '" + f.path +
                        "'); give each output its own file");
        if (writtenIn(a.path, f.path, f.writes))
            throw Error(quoted(a.option, a.path) + " is one of the files " + quoted(f.option, f.path) +
                        " writes; give " + a.option + " another name");
    }
}

// After the outputs are compared: "sub/../a.csv" is refused as another
// output's file before its folder's absence is reported.
void OutputPlan::checkPlace(const Named& a) const {
    std::error_code error;
    const fs::path folder = folderOf(a.path);
    if (!fs::is_directory(folder, error))
        throw Error(quoted(a.option, a.path) + ": the folder '" + folder.string() + "' " +
                    (fs::exists(folder, error) ? "is a file" : "does not exist") + "; create it, or write elsewhere");
    if (const char* stream = standardStreamOf(a.path))
        throw Error(quoted(a.option, a.path) + " is the file carom's " + stream +
                    " goes to; carom would replace it with the output and lose what it prints there; give the output "
                    "its own file");
}

void OutputPlan::checkFolder(const Folder& f) const {
    std::error_code error;
    if (fs::exists(f.path, error) && !fs::is_directory(f.path, error))
        throw Error(quoted(f.option, f.path) + " is a file; give a folder (it is created if missing)");
    std::string why;
    if (!writableFolder(f.path, why)) throw Error(quoted(f.option, f.path) + ": " + why);
    for (const Folder& g : folders_)
        if (&f < &g && io::sameFile(f.path, g.path))
            throw Error(f.option + " and " + g.option + " name the same folder ('" + f.path + "' and '" + g.path +
                        "'); give each its own");
    for (const Named& input : inputs_)
        if (writtenIn(input.path, f.path, f.writes))
            throw Error(quoted(f.option, f.path) + " would overwrite the input " + quoted(input.option, input.path) +
                        ", one of the files it writes; give " + f.option + " another folder");
}

void createFolder(const std::string& option, const std::string& path) {
    std::error_code error;
    fs::create_directories(path, error);
    if (error || !fs::is_directory(path, error))
        throw Error("cannot create the folder " + quoted(option, path) + ": " +
                    (error ? error.message() : "a file of that name exists"));
}

}  // namespace carom::app
