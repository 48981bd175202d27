// Another program run to its end, as a shell would, but without one: the study runs a flow under
// `mpirun` this way (study/study.h, `ranks`). And this process's memory, as the flow reports it.
#pragma once

#include <string>
#include <vector>

namespace vesselmesh::io {

// Runs `argv` (argv[0] looked up on PATH), its output and errors on ours, with our environment
// less the variables whose names begin with one of `drop` and with `environment`'s NAME=VALUE
// entries set (in place of ours of the same name); waits for it. SIGTERM and SIGINT reaching this process
// meanwhile are passed on to it (mpirun passes them on to its processes), so that it ends as it
// would have alone. Returns its exit code, or 128 + the signal that ended it; InputError when the
// program cannot be started (not found), naming it.
int run_process(const std::vector<std::string>& argv, const std::vector<std::string>& environment = {},
                const std::vector<std::string>& drop = {});

// This process's peak resident memory so far (MB).
double peak_memory_mb();
// This process's resident pages of mapped files (MB; /proc/self/status RssFile, 0 where there is
// none): the shared libraries' code and constants, mapped once at the start and shared by every
// process of a node (about 57 MB here: PETSc and its solvers, MPI, VTK, Gmsh). The peak less it is
// the memory the process holds of its own.
double file_memory_mb();

}  // namespace vesselmesh::io
