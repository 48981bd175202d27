// The library's PETSc solver as this program has it: the LinearSolver here holds one made inside
// PETSc's module, opened on first use (see modules/petsc_module.h for why).
#include "flow/linear_solver.h"
#include "modules/petsc_module.h"
#include "parallel/processes.h"
#include "io/hdf5_file.h"
#include "modules.h"

#include <cstdlib>

namespace vesselmesh::flow {
namespace {

const PetscCalls& petsc_calls() {
  // Global: OpenMPI's components, which PETSc's MPI loads in turn, look for its symbols there.
  static const auto* calls = static_cast<const PetscCalls*>(
      cli::open_module(kPetscModuleFile, "vesselmesh_petsc_calls", kPetscCallsLayout, /*global=*/true));
  return *calls;
}

}  // namespace

// Here, Impl is the solver the module made (the module has its own, PETSc's, Impl).
struct LinearSolver::Impl {
  LinearSolver* inside = nullptr;
};


LinearSolver::LinearSolver(SparsePattern pattern, int block_size, const std::string& defaults,
                           const std::string& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->inside = petsc_calls().create(std::move(pattern), block_size, defaults, options);
}

LinearSolver::~LinearSolver() {
  if (impl_ && impl_->inside) petsc_calls().destroy(impl_->inside);
}

const SparsePattern& LinearSolver::pattern() const { return petsc_calls().pattern(*impl_->inside); }

SolveStats LinearSolver::solve(const std::vector<double>& values, const std::vector<double>& rhs,
                               std::vector<double>& x) {
  return petsc_calls().solve(*impl_->inside, values, rhs, x);
}

MatrixValues LinearSolver::begin_assembly() { return petsc_calls().begin_assembly(*impl_->inside); }
void LinearSolver::end_assembly() { petsc_calls().end_assembly(*impl_->inside); }
SolveStats LinearSolver::solve_assembled(const std::vector<double>& rhs, std::vector<double>& x) {
  return petsc_calls().solve_assembled(*impl_->inside, rhs, x);
}

void LinearSolver::set_residual_floor(double relative) { petsc_calls().set_residual_floor(*impl_->inside, relative); }
void LinearSolver::set_residual_check(bool on) { petsc_calls().set_residual_check(*impl_->inside, on); }
bool LinearSolver::sweep_velocity_blocks() { return petsc_calls().sweep_velocity_blocks(*impl_->inside); }
void LinearSolver::scale_tolerance(double factor) { petsc_calls().scale_tolerance(*impl_->inside, factor); }

double LinearSolver::relative_residual(const std::vector<double>& rhs, const std::vector<double>& x) {
  return petsc_calls().relative_residual(*impl_->inside, rhs, x);
}

SolveStats LinearSolver::solve_assembled_direct(const std::vector<double>& rhs, std::vector<double>& x) {
  return petsc_calls().solve_assembled_direct(*impl_->inside, rhs, x);
}

void LinearSolver::reuse_preconditioner(bool on) { petsc_calls().reuse_preconditioner(*impl_->inside, on); }
void LinearSolver::rebuild_preconditioner() { petsc_calls().rebuild_preconditioner(*impl_->inside); }
void LinearSolver::keep_solutions(int count) { petsc_calls().keep_solutions(*impl_->inside, count); }
void LinearSolver::forget_solutions() { petsc_calls().forget_solutions(*impl_->inside); }
void LinearSolver::set_low_rank_columns(const std::vector<std::vector<double>>& columns) {
  petsc_calls().set_low_rank_columns(*impl_->inside, columns);
}
void LinearSolver::set_low_rank_coefficients(const std::vector<double>& coefficients) {
  petsc_calls().set_low_rank_coefficients(*impl_->inside, coefficients);
}
std::string LinearSolver::description() const { return petsc_calls().description(*impl_->inside); }

}  // namespace vesselmesh::flow

namespace vesselmesh::parallel {

using flow::petsc_calls;

int process_count() { return petsc_calls().process_count(); }
int process_rank() { return petsc_calls().process_rank(); }
bool any_process(bool flag) { return petsc_calls().any_process(flag); }
std::vector<double> gather_all(double value) { return petsc_calls().gather_all(value); }
std::vector<double> sum_all(std::vector<double> values) { return petsc_calls().sum_all(std::move(values)); }
std::vector<double> gather_to_first(const std::vector<double>& values) {
  return petsc_calls().gather_to_first(values);
}
std::vector<int> partition_graph(const std::vector<int>& start, const std::vector<int>& neighbours, int parts) {
  return petsc_calls().partition_graph(start, neighbours, parts);
}
std::string scatter_from_first(const std::function<std::string(int rank)>& make) {
  return petsc_calls().scatter_from_first(make);
}
void abort_all(int code) {
  petsc_calls().abort_all(code);
  std::abort();  // not reached
}
void error_told_together(double seconds) { petsc_calls().error_told_together(seconds); }

}  // namespace vesselmesh::parallel

namespace vesselmesh::io {

void write_hdf5(const std::string& path, const std::vector<Hdf5Dataset>& datasets) {
  flow::petsc_calls().write_hdf5(path, datasets);
}

}  // namespace vesselmesh::io
