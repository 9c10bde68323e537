// Preloaded (LD_PRELOAD) into carom by outputs.synced_before_rename: logs
// every fsync, with the path of its descriptor, and every rename to the file
// named by $CAROM_SPY_LOG, then does the real call. Linux only (/proc).
#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>

namespace {

void note(const char* call, const char* path) {
    const char* log = std::getenv("CAROM_SPY_LOG");
    if (log == nullptr) return;
    if (std::FILE* file = std::fopen(log, "a")) {
        std::fprintf(file, "%s %s\n", call, path);
        std::fclose(file);
    }
}

template <class Function>
Function real(const char* name) {
    return reinterpret_cast<Function>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" int fsync(int descriptor) {
    static const auto next = real<int (*)(int)>("fsync");
    char link[64], path[PATH_MAX];
    std::snprintf(link, sizeof link, "/proc/self/fd/%d", descriptor);
    const ssize_t length = readlink(link, path, sizeof path - 1);
    path[length > 0 ? length : 0] = '\0';
    note("fsync", path);
    return next(descriptor);
}

extern "C" int rename(const char* from, const char* to) {
    static const auto next = real<int (*)(const char*, const char*)>("rename");
    note("rename", from);
    return next(from, to);
}
