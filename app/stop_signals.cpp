#include "app/stop_signals.h"

#include <csignal>
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

volatile std::sig_atomic_t receivedSignal = 0;
bool handled[kCount] = {};  // the signals whose handler StopSignals installed

extern "C" void onStopSignal(int signal) {
    receivedSignal = signal;
    for (std::size_t i = 0; i < kCount; ++i)
        if (handled[i]) std::signal(kStopSignals[i], SIG_DFL);  // the second one kills
}

using Handler = void (*)(int);
Handler previous[kCount] = {};

}  // namespace

StopSignals::StopSignals() {
    receivedSignal = 0;
    for (std::size_t i = 0; i < kCount; ++i) {
        previous[i] = std::signal(kStopSignals[i], onStopSignal);
        handled[i] = previous[i] != SIG_IGN;
        if (!handled[i]) std::signal(kStopSignals[i], SIG_IGN);
    }
}

StopSignals::~StopSignals() {
    for (std::size_t i = 0; i < kCount; ++i) {
        if (previous[i] != SIG_ERR) std::signal(kStopSignals[i], previous[i]);
        handled[i] = false;
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
