// SIGINT, SIGTERM and SIGHUP: Ctrl-C, and what `timeout`, Slurm, `docker stop`
// and a closed terminal send. While a StopSignals object lives, the first of
// them is only recorded: `carom run` and `carom view` stop at their next step
// boundary, write their outputs and exit 128 + the signal. A second signal,
// a second or more after the first, kills at once (`timeout` sends two at
// once). A signal ignored when the object is made (nohup, a shell's
// background job) stays ignored.
#pragma once

namespace carom::app {

class StopSignals {
public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

    // The signal received, 0 while none has come.
    static int received();
};

// "SIGTERM" for SIGTERM.
const char* signalName(int signal);

// 128 + the signal: the status a shell reports for a process the signal ended.
inline int signalExitStatus(int signal) { return 128 + signal; }

}  // namespace carom::app
