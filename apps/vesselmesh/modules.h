// The modules this program opens when a command needs them (Gmsh's and PETSc's code: see
// modules/gmsh_module.h and modules/petsc_module.h): looked for beside the program (a build folder),
// then in ../lib/vesselmesh (an installed program).
#pragma once

namespace vesselmesh::cli {

// The table the module's C function `entry` returns, checked to have `layout` as its first
// int; InputError naming the module, where it was looked for and why not, when it cannot be
// had. `global`: its symbols visible to the libraries it loads in turn (MPI's components).
const void* open_module(const char* file, const char* entry, int layout, bool global = false);

}  // namespace vesselmesh::cli
