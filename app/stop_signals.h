// SIGINT, SIGTERM and SIGHUP: Ctrl-C, and what `timeout`, Slurm, `docker stop`
// and a closed terminal send. While a StopSignals object lives they do one
// of two things, as the command sets:
//  - FirstSignal::Ends (before a command has anything to write, and through
//    the work of one that writes only at its end): the program ends at once
//    with 128 + the signal, its temporary files removed, every file as it was.
//  - FirstSignal::Stops: the first signal is only recorded, and the command
//    (`carom run`, `carom view`) stops at its next step boundary, writes its
//    outputs and exits 128 + the signal; a FIFO output with no reader is no
//    longer waited for. A second signal, a second or more after the first,
//    ends the program at once, its temporary files removed (`timeout` sends
//    two at once).
// A signal ignored when the object is made (nohup, a shell's background job)
// stays ignored.
#pragma once

namespace carom::app {

class StopSignals {
public:
    enum class FirstSignal { Ends, Stops };

    // `command` ("carom run") names the program in the message of a signal that ends it.
    StopSignals(FirstSignal first, const char* command);
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

    // What the next first signal does.
    void setFirstSignal(FirstSignal first);

    // The signal received, 0 while none has come.
    static int received();
};

// "SIGTERM" for SIGTERM.
const char* signalName(int signal);

// 128 + the signal: the status a shell reports for a process the signal ended.
inline int signalExitStatus(int signal) { return 128 + signal; }

}  // namespace carom::app
