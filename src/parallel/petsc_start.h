// PETSc's start and its errors, shared by the files that call PETSc (parallel/processes.cpp,
// flow/linear_solver.cpp); not a public header, and without PETSc's own headers.
#pragma once

#include <string>

namespace vesselmesh::parallel {

// PETSc (and MPI under it) start once per process, on first use, and end when it exits; PETSc's
// errors are kept (its first message of a chain) for check_petsc.
void ensure_petsc();
// The message PETSc's last error left (empty: none), forgotten once read.
std::string take_petsc_message();
// Throws InternalError with PETSc's words when `code` (a PetscErrorCode) is not 0; `what` names the call.
void check_petsc(int code, const char* what);

}  // namespace vesselmesh::parallel
