// Another program run to its end, as a shell would, but without one: the study runs a flow under
// `mpirun` this way (study/study.h, `ranks`).
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

}  // namespace vesselmesh::io
