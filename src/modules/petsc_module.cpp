// The entry table of libvesselmesh-petsc.so (see petsc_module.h); built into the module only.
#include "modules/petsc_module.h"

extern "C" __attribute__((visibility("default"))) const vesselmesh::flow::PetscCalls* vesselmesh_petsc_calls() {
  using namespace vesselmesh::flow;
  static const PetscCalls calls{
      kPetscCallsLayout,
      &vesselmesh::parallel::process_count,
      &vesselmesh::parallel::process_rank,
      &vesselmesh::parallel::any_process,
      &vesselmesh::parallel::gather_all,
      &vesselmesh::parallel::sum_all,
      &vesselmesh::parallel::gather_to_first,
      &vesselmesh::parallel::partition_graph,
      &vesselmesh::parallel::scatter_from_first,
      &vesselmesh::parallel::abort_all,
      &vesselmesh::parallel::error_told_together,
      [](SparsePattern pattern, int block_size, const std::string& defaults, const std::string& options) {
        return new LinearSolver(std::move(pattern), block_size, defaults, options);
      },
      [](LinearSolver* solver) { delete solver; },
      [](const LinearSolver& solver) -> const SparsePattern& { return solver.pattern(); },
      [](LinearSolver& solver, const std::vector<double>& values, const std::vector<double>& rhs,
         std::vector<double>& x) { return solver.solve(values, rhs, x); },
      [](LinearSolver& solver) { return solver.begin_assembly(); },
      [](LinearSolver& solver) { solver.end_assembly(); },
      [](LinearSolver& solver, const std::vector<double>& rhs, std::vector<double>& x) {
        return solver.solve_assembled(rhs, x);
      },
      [](LinearSolver& solver, const std::vector<double>& rhs, std::vector<double>& x) {
        return solver.solve_assembled_direct(rhs, x);
      },
      [](LinearSolver& solver, const std::vector<double>& rhs, const std::vector<double>& x) {
        return solver.relative_residual(rhs, x);
      },
      [](LinearSolver& solver, double relative) { solver.set_residual_floor(relative); },
      [](LinearSolver& solver, bool on) { solver.set_residual_check(on); },
      [](LinearSolver& solver) { return solver.sweep_velocity_blocks(); },
      [](LinearSolver& solver, double factor) { solver.scale_tolerance(factor); },
      [](LinearSolver& solver, bool on) { solver.reuse_preconditioner(on); },
      [](LinearSolver& solver) { solver.rebuild_preconditioner(); },
      [](LinearSolver& solver, int count) { solver.keep_solutions(count); },
      [](LinearSolver& solver) { solver.forget_solutions(); },
      [](const LinearSolver& solver) { return solver.description(); },
      [](LinearSolver& solver, const std::vector<std::vector<double>>& columns) {
        solver.set_low_rank_columns(columns);
      },
      [](LinearSolver& solver, const std::vector<double>& coefficients) {
        solver.set_low_rank_coefficients(coefficients);
      },
      &vesselmesh::io::write_hdf5,
  };
  return &calls;
}
