#include "app/stop_signals.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <iterator>

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

extern "C" void onStopSignal(int signal) {
    const std::int64_t now = steadyNanoseconds();
    if (receivedSignal == 0 || now - firstSignalAtNs < kSecondSignalKillsAfterNs) {
        if (receivedSignal == 0) {
            firstSignalAtNs = now;
            receivedSignal = signal;
        }
        std::signal(signal, onStopSignal);  // where delivery resets the handler (Windows)
        return;
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

using Handler = void (*)(int);
Handler previous[kCount] = {};

}  // namespace

StopSignals::StopSignals() {
    receivedSignal = 0;
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

int StopSignals::received() { return receivedSignal; }

const char* signalName(int signal) {
    switch (signal) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
#ifdef SIGHUP
        case SIGHUP: return "SIGHUP";
#endif
        default: return "a signal";
    }
}

}  // namespace carom::app
