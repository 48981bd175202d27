// PETSc, loaded only when a command needs it (the flow solver; the HDF5 its build brings, for the
// XDMF export, io/hdf5_file.h), as Gmsh is (modules/gmsh_module.h):
// PETSc and what it brings (MPI, hypre, MUMPS, Trilinos, ...) cost every command 0.07-0.09 s
// of symbol binding at start. flow/linear_solver.cpp is built into vesselmesh_lib, which the
// tests and benchmarks link with PETSc, and into the module libvesselmesh-petsc.so, which the
// program opens on first use (apps/vesselmesh/petsc_calls.cpp forwards to this table).
#pragma once

#include "flow/linear_solver.h"
#include "parallel/processes.h"
#include "io/hdf5_file.h"

namespace vesselmesh::flow {

inline constexpr const char* kPetscModuleFile = "libvesselmesh-petsc.so";

// The module's entry points: a LinearSolver made, used and destroyed inside the module; `layout`
// first, as in modules/gmsh_module.h (raise it when this table or a type it passes changes).
inline constexpr int kPetscCallsLayout = 16;
struct PetscCalls {
  int layout;
  int (*process_count)();
  int (*process_rank)();
  bool (*any_process)(bool flag);
  std::vector<double> (*gather_all)(double value);
  std::vector<double> (*sum_all)(std::vector<double> values);
  std::vector<double> (*gather_to_first)(const std::vector<double>& values);
  std::vector<int> (*partition_graph)(const std::vector<int>& start, const std::vector<int>& neighbours,
                                      int parts);
  std::string (*scatter_from_first)(const std::function<std::string(int rank)>& make);
  void (*abort_all)(int code);
  void (*error_told_together)(double seconds);
  LinearSolver* (*create)(SparsePattern pattern, int block_size, const std::string& defaults,
                          const std::string& options);
  void (*destroy)(LinearSolver* solver);
  const SparsePattern& (*pattern)(const LinearSolver& solver);
  SolveStats (*solve)(LinearSolver& solver, const std::vector<double>& values, const std::vector<double>& rhs,
                      std::vector<double>& x);
  MatrixValues (*begin_assembly)(LinearSolver& solver);
  void (*end_assembly)(LinearSolver& solver);
  SolveStats (*solve_assembled)(LinearSolver& solver, const std::vector<double>& rhs, std::vector<double>& x);
  SolveStats (*solve_assembled_direct)(LinearSolver& solver, const std::vector<double>& rhs, std::vector<double>& x);
  double (*relative_residual)(LinearSolver& solver, const std::vector<double>& rhs, const std::vector<double>& x);
  void (*set_residual_floor)(LinearSolver& solver, double relative);
  void (*set_residual_check)(LinearSolver& solver, bool on);
  bool (*sweep_velocity_blocks)(LinearSolver& solver);
  void (*scale_tolerance)(LinearSolver& solver, double factor);
  void (*reuse_preconditioner)(LinearSolver& solver, bool on);
  void (*rebuild_preconditioner)(LinearSolver& solver);
  void (*keep_solutions)(LinearSolver& solver, int count);
  void (*forget_solutions)(LinearSolver& solver);
  std::string (*description)(const LinearSolver& solver);
  void (*set_low_rank_columns)(LinearSolver& solver, const std::vector<std::vector<double>>& columns);
  void (*set_low_rank_coefficients)(LinearSolver& solver, const std::vector<double>& coefficients);
  void (*write_hdf5)(const std::string& path, const std::vector<io::Hdf5Dataset>& datasets);
};

}  // namespace vesselmesh::flow

extern "C" const vesselmesh::flow::PetscCalls* vesselmesh_petsc_calls();
