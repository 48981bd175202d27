#include "flow/linear_solver.h"

#include "mesh/error.h"

#include <fmt/format.h>
#include <petscksp.h>
// After PETSc's headers (scotch.h needs <cstdio> and <cstdint>, which they bring).
#include <scotch.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>

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

std::vector<double> sum_all(std::vector<double> values) {
  ensure_petsc();
  if (process_count() > 1)
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                  PETSC_COMM_WORLD);
  return values;
}

std::vector<double> gather_to_first(const std::vector<double>& values) {
  ensure_petsc();
  const int ranks = process_count(), rank = process_rank();
  if (ranks == 1) return values;
  const int mine = static_cast<int>(values.size());
  std::vector<int> counts(ranks), offsets(ranks, 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, PETSC_COMM_WORLD);
  std::vector<double> all;
  if (rank == 0) {
    for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
    all.resize(static_cast<size_t>(offsets[ranks - 1]) + counts[ranks - 1]);
  }
  MPI_Gatherv(values.data(), mine, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0,
              PETSC_COMM_WORLD);
  return all;
}

std::vector<int> partition_graph(const std::vector<int>& start, const std::vector<int>& neighbours, int parts) {
  ensure_petsc();
  const int total = static_cast<int>(start.size()) - 1;
  VM_CHECK(total >= 0 && parts >= 1, "a graph and a part count");
  std::vector<int> owner_of(total, 0);
  if (parts == 1 || total == 0) return owner_of;
  // PT-Scotch on this one process. Debian's Scotch seeds from the clock and runs threads that race
  // (the same graph cut apart differently from run to run): one thread, a fixed seed.
  setenv("SCOTCH_PTHREAD_NUMBER", "1", 1);
  SCOTCH_randomSeed(1);
  SCOTCH_randomReset();
  // The adjacency without its diagonal, in arrays PETSc frees with the matrix.
  PetscInt *ia = nullptr, *ja = nullptr;
  check(PetscMalloc1(total + 1, &ia), "PetscMalloc1");
  check(PetscMalloc1(std::max<size_t>(neighbours.size(), 1), &ja), "PetscMalloc1");
  ia[0] = 0;
  for (int r = 0; r < total; ++r) {
    ia[r + 1] = ia[r];
    for (int k = start[r]; k < start[r + 1]; ++k)
      if (neighbours[k] != r) ja[ia[r + 1]++] = neighbours[k];
  }
  Mat adjacency = nullptr;
  check(MatCreateMPIAdj(PETSC_COMM_SELF, total, total, ia, ja, nullptr, &adjacency), "MatCreateMPIAdj");
  MatPartitioning partitioning = nullptr;
  IS owners = nullptr;
  check(MatPartitioningCreate(PETSC_COMM_SELF, &partitioning), "MatPartitioningCreate");
  check(MatPartitioningSetAdjacency(partitioning, adjacency), "MatPartitioningSetAdjacency");
  check(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH), "MatPartitioningSetType (PT-Scotch)");
  check(MatPartitioningSetNParts(partitioning, parts), "MatPartitioningSetNParts");
  check(MatPartitioningApply(partitioning, &owners), "MatPartitioningApply (PT-Scotch)");
  const PetscInt* owner = nullptr;
  check(ISGetIndices(owners, &owner), "ISGetIndices");
  std::copy(owner, owner + total, owner_of.begin());
  check(ISRestoreIndices(owners, &owner), "ISRestoreIndices");
  ISDestroy(&owners);
  MatPartitioningDestroy(&partitioning);
  MatDestroy(&adjacency);
  return owner_of;
}

std::string scatter_from_first(const std::function<std::string(int rank)>& make) {
  ensure_petsc();
  const int ranks = process_count(), rank = process_rank();
  constexpr size_t kChunk = size_t{1} << 30;  // MPI counts are ints: a part goes in pieces of 1 GiB
  std::string mine;
  if (rank == 0) {
    for (int r = 1; r < ranks; ++r) {
      const std::string bytes = make(r);
      const uint64_t size = bytes.size();
      MPI_Send(&size, 1, MPI_UINT64_T, r, 0, PETSC_COMM_WORLD);
      for (size_t at = 0; at < bytes.size(); at += kChunk)
        MPI_Send(bytes.data() + at, static_cast<int>(std::min(kChunk, bytes.size() - at)), MPI_CHAR, r, 1,
                 PETSC_COMM_WORLD);
    }
    return mine;
  }
  uint64_t size = 0;
  MPI_Recv(&size, 1, MPI_UINT64_T, 0, 0, PETSC_COMM_WORLD, MPI_STATUS_IGNORE);
  mine.resize(size);
  for (size_t at = 0; at < mine.size(); at += kChunk)
    MPI_Recv(mine.data() + at, static_cast<int>(std::min(kChunk, mine.size() - at)), MPI_CHAR, 0, 1, PETSC_COMM_WORLD,
             MPI_STATUS_IGNORE);
  return mine;
}

void abort_all(int code) {
  ensure_petsc();
  std::fflush(stderr);
  MPI_Abort(PETSC_COMM_WORLD, code);
  std::abort();  // MPI_Abort does not return
}

struct LinearSolver::Impl {
  SparsePattern pattern;
  int block_size = 1;
  Mat matrix = nullptr;
  Vec rhs = nullptr, solution = nullptr;
  KSP ksp = nullptr;
  KSP direct = nullptr;  // solve_assembled_direct's, made when first needed
  IS velocity = nullptr, pressure = nullptr;
  bool distributed = false;
  int nonzeros = 0;
  // MPI: the blocks of the process's rows in its own and in the others' columns (PETSc's), and
  // per row where its own columns begin in it and how many there are.
  Mat own_block = nullptr, other_block = nullptr;
  int own_nonzeros = 0;
  std::vector<int> own_begin, own_count;
  MatrixValues assembling;  // PETSc's arrays while they are out
  VecScatter ghosts = nullptr;  // MPI: the solution's ghost rows to this process
  Vec ghost_values = nullptr;
  bool reuse = false;
  int built_iterations = -1;  // iterations of the last solve that built the preconditioner; -1: build next
  int last_iterations = 0;
  // The assembled system's right-hand side and x's own rows into PETSc's vectors, checked: the
  // opening of every use of the assembled matrix (`what` names it).
  void load(const std::vector<double>& b, const std::vector<double>& x, const char* what);
  double residual_floor = 0.0;  // set_residual_floor's, times ||b||, is the least absolute tolerance
  double tolerance_factor = 1.0;  // scale_tolerance's
  double user_rtol = -1.0, user_abstol = -1.0;  // the options' tolerances (-1: not read yet)

  // The solution's own rows into x, and under MPI its ghost rows from the processes owning them.
  void copy_out(std::vector<double>& x) {
    Impl& s = *this;
    const int n = s.pattern.rows;
    const PetscScalar* r = nullptr;
    check(VecGetArrayRead(s.solution, &r), "VecGetArrayRead");
    std::memcpy(x.data(), r, static_cast<size_t>(n) * sizeof(double));
    check(VecRestoreArrayRead(s.solution, &r), "VecRestoreArrayRead");
    if (s.distributed) {  // the ghosts' values from the processes that own them
      check(VecScatterBegin(s.ghosts, s.solution, s.ghost_values, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
      check(VecScatterEnd(s.ghosts, s.solution, s.ghost_values, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
      check(VecGetArrayRead(s.ghost_values, &r), "VecGetArrayRead");
      std::memcpy(x.data() + n, r, s.pattern.ghost_rows.size() * sizeof(double));
      check(VecRestoreArrayRead(s.ghost_values, &r), "VecRestoreArrayRead");
    }
  }

  ~Impl() {
    if (ghosts) VecScatterDestroy(&ghosts);
    if (ghost_values) VecDestroy(&ghost_values);
    if (velocity) ISDestroy(&velocity);
    if (pressure) ISDestroy(&pressure);
    if (ksp) KSPDestroy(&ksp);
    if (direct) KSPDestroy(&direct);
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
  // The defaults' preconditioning side goes with their Krylov method: a caller's -ksp_type without
  // -ksp_pc_side takes its method's own (CG refuses the right side).
  std::string base = defaults;
  const std::string side = "-ksp_pc_side right";
  if (options.find("-ksp_type") != std::string::npos && options.find("-ksp_pc_side") == std::string::npos &&
      base.find(side) != std::string::npos)
    base.erase(base.find(side), side.size());
  check(PetscOptionsInsertString(nullptr, base.c_str()), "default options");
  if (PetscOptionsInsertString(nullptr, options.c_str()) != 0) {
    petsc_message.clear();
    throw OptionError(fmt::format("PETSc cannot read the solver options \"{}\"", options));
  }

  const PetscInt N = s.pattern.total_rows();
  s.distributed = process_count() > 1;
  const MPI_Comm comm = s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
  VM_CHECK(s.distributed || (N == n && s.pattern.first_row == 0), "one process holds every row");
  check(MatCreate(comm, &s.matrix), "MatCreate");
  check(MatSetSizes(s.matrix, n, n, N, N), "MatSetSizes");
  check(MatSetType(s.matrix, s.distributed ? MATMPIAIJ : MATSEQAIJ), "MatSetType");
  check(MatSetBlockSize(s.matrix, block_size), "MatSetBlockSize");
  static_assert(std::is_same_v<PetscInt, int>, "PETSc with 32-bit indices, as the pattern's");
  if (s.distributed)
    check(MatMPIAIJSetPreallocationCSR(s.matrix, s.pattern.row_start.data(), s.pattern.columns.data(), nullptr),
          "preallocation");
  else
    check(MatSeqAIJSetPreallocationCSR(s.matrix, s.pattern.row_start.data(), s.pattern.columns.data(), nullptr),
          "preallocation");
  if (s.distributed) {
    // Each row's own columns (sorted, consecutive in it) and PETSc's two blocks of them.
    const int first = s.pattern.first_row;
    s.own_begin.resize(n);
    s.own_count.resize(n);
    for (int r = 0; r < n; ++r) {
      const auto row = s.pattern.columns.begin() + s.pattern.row_start[r],
                 end = s.pattern.columns.begin() + s.pattern.row_start[r + 1];
      const auto begin_own = std::lower_bound(row, end, first), end_own = std::lower_bound(row, end, first + n);
      s.own_begin[r] = static_cast<int>(begin_own - row);
      s.own_count[r] = static_cast<int>(end_own - begin_own);
      s.own_nonzeros += s.own_count[r];
    }
    check(MatMPIAIJGetSeqAIJ(s.matrix, &s.own_block, &s.other_block, nullptr), "MatMPIAIJGetSeqAIJ");
    MatInfo own{}, other{};
    check(MatGetInfo(s.own_block, MAT_LOCAL, &own), "MatGetInfo");
    check(MatGetInfo(s.other_block, MAT_LOCAL, &other), "MatGetInfo");
    VM_CHECK(static_cast<int>(own.nz_used) == s.own_nonzeros &&
                 static_cast<int>(other.nz_used) == s.pattern.nonzeros() - s.own_nonzeros,
             "PETSc's blocks are the pattern's");
  }
  // The pattern's columns are the matrix's: kept once.
  s.nonzeros = s.pattern.nonzeros();
  std::vector<int>().swap(s.pattern.columns);
  check(MatSetOption(s.matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  check(MatCreateVecs(s.matrix, &s.solution, &s.rhs), "MatCreateVecs");
  if (s.distributed) {
    const std::vector<int>& rows = s.pattern.ghost_rows;  // PetscInt is int (asserted above)
    IS wanted = nullptr;
    check(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(rows.size()), rows.data(), PETSC_COPY_VALUES, &wanted),
          "ISCreateGeneral");
    check(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(rows.size()), &s.ghost_values), "VecCreateSeq");
    const PetscErrorCode code = VecScatterCreate(s.solution, wanted, s.ghost_values, nullptr, &s.ghosts);
    ISDestroy(&wanted);
    check(code, "VecScatterCreate (ghost rows)");
  } else {
    VM_CHECK(s.pattern.ghost_rows.empty(), "ghost rows on one process");
  }

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
  const Impl& s = *impl_;
  VM_CHECK(static_cast<int>(values.size()) == s.nonzeros, "matrix values do not match the pattern");
  const MatrixValues m = begin_assembly();
  if (!s.distributed) {
    std::copy(values.begin(), values.end(), m.own);
  } else {
    double *own = m.own, *other = m.other;
    for (int r = 0; r < s.pattern.rows; ++r) {
      const double* row = values.data() + s.pattern.row_start[r];
      const int length = s.pattern.row_start[r + 1] - s.pattern.row_start[r];
      other = std::copy(row, row + s.own_begin[r], other);
      own = std::copy(row + s.own_begin[r], row + s.own_begin[r] + s.own_count[r], own);
      other = std::copy(row + s.own_begin[r] + s.own_count[r], row + length, other);
    }
  }
  end_assembly();
  return solve_assembled(rhs, x);
}

MatrixValues LinearSolver::begin_assembly() {
  Impl& s = *impl_;
  VM_CHECK(!s.assembling.own, "begin_assembly twice");
  if (s.distributed) {
    check(MatSeqAIJGetArray(s.own_block, &s.assembling.own), "MatSeqAIJGetArray");
    check(MatSeqAIJGetArray(s.other_block, &s.assembling.other), "MatSeqAIJGetArray");
    std::fill(s.assembling.own, s.assembling.own + s.own_nonzeros, 0.0);
    std::fill(s.assembling.other, s.assembling.other + (s.nonzeros - s.own_nonzeros), 0.0);
  } else {
    check(MatSeqAIJGetArray(s.matrix, &s.assembling.own), "MatSeqAIJGetArray");
    std::fill(s.assembling.own, s.assembling.own + s.nonzeros, 0.0);
  }
  return s.assembling;
}

void LinearSolver::end_assembly() {
  Impl& s = *impl_;
  VM_CHECK(s.assembling.own, "end_assembly without begin_assembly");
  if (s.distributed) {
    check(MatSeqAIJRestoreArray(s.own_block, &s.assembling.own), "MatSeqAIJRestoreArray");
    check(MatSeqAIJRestoreArray(s.other_block, &s.assembling.other), "MatSeqAIJRestoreArray");
    // The whole matrix changed (its preconditioner and field split see it by its state): an
    // assembly with nothing to send says so.
    check(MatAssemblyBegin(s.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(s.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  } else {
    check(MatSeqAIJRestoreArray(s.matrix, &s.assembling.own), "MatSeqAIJRestoreArray");
  }
  s.assembling = MatrixValues{};
}

namespace {

// `rhs` and the initial guess (x's own rows) into PETSc's vectors.
void copy_in(Vec rhs_vec, Vec solution, const std::vector<double>& rhs, const std::vector<double>& x, int n) {
  PetscScalar* v = nullptr;
  check(VecGetArray(rhs_vec, &v), "VecGetArray");
  std::memcpy(v, rhs.data(), rhs.size() * sizeof(double));
  check(VecRestoreArray(rhs_vec, &v), "VecRestoreArray");
  check(VecGetArray(solution, &v), "VecGetArray");
  std::memcpy(v, x.data(), static_cast<size_t>(n) * sizeof(double));
  check(VecRestoreArray(solution, &v), "VecRestoreArray");
}

}  // namespace

void LinearSolver::Impl::load(const std::vector<double>& b, const std::vector<double>& x, const char* what) {
  const int n = pattern.rows;
  VM_CHECK(!assembling.own, std::string(what) + " before end_assembly");
  VM_CHECK(static_cast<int>(b.size()) == n && x.size() >= static_cast<size_t>(n), "vector sizes");
  copy_in(rhs, solution, b, x, n);
}

SolveStats LinearSolver::solve_assembled_direct(const std::vector<double>& rhs, std::vector<double>& x) {
  Impl& s = *impl_;
  const int n = s.pattern.rows;
  VM_CHECK(x.size() == n + s.pattern.ghost_rows.size(), "the solution's size: own and ghost rows");
  s.load(rhs, x, "solve_assembled_direct");
  if (!s.direct) {  // kept: the next solves reuse its symbolic factorization (the same pattern)
    check(KSPCreate(s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF, &s.direct), "KSPCreate");
    PC pc = nullptr;
    check(KSPSetType(s.direct, KSPPREONLY), "KSPSetType");
    check(KSPGetPC(s.direct, &pc), "KSPGetPC");
    check(PCSetType(pc, PCLU), "PCSetType");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  }
  check(KSPSetOperators(s.direct, s.matrix, s.matrix), "KSPSetOperators");
  check(KSPSolve(s.direct, s.rhs, s.solution), "KSPSolve (MUMPS)");
  KSPConvergedReason reason = KSP_DIVERGED_PC_FAILED;
  check(KSPGetConvergedReason(s.direct, &reason), "KSPGetConvergedReason");
  s.copy_out(x);
  SolveStats stats;
  stats.iterations = 1;
  stats.converged = reason > 0;
  stats.reason = KSPConvergedReasons[reason];
  s.built_iterations = -1;  // the iterative solver's preconditioner is built anew next time
  return stats;
}

double LinearSolver::relative_residual(const std::vector<double>& rhs, const std::vector<double>& x) {
  Impl& s = *impl_;
  s.load(rhs, x, "relative_residual");
  Vec r = nullptr;
  check(VecDuplicate(s.rhs, &r), "VecDuplicate");
  check(MatMult(s.matrix, s.solution, r), "MatMult");
  check(VecAXPY(r, -1.0, s.rhs), "VecAXPY");
  PetscReal residual = 0.0, scale = 0.0;
  check(VecNorm(r, NORM_2, &residual), "VecNorm");
  check(VecNorm(s.rhs, NORM_2, &scale), "VecNorm");
  VecDestroy(&r);
  return scale > 0.0 ? residual / scale : residual;
}

SolveStats LinearSolver::solve_assembled(const std::vector<double>& rhs, std::vector<double>& x) {
  Impl& s = *impl_;
  const int n = s.pattern.rows;
  VM_CHECK(x.size() == n + s.pattern.ghost_rows.size(), "the solution's size: own and ghost rows");
  s.load(rhs, x, "solve_assembled");
  PetscScalar* v = nullptr;

  // Reuse the preconditioner while the solve before did not take much more than the one
  // that built it; cap the reusing solve at twice that, and repeat it with a new preconditioner
  // if it fails.
  const int reuse_limit =
      static_cast<int>(kReuseGrowth * std::max(s.built_iterations, 0)) + kReuseSlack;
  const bool reuse = s.reuse && s.built_iterations >= 0 && s.last_iterations <= reuse_limit;
  PetscReal rtol = 0, abstol = 0, dtol = 0;
  PetscInt max_it = 0;
  check(KSPGetTolerances(s.ksp, &rtol, &abstol, &dtol, &max_it), "KSPGetTolerances");
  if (s.user_abstol < 0.0) s.user_abstol = abstol, s.user_rtol = rtol;
  if (s.residual_floor > 0.0 || s.tolerance_factor != 1.0) {
    rtol = s.user_rtol * s.tolerance_factor;
    if (s.residual_floor > 0.0) {  // done at once when the residual is already under the floor
      PetscReal b = 0.0;
      check(VecNorm(s.rhs, NORM_2, &b), "VecNorm");
      abstol = std::max<PetscReal>(s.user_abstol, s.residual_floor * b);
    }
    check(KSPSetTolerances(s.ksp, rtol, abstol, dtol, max_it), "KSPSetTolerances");
  }
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
      std::memcpy(v, x.data(), static_cast<size_t>(n) * sizeof(double));
      check(VecRestoreArray(s.solution, &v), "VecRestoreArray");
      check(KSPSetReusePreconditioner(s.ksp, PETSC_FALSE), "KSPSetReusePreconditioner");
      check(KSPSolve(s.ksp, s.rhs, s.solution), "KSPSolve");
      built = true;
    }
  }

  s.copy_out(x);

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

void LinearSolver::set_residual_floor(double relative) { impl_->residual_floor = relative; }
void LinearSolver::scale_tolerance(double factor) { impl_->tolerance_factor = factor; }

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
