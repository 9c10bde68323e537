// Several processes, one world: a World split into rectangular domains, one
// per process of an MPI communicator (for example under `mpirun`).
//
// Every process makes the same World from the same WorldDef and disks, with
// WorldDef::decomposition set to the same decomposition:
//
//     MPI_Init(&argc, &argv);
//     carom::WorldDef def = ...;
//     def.decomposition = carom::makeDecomposition({MPI_COMM_WORLD});
//     carom::World world(def);
//     world.setDisks(disks);  // the whole world's disks, on every process
//     world.step(1000);
//
// Each process then steps the disks whose centres lie in its domain, with
// copies of those around it, and hands disks on as they cross. The results
// are bit for bit those of one process, whatever the number of processes
// and the domains: the states, the totals and everything measured from them.
// step, setDisks and the other edits are collective: every process calls
// them, in the same order. At the end of each step call every process
// gathers the whole world, so the reads between steps (getDisks, the
// observables, the measurements) are each process's own and give the whole
// world on every process. With Gather::OnRequest the whole world comes only
// at World::gather(), and World::ownDisks() reads a process's own disks.
//
// Python takes the same path: carom.World(..., comm=MPI.COMM_WORLD) with
// mpi4py (docs/mpi.md). Every engine steps a domain (an OpenCL one on the
// node's GPU r mod their count for the node's process r, unless
// WorldDef::device names one), with the stepped schemes
// (CollisionScheme::Pairwise and Simultaneous); Events is refused.
// World::decompositionCosts() says what the split costs.
// This header exists only where carom was built with MPI.
#pragma once

#include <memory>
#include <string>

#include <mpi.h>

#include <carom/types.h>

namespace carom {

/// When every process receives the whole world (DecompositionDef::gather).
enum class Gather {
    /// After every World::step call: every read between steps is the whole
    /// world's, on every process.
    EachStep,
    /// Only at World::gather(): between steps a process reads its own disks
    /// (World::ownDisks) and pays nothing for the others'. The reads of the
    /// whole world (the disks, the observables, the measurements, snapshots)
    /// and the edits throw Error until every process has called gather().
    OnRequest,
};

/// How a world is split among the processes of a communicator.
struct DecompositionDef {
    /// The processes: each takes one domain, rank r the r-th in rows from
    /// the bottom left. carom duplicates it, so its messages never mix with
    /// the caller's. Must be an intra-communicator.
    MPI_Comm communicator = MPI_COMM_WORLD;
    /// Domains across and up the box, whose product is the number of
    /// processes; 0 and 0 (the default): chosen from the number of processes
    /// and the box's aspect, as square as they can be. Each domain must be at
    /// least one grid cell wide and high (World::setDisks refuses others).
    int domainsX = 0;
    int domainsY = 0;
    Gather gather = Gather::EachStep;
};

/// Splits worlds as `def` says; throws Error for domains that do not
/// multiply to the number of processes. Collective: every process of the
/// communicator calls it.
std::shared_ptr<const Decomposition> makeDecomposition(const DecompositionDef& def);

/// Returns where every process's `failure` is empty; else throws Error, on
/// every process, with the failure of the lowest process that had one,
/// named ("process 3 of 8: ..."). Collective: for a program whose processes
/// may fail apart (a file one node cannot read), so that none goes on to
/// wait for one that gave up.
void requireEveryProcess(const Decomposition& decomposition, const std::string& failure);

}  // namespace carom
