// The collective calls of a run on several processes (MPI, started through PETSc): what a
// newcomer reads to know how the processes of `mpirun -np N vesselmesh simulate` talk. Every
// function here is called by every process unless it says otherwise; on one process each is
// trivial (nothing is sent). The flow stage is built on it (flow/mesh_part.h distributes a mesh,
// flow/navier_stokes.h sums and gathers); PETSc's headers stay in processes.cpp, and the program
// reaches it through PETSc's module as it reaches the solver (modules/petsc_module.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace vesselmesh::parallel {

// The number of MPI processes this program runs on and this one's rank (start PETSc and MPI
// when needed).
int process_count();
int process_rank();
// Whether `flag` is true on any process (every process calls it; one process: the flag).
bool any_process(bool flag);
// Every process's `value`, in rank order (every process calls it).
std::vector<double> gather_all(double value);
// The sums over the processes of `values` (as long on every process), on every process.
std::vector<double> sum_all(std::vector<double> values);
// Every process's `values` one after the other in rank order, on the first process (empty on
// the others).
std::vector<double> gather_to_first(const std::vector<double>& values);
// Graph partitioning (PT-Scotch, through PETSc's MatPartitioning) on the calling process alone:
// the points of a graph (rows `start`, `neighbours` by number, itself possibly among them) split
// into `parts` parts balanced in points (within 1 %), with few edges cut; on one thread with a
// fixed seed, so that the same graph gives the same parts, run after run. Returns every point's
// part (all 0 for one part).
std::vector<int> partition_graph(const std::vector<int>& start, const std::vector<int>& neighbours, int parts);
// The first process makes each other process's bytes (`make(rank)`, rank 1, 2, ..., one at a time,
// each sent before the next is made) and every other process returns its own; the first returns
// none (every process calls it).
std::string scatter_from_first(const std::function<std::string(int rank)>& make);
// Ends every process at once (MPI_Abort) with this exit code: for a failure on one process that
// the others, waiting on it, would not see.
[[noreturn]] void abort_all(int code);
// An error every process raised alike, told by the first: the first (its stderr flushed) says so to
// the others, which wait for that word, `seconds` at most (an error raised on some only must not
// hang them), before they end with the error's code: mpirun ends every process once one has ended
// with an error, which could cut the first's message short. One process: nothing to wait for.
void error_told_together(double seconds);

}  // namespace vesselmesh::parallel
