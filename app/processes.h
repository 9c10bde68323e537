// The processes of one `carom` run: one, or those `mpirun` (or another MPI
// launcher) started, which then split the world among them
// (carom/decomposition.h). Process 0 prints and writes the files; every
// process takes the same steps and decisions, agreed where they could differ
// (a signal, a failed write, a chunk of steps timed on one process).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <carom/types.h>

namespace carom::app {

// Starts MPI where an MPI launcher started this process, and ends it at
// destruction. On processes other than 0, standard output and error are
// silenced: process 0 speaks for the run (reportError still reaches the user).
class Processes {
public:
    Processes(int& argc, char**& argv);
    ~Processes();
    Processes(const Processes&) = delete;
    Processes& operator=(const Processes&) = delete;
};

int processRank();   // 0 in a run of one process
int processCount();  // 1 without an MPI launcher
// Whether any process says yes: the same answer on every one (collective).
bool anyProcess(bool yes);
// The largest of every process's `seconds`, on every process (collective).
double slowestProcess(double seconds);
// Process 0's `value`, on every process (collective).
std::uint64_t processZeros(std::uint64_t value);
// Prints `message` as carom's error and, with several processes, ends them
// all (MPI_Abort): one that failed alone must not leave the others waiting.
// Returns the exit status for one process.
int reportError(const std::string& message);
// Runs `work` on every process of `decomposition` (alone where it is null);
// where it throws on any of them, throws on every one the Error of the lowest
// process that failed, named, so that none goes on alone (collective).
void everyProcess(const Decomposition* decomposition, const std::function<void()>& work);
// Every process's decomposition costs, in rank order, on process 0; empty
// on the others and in one process (collective).
std::vector<DecompositionCosts> processCosts(const DecompositionCosts& mine);
// The decomposition of a run of several processes into domainsX x domainsY
// (0 x 0: chosen from the box); empty in one process, where domains other
// than 1 x 1 or 0 x 0 are refused.
std::shared_ptr<const Decomposition> runDecomposition(int domainsX, int domainsY);

}  // namespace carom::app
