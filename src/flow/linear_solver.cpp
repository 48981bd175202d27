#include "flow/linear_solver.h"

#include "mesh/error.h"

#include <fmt/format.h>
#include <petscksp.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

namespace vesselmesh::flow {
namespace {

// PETSc reports errors through a handler: ours keeps the first message of the chain and returns
// the code, so that a failure becomes an exception with PETSc's words instead of a traceback.
thread_local std::string petsc_message;

PetscErrorCode keep_message(MPI_Comm, int, const char*, const char*, PetscErrorCode n, PetscErrorType p,
                            const char* message, void*) {
  if (p == PETSC_ERROR_INITIAL) petsc_message = message ? message : "";
  return n;
}

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  std::string text = petsc_message;
  petsc_message.clear();
  if (text.empty()) {
    const char* generic = nullptr;
    PetscErrorMessage(code, &generic, nullptr);
    text = generic ? generic : "unknown error";
  }
  throw InternalError(fmt::format("PETSc failed in {}: {}", what, text));
}

// PETSc (and MPI under it) start once per process and end when it exits.
void ensure_petsc() {
  static const bool started = [] {
    PetscBool initialized = PETSC_FALSE;
    PetscInitialized(&initialized);
    if (!initialized) {
      if (PetscInitializeNoArguments() != 0) throw InternalError("PETSc could not be initialized");
      std::atexit([] { PetscFinalize(); });
    }
    PetscPushErrorHandler(keep_message, nullptr);
    return true;
  }();
  (void)started;
}

}  // namespace

int process_count() {
  ensure_petsc();
  PetscMPIInt size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}

int process_rank() {
  ensure_petsc();
  PetscMPIInt rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

bool any_process(bool flag) {
  ensure_petsc();
  int mine = flag ? 1 : 0, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  return any != 0;
}

std::vector<double> gather_all(double value) {
  ensure_petsc();
  std::vector<double> all(process_count());
  MPI_Allgather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, PETSC_COMM_WORLD);
  return all;
}

struct LinearSolver::Impl {
  SparsePattern pattern;
  int block_size = 1;
  Mat matrix = nullptr;
  Vec rhs = nullptr, solution = nullptr;
  KSP ksp = nullptr;
  IS velocity = nullptr, pressure = nullptr;
  bool distributed = false;
  std::vector<PetscInt> starts, columns;  // the MPI matrix's CSR, kept for its updates
  int nonzeros = 0;
  std::vector<PetscScalar> buffer;  // MPI: the values between begin_assembly and the solve
  PetscScalar* assembling = nullptr;  // one process: PETSc's array while it is out
  VecScatter gather = nullptr;            // the distributed solution to every process
  Vec whole = nullptr;
  bool reuse = false;
  int built_iterations = -1;  // iterations of the last solve that built the preconditioner; -1: build next
  int last_iterations = 0;

  ~Impl() {
    if (gather) VecScatterDestroy(&gather);
    if (whole) VecDestroy(&whole);
    if (velocity) ISDestroy(&velocity);
    if (pressure) ISDestroy(&pressure);
    if (ksp) KSPDestroy(&ksp);
    if (rhs) VecDestroy(&rhs);
    if (solution) VecDestroy(&solution);
    if (matrix) MatDestroy(&matrix);
  }
};

LinearSolver::LinearSolver(SparsePattern pattern, int block_size, const std::string& defaults,
                           const std::string& options)
    : impl_(std::make_unique<Impl>()) {
  ensure_petsc();
  Impl& s = *impl_;
  s.pattern = std::move(pattern);
  s.block_size = block_size;
  const PetscInt n = s.pattern.rows;
  VM_CHECK(static_cast<int>(s.pattern.row_start.size()) == n + 1, "pattern row offsets");
  VM_CHECK(block_size >= 1 && n % block_size == 0, "rows are not whole blocks");

  // The options database holds this solver's options only: defaults, then the caller's.
  check(PetscOptionsClear(nullptr), "clearing options");
  check(PetscOptionsInsertString(nullptr, defaults.c_str()), "default options");
  if (PetscOptionsInsertString(nullptr, options.c_str()) != 0) {
    petsc_message.clear();
    throw OptionError(fmt::format("PETSc cannot read the solver options \"{}\"", options));
  }

  const PetscInt N = s.pattern.total_rows();
  s.distributed = process_count() > 1;
  const MPI_Comm comm = s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
  s.starts.assign(s.pattern.row_start.begin(), s.pattern.row_start.end());
  s.columns.assign(s.pattern.columns.begin(), s.pattern.columns.end());
  if (s.distributed) {
    std::vector<PetscScalar> zeros(s.columns.size(), 0.0);
    check(MatCreateMPIAIJWithArrays(comm, n, n, N, N, s.starts.data(), s.columns.data(), zeros.data(), &s.matrix),
          "MatCreateMPIAIJWithArrays");
    check(MatSetBlockSize(s.matrix, block_size), "MatSetBlockSize");
  } else {
    VM_CHECK(N == n && s.pattern.first_row == 0, "one process holds every row");
    check(MatCreate(comm, &s.matrix), "MatCreate");
    check(MatSetSizes(s.matrix, n, n, n, n), "MatSetSizes");
    check(MatSetType(s.matrix, MATSEQAIJ), "MatSetType");
    check(MatSetBlockSize(s.matrix, block_size), "MatSetBlockSize");
    check(MatSeqAIJSetPreallocationCSR(s.matrix, s.starts.data(), s.columns.data(), nullptr), "preallocation");
    std::vector<PetscInt>().swap(s.starts);  // the matrix has its own copy
    std::vector<PetscInt>().swap(s.columns);
  }
  // The pattern's columns are the matrix's (and, distributed, `columns`): kept once.
  s.nonzeros = s.pattern.nonzeros();
  std::vector<int>().swap(s.pattern.columns);
  check(MatSetOption(s.matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  check(MatCreateVecs(s.matrix, &s.solution, &s.rhs), "MatCreateVecs");
  if (s.distributed) check(VecScatterCreateToAll(s.solution, &s.gather, &s.whole), "VecScatterCreateToAll");

  check(KSPCreate(comm, &s.ksp), "KSPCreate");
  check(KSPSetOperators(s.ksp, s.matrix, s.matrix), "KSPSetOperators");
  check(KSPSetInitialGuessNonzero(s.ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
  if (KSPSetFromOptions(s.ksp) != 0) {
    const std::string why = petsc_message;
    petsc_message.clear();
    throw OptionError(fmt::format("PETSc refused the solver options: {}", why));
  }
  PC pc = nullptr;
  check(KSPGetPC(s.ksp, &pc), "KSPGetPC");
  PetscBool split = PETSC_FALSE;
  check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &split), "PC type");
  if (split && block_size > 1) {
    std::vector<PetscInt> u, p;
    for (PetscInt i = s.pattern.first_row; i < s.pattern.first_row + n; ++i)
      (i % block_size == block_size - 1 ? p : u).push_back(i);
    check(ISCreateGeneral(comm, static_cast<PetscInt>(u.size()), u.data(), PETSC_COPY_VALUES, &s.velocity), "IS");
    check(ISCreateGeneral(comm, static_cast<PetscInt>(p.size()), p.data(), PETSC_COPY_VALUES, &s.pressure), "IS");
    check(PCFieldSplitSetIS(pc, "u", s.velocity), "PCFieldSplitSetIS");
    check(PCFieldSplitSetIS(pc, "p", s.pressure), "PCFieldSplitSetIS");
  }
}

LinearSolver::~LinearSolver() = default;

const SparsePattern& LinearSolver::pattern() const { return impl_->pattern; }

SolveStats LinearSolver::solve(const std::vector<double>& values, const std::vector<double>& rhs,
                               std::vector<double>& x) {
  VM_CHECK(static_cast<int>(values.size()) == impl_->nonzeros, "matrix values do not match the pattern");
  std::memcpy(begin_assembly(), values.data(), values.size() * sizeof(double));
  end_assembly();
  return solve_assembled(rhs, x);
}

double* LinearSolver::begin_assembly() {
  Impl& s = *impl_;
  VM_CHECK(!s.assembling, "begin_assembly twice");
  if (s.distributed) {
    s.buffer.assign(s.nonzeros, 0.0);
    return s.buffer.data();
  }
  check(MatSeqAIJGetArray(s.matrix, &s.assembling), "MatSeqAIJGetArray");
  std::fill(s.assembling, s.assembling + s.nonzeros, 0.0);
  return s.assembling;
}

void LinearSolver::end_assembly() {
  Impl& s = *impl_;
  if (s.distributed) {
    const PetscInt n = s.pattern.rows, N = s.pattern.total_rows();
    check(MatUpdateMPIAIJWithArrays(s.matrix, n, n, N, N, s.starts.data(), s.columns.data(), s.buffer.data()),
          "MatUpdateMPIAIJWithArrays");
    std::vector<PetscScalar>().swap(s.buffer);
    return;
  }
  VM_CHECK(s.assembling, "end_assembly without begin_assembly");
  check(MatSeqAIJRestoreArray(s.matrix, &s.assembling), "MatSeqAIJRestoreArray");
  s.assembling = nullptr;
}

SolveStats LinearSolver::solve_assembled(const std::vector<double>& rhs, std::vector<double>& x) {
  Impl& s = *impl_;
  const int n = s.pattern.rows;
  const int first = s.pattern.first_row, total = s.pattern.total_rows();
  VM_CHECK(!s.assembling, "solve_assembled before end_assembly");
  VM_CHECK(static_cast<int>(rhs.size()) == n && static_cast<int>(x.size()) == total, "vector sizes");

  PetscScalar* v = nullptr;
  check(VecGetArray(s.rhs, &v), "VecGetArray");
  std::memcpy(v, rhs.data(), rhs.size() * sizeof(double));
  check(VecRestoreArray(s.rhs, &v), "VecRestoreArray");
  check(VecGetArray(s.solution, &v), "VecGetArray");
  std::memcpy(v, x.data() + first, static_cast<size_t>(n) * sizeof(double));
  check(VecRestoreArray(s.solution, &v), "VecRestoreArray");

  // Reuse the preconditioner while the solve before did not take much more than the one
  // that built it; cap the reusing solve at twice that, and repeat it with a new preconditioner
  // if it fails.
  const int reuse_limit =
      static_cast<int>(kReuseGrowth * std::max(s.built_iterations, 0)) + kReuseSlack;
  const bool reuse = s.reuse && s.built_iterations >= 0 && s.last_iterations <= reuse_limit;
  PetscReal rtol = 0, abstol = 0, dtol = 0;
  PetscInt max_it = 0;
  check(KSPGetTolerances(s.ksp, &rtol, &abstol, &dtol, &max_it), "KSPGetTolerances");
  check(KSPSetReusePreconditioner(s.ksp, reuse ? PETSC_TRUE : PETSC_FALSE), "KSPSetReusePreconditioner");
  if (reuse)
    check(KSPSetTolerances(s.ksp, rtol, abstol, dtol, std::min<PetscInt>(max_it, 2 * reuse_limit)), "KSPSetTolerances");
  check(KSPSolve(s.ksp, s.rhs, s.solution), "KSPSolve");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(s.ksp, &reason), "KSPGetConvergedReason");
  bool built = !reuse;
  PetscInt failed_iterations = 0;  // of a capped solve that did not converge
  if (reuse) {
    check(KSPSetTolerances(s.ksp, rtol, abstol, dtol, max_it), "KSPSetTolerances");
    if (reason <= 0) {  // the old preconditioner no longer serves: start again with a new one
      check(KSPGetIterationNumber(s.ksp, &failed_iterations), "KSPGetIterationNumber");
      check(VecGetArray(s.solution, &v), "VecGetArray");
      std::memcpy(v, x.data() + first, static_cast<size_t>(n) * sizeof(double));
      check(VecRestoreArray(s.solution, &v), "VecRestoreArray");
      check(KSPSetReusePreconditioner(s.ksp, PETSC_FALSE), "KSPSetReusePreconditioner");
      check(KSPSolve(s.ksp, s.rhs, s.solution), "KSPSolve");
      built = true;
    }
  }

  Vec result = s.solution;
  if (s.distributed) {
    check(VecScatterBegin(s.gather, s.solution, s.whole, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    check(VecScatterEnd(s.gather, s.solution, s.whole, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    result = s.whole;
  }
  const PetscScalar* r = nullptr;
  check(VecGetArrayRead(result, &r), "VecGetArrayRead");
  std::memcpy(x.data(), r, x.size() * sizeof(double));
  check(VecRestoreArrayRead(result, &r), "VecRestoreArrayRead");

  SolveStats stats;
  PetscInt iterations = 0;
  PetscReal norm = 0.0;
  check(KSPGetIterationNumber(s.ksp, &iterations), "KSPGetIterationNumber");
  check(KSPGetResidualNorm(s.ksp, &norm), "KSPGetResidualNorm");
  check(KSPGetConvergedReason(s.ksp, &reason), "KSPGetConvergedReason");
  stats.iterations = static_cast<int>(iterations + failed_iterations);
  stats.residual_norm = norm;
  stats.converged = reason > 0;
  stats.reason = KSPConvergedReasons[reason];
  stats.preconditioner_built = built;
  if (built) s.built_iterations = static_cast<int>(iterations);
  s.last_iterations = static_cast<int>(iterations);
  return stats;
}

void LinearSolver::reuse_preconditioner(bool on) { impl_->reuse = on; }

void LinearSolver::rebuild_preconditioner() { impl_->built_iterations = -1; }

std::string LinearSolver::description() const {
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  PC pc = nullptr;
  KSPGetType(impl_->ksp, &ksp_type);
  KSPGetPC(impl_->ksp, &pc);
  PCGetType(pc, &pc_type);
  return fmt::format("{} + {}", ksp_type ? ksp_type : "?", pc_type ? pc_type : "?");
}

}  // namespace vesselmesh::flow
