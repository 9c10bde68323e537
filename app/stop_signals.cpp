#include "app/stop_signals.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iterator>

#ifdef _WIN32
#include <io.h>
#else
#include <unistd.h>
#endif

#include <carom/files.h>

namespace carom::app {
namespace {

// SIGHUP is POSIX only (Windows has no hangup).
constexpr int kStopSignals[] = {SIGINT, SIGTERM,
#ifdef SIGHUP
                                SIGHUP
#endif
};
constexpr std::size_t kCount = std::size(kStopSignals);

volatile std::sig_atomic_t receivedSignal = 0;  // the first stop signal, 0 before it

// A second signal kills, but only from a second after the first: `timeout`
// sends its signal twice at once (to carom, then to its process group), and
// that must stop the run, not kill it.
constexpr std::int64_t kSecondSignalKillsAfterNs = 1'000'000'000;
std::atomic<std::int64_t> firstSignalAtNs{0};  // lock-free, so the handler may use it
static_assert(std::atomic<std::int64_t>::is_always_lock_free);

std::int64_t steadyNanoseconds() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

std::atomic<bool> firstSignalEnds{true};
static_assert(std::atomic<bool>::is_always_lock_free);
const char* commandName = "carom";

// Writes `text` on stderr from a signal handler (no stdio there).
void say(const char* text) {
#ifdef _WIN32
    _write(2, text, static_cast<unsigned>(std::strlen(text)));
#else
    if (write(2, text, std::strlen(text)) < 0) return;  // nothing to do about it: the program ends
#endif
}

const char* nameOf(int signal) {
    switch (signal) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
#ifdef SIGHUP
        case SIGHUP: return "SIGHUP";
#endif
        default: return "a signal";
    }
}

extern "C" void onStopSignal(int signal) {
    const std::int64_t now = steadyNanoseconds();
    if (firstSignalEnds.load() && receivedSignal == 0) {
        // Only async-signal-safe calls: the files, the message, the exit.
        io::removeTemporaryFiles();
        say(commandName);
        say(": interrupted by ");
        say(nameOf(signal));
        say(" before writing any output; every file is as it was\n");
        std::_Exit(signalExitStatus(signal));
    }
    if (receivedSignal == 0 || now - firstSignalAtNs < kSecondSignalKillsAfterNs) {
        if (receivedSignal == 0) {
            firstSignalAtNs = now;
            receivedSignal = signal;
            io::interruptWaits();
        }
        std::signal(signal, onStopSignal);  // where delivery resets the handler (Windows)
        return;
    }
    io::removeTemporaryFiles();
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

using Handler = void (*)(int);
Handler previous[kCount] = {};

}  // namespace

StopSignals::StopSignals(FirstSignal first, const char* command) {
    receivedSignal = 0;
    commandName = command;
    setFirstSignal(first);
    for (std::size_t i = 0; i < kCount; ++i) {
        previous[i] = std::signal(kStopSignals[i], onStopSignal);
        if (previous[i] == SIG_IGN) std::signal(kStopSignals[i], SIG_IGN);
    }
}

StopSignals::~StopSignals() {
    for (std::size_t i = 0; i < kCount; ++i) {
        if (previous[i] != SIG_ERR) std::signal(kStopSignals[i], previous[i]);
    }
}

void StopSignals::setFirstSignal(FirstSignal first) { firstSignalEnds.store(first == FirstSignal::Ends); }

int StopSignals::received() { return receivedSignal; }

const char* signalName(int signal) { return nameOf(signal); }

}  // namespace carom::app
