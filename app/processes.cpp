#include "app/processes.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <thread>

#ifdef CAROM_HAVE_MPI
#include <mpi.h>

#include <carom/decomposition.h>
#ifndef _WIN32
#include <unistd.h>
#endif
#endif

namespace carom::app {

namespace {

int rank = 0, count = 1;
bool started = false;    // MPI_Init was called here
FILE* errors = nullptr;  // standard error as it was, on a process whose own is silenced

}  // namespace

Processes::Processes(int& argc, char**& argv) {
#ifdef CAROM_HAVE_MPI
    // Only under a launcher: MPI_Init in a lone process costs start-up time
    // and, on some hosts, needs a network it does not have.
    const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
    if (!launched) return;
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    started = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &count);
#ifndef _WIN32
    if (rank != 0) {
        errors = fdopen(dup(2), "w");
        (void)std::freopen("/dev/null", "w", stdout);
        (void)std::freopen("/dev/null", "w", stderr);
    }
#endif
#else
    (void)argc;
    (void)argv;
#endif
}

Processes::~Processes() {
#ifdef CAROM_HAVE_MPI
    if (started) MPI_Finalize();
#endif
}

int processRank() { return rank; }
int processCount() { return count; }

bool anyProcess(bool yes) {
#ifdef CAROM_HAVE_MPI
    if (count > 1) {
        int any = yes ? 1 : 0;
        MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
        return any != 0;
    }
#endif
    return yes;
}

double slowestProcess(double seconds) {
#ifdef CAROM_HAVE_MPI
    if (count > 1) MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
#endif
    return seconds;
}

std::uint64_t processZeros(std::uint64_t value) {
#ifdef CAROM_HAVE_MPI
    if (count > 1) MPI_Bcast(&value, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
#endif
    return value;
}

int reportError(const std::string& message) {
    if (rank == 0) {
        std::fprintf(stderr, "carom: error: %s\n", message.c_str());
        std::fflush(stderr);
    }
#ifdef CAROM_HAVE_MPI
    if (count > 1) {
        if (rank != 0) {
            // Most errors are every process's (bad input), and process 0's
            // abort ends this one first; one that waits this long is alone.
            std::this_thread::sleep_for(std::chrono::seconds(2));
            std::fprintf(errors ? errors : stderr, "carom: error (process %d of %d): %s\n", rank, count,
                         message.c_str());
            std::fflush(errors ? errors : stderr);
        }
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
#endif
    return 1;
}

void everyProcess(const Decomposition* decomposition, const std::function<void()>& work) {
#ifdef CAROM_HAVE_MPI
    if (decomposition) {
        std::string failure;
        try {
            work();
        } catch (const std::exception& e) {
            failure = e.what();
        }
        requireEveryProcess(*decomposition, failure);
        return;
    }
#else
    (void)decomposition;
#endif
    work();
}

std::vector<DecompositionCosts> processCosts(const DecompositionCosts& mine) {
    std::vector<DecompositionCosts> all;
#ifdef CAROM_HAVE_MPI
    if (count > 1) {
        if (rank == 0) all.resize(std::size_t(count));
        MPI_Gather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, 0, MPI_COMM_WORLD);
    }
#else
    (void)mine;
#endif
    return all;
}

std::shared_ptr<const Decomposition> runDecomposition(int domainsX, int domainsY) {
#ifdef CAROM_HAVE_MPI
    if (count > 1) return makeDecomposition(DecompositionDef{MPI_COMM_WORLD, domainsX, domainsY});
#endif
    if (std::int64_t(domainsX) * domainsY > 1)
        throw Error("--domains " + std::to_string(domainsX) + " " + std::to_string(domainsY) +
                    " in one process; allowed: several domains only under mpirun"
#ifndef CAROM_HAVE_MPI
                    " (this carom was built without MPI)"
#endif
                    ", one process per domain");
    return nullptr;
}

}  // namespace carom::app
