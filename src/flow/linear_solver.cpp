#include "flow/linear_solver.h"

#include "parallel/petsc_start.h"
#include "parallel/processes.h"

#include "mesh/error.h"

#include <fmt/format.h>
#include <petscksp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <tuple>
#include <type_traits>

namespace vesselmesh::flow {
namespace {

void check(PetscErrorCode code, const char* what) { parallel::check_petsc(code, what); }

// Whether a PETSc object (a PC, a Mat) is of the type named.
template <typename Object>
bool of_type(Object object, const char* type) {
  PetscBool same = PETSC_FALSE;
  check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(object), type, &same), "PetscObjectTypeCompare");
  return same == PETSC_TRUE;
}

void ensure_petsc() { parallel::ensure_petsc(); }

// Whether the next solve keeps its preconditioner: the Krylov method's, and that of each solver
// nested in a field split (its velocity block's and its Schur complement's), whose own matrices
// changed with the assembly too: reuse on the outer solver alone left PETSc building those anew
// at every solve (hypre's AMG of the Schur complement's matrix a fifth of a time step's cost at
// 420k unknowns). `built`: a solve has set the preconditioner up (before, nothing nested exists).
void set_reuse(KSP ksp, bool reuse, bool built) {
  const PetscBool flag = reuse ? PETSC_TRUE : PETSC_FALSE;
  check(KSPSetReusePreconditioner(ksp, flag), "KSPSetReusePreconditioner");
  PC pc = nullptr;
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  if (!of_type(pc, PCFIELDSPLIT) || !built) return;
  PetscInt count = 0;
  KSP* inner = nullptr;
  check(PCFieldSplitGetSubKSP(pc, &count, &inner), "PCFieldSplitGetSubKSP");
  for (PetscInt k = 0; k < count; ++k) check(KSPSetReusePreconditioner(inner[k], flag), "KSPSetReusePreconditioner");
  PetscFree(inner);
}
}  // namespace


struct LinearSolver::Impl {
  SparsePattern pattern;  // of points; its columns handed to PETSc's matrix, not kept twice
  int block_size = 1;
  int rows = 0;  // this process's rows of unknowns: block_size x its points
  Mat matrix = nullptr;
  Vec rhs = nullptr, solution = nullptr;
  KSP ksp = nullptr;
  KSP direct = nullptr;  // solve_assembled_direct's, made when first needed
  Mat converted = nullptr;  // a field split's matrix as one, for the direct solver (made when needed)
  IS velocity = nullptr, pressure = nullptr;  // one matrix under a field split: the fields' rows
  bool distributed = false;
  // A field split (MatrixValues::split): `matrix` is PETSc's nest of `blocks`, and PETSc's vectors
  // hold a process's rows field after field (its points' first block_size - 1 components, then
  // their last), which load and copy_out translate from and to the interleaved rows.
  bool split = false;
  Mat blocks[2][2] = {};
  // Per point row: its own (the process's) column points' first position in it and their count,
  // and the counts in the rows before it (own, others').
  std::vector<int> own_begin, own_count, own_before, other_before;
  // The parts PETSc holds the values in: per matrix (one, or the split's four) its own and
  // others' column blocks (the matrix itself on one process).
  Mat own_part[2][2] = {}, other_part[2][2] = {};
  // The Schur complement's preconditioning matrix of the caller's (MatrixValues::schur_own), in
  // block [1][1]'s pattern, and its own and others' parts; null unless the options ask for it.
  Mat schur = nullptr, schur_own = nullptr, schur_other = nullptr;
  bool user_schur = false;  // -pc_fieldsplit_schur_precondition user
  MatrixValues assembling;  // PETSc's arrays while they are out
  bool out = false;         // between begin_assembly and end_assembly
  VecScatter ghosts = nullptr;  // MPI: the solution's ghost rows to this process
  Vec ghost_values = nullptr;
  bool reuse = false;
  // The fewest iterations of a solve with the current preconditioner (its building solve's or a later one's);
  // -1: build it next.
  int least_iterations = -1;
  bool solved = false;  // the iterative solver has solved (its preconditioner set up) once
  int last_iterations = 0;
  // The assembled system's right-hand side and x's own rows into PETSc's vectors, checked: the
  // opening of every use of the assembled matrix (`what` names it).
  void load(const std::vector<double>& b, const std::vector<double>& x, const char* what);
  double residual_floor = 0.0;  // set_residual_floor's, times ||b||, is the least absolute tolerance
  bool check_residual = false;  // set_residual_check's
  PetscReal residual_norm() const;  // ||b - A x|| of the loaded b and x, A the whole operator
  double tolerance_factor = 1.0;  // scale_tolerance's
  double user_rtol = -1.0, user_abstol = -1.0;  // the options' tolerances (-1: not read yet)
  // The low-rank term (set_low_rank_columns): its columns in PETSc's layout, their coefficients,
  // and the whole operator A + U C U^T as a shell matrix (null without columns).
  std::vector<Vec> low_rank;
  std::vector<PetscScalar> low_rank_c;
  Mat whole = nullptr;
  // keep_solutions: the last solutions (newest first, at most keep_count), and the work vectors of
  // the initial guess's projection on them (their products with A, the caller's guess).
  int keep_count = 0;
  std::vector<Vec> kept, products;
  Vec projected = nullptr;  // the last solve's start where project_guess made it (one of `products`), else null
  void project_guess(double rtol);  // the loaded initial guess replaced by its least-residual combination
  void keep_solution();
  void forget_solutions();
  // The operator the Krylov methods and the residual apply: the shell, or the matrix.
  Mat op() const { return whole ? whole : matrix; }
  static PetscErrorCode low_rank_product(Mat shell, Vec x, Vec y);

  // A process's row of unknowns (point a's component i, interleaved) in PETSc's vectors.
  int petsc_row(int row) const {
    if (!split) return row;
    const int a = row / block_size, i = row % block_size, c = block_size - 1;
    return i < c ? c * a + i : c * pattern.rows + a;
  }
  void make_matrix(MPI_Comm comm);
  void make_ghost_scatter();
  // The solution's own rows into x, and under MPI its ghost rows from the processes owning them.
  void copy_out(std::vector<double>& x);

  ~Impl() {
    if (ghosts) VecScatterDestroy(&ghosts);
    if (ghost_values) VecDestroy(&ghost_values);
    if (velocity) ISDestroy(&velocity);
    if (pressure) ISDestroy(&pressure);
    if (ksp) KSPDestroy(&ksp);
    if (direct) KSPDestroy(&direct);
    if (rhs) VecDestroy(&rhs);
    if (solution) VecDestroy(&solution);
    if (converted) MatDestroy(&converted);
    if (whole) MatDestroy(&whole);
    for (Vec& v : low_rank) VecDestroy(&v);
    forget_solutions();
    if (schur) MatDestroy(&schur);
    if (matrix) MatDestroy(&matrix);
    for (auto& row : blocks)
      for (Mat& block : row)
        if (block) MatDestroy(&block);
  }
};

namespace {

// PETSc's parts are the pattern's: their entries (`per_entry` values each) as many as the
// pattern's, in its order (sorted columns, which entry_place's positions count in).
void check_parts(const SparsePattern& pattern, Mat own, Mat other, long per_entry) {
  long own_entries = 0;
  for (int k = 0; k < pattern.nonzeros(); ++k)
    own_entries += pattern.columns[k] >= pattern.first_row && pattern.columns[k] < pattern.first_row + pattern.rows;
  MatInfo info{};
  check(MatGetInfo(own, MAT_LOCAL, &info), "MatGetInfo");
  VM_CHECK(static_cast<long>(info.nz_used) == per_entry * own_entries, "PETSc's own part");
  if (!other) return;
  check(MatGetInfo(other, MAT_LOCAL, &info), "MatGetInfo");
  VM_CHECK(static_cast<long>(info.nz_used) == per_entry * (pattern.nonzeros() - own_entries),
           "PETSc's part in the others' columns");
}

// One AIJ matrix of `comm` with `rows` x `columns` unknowns a point of this process's rows and of
// the column points, preallocated with the point pattern's entries expanded (rows in each point
// row, columns at each column point), its own and others' parts into `own`, `other`.
Mat expanded_matrix(MPI_Comm comm, bool distributed, const SparsePattern& pattern, int rows, int columns, Mat& own,
                    Mat& other) {
  const int n = pattern.rows, total = pattern.total_rows();
  std::vector<PetscInt> start(static_cast<size_t>(rows) * n + 1, 0), index;
  index.reserve(static_cast<size_t>(rows) * columns * pattern.nonzeros());
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < rows; ++i) {
      for (int k = pattern.row_start[a]; k < pattern.row_start[a + 1]; ++k)
        for (int j = 0; j < columns; ++j) index.push_back(columns * pattern.columns[k] + j);
      start[rows * a + i + 1] = static_cast<PetscInt>(index.size());
    }
  Mat m = nullptr;
  check(MatCreate(comm, &m), "MatCreate");
  check(MatSetSizes(m, rows * n, columns * n, rows * total, columns * total), "MatSetSizes");
  check(MatSetType(m, distributed ? MATMPIAIJ : MATSEQAIJ), "MatSetType");
  check(MatSetBlockSizes(m, rows, columns), "MatSetBlockSizes");
  if (distributed) {
    check(MatMPIAIJSetPreallocationCSR(m, start.data(), index.data(), nullptr), "preallocation");
    check(MatMPIAIJGetSeqAIJ(m, &own, &other, nullptr), "MatMPIAIJGetSeqAIJ");
  } else {
    check(MatSeqAIJSetPreallocationCSR(m, start.data(), index.data(), nullptr), "preallocation");
    own = m;
    other = nullptr;
  }
  check_parts(pattern, own, other, static_cast<long>(rows) * columns);
  check(MatSetOption(m, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  return m;
}

// One BAIJ matrix of `comm` in `bs` x `bs` blocks, one a pattern entry: a block's column index
// kept once (AIJ keeps it for each of its bs x bs entries: 164 -> 115 MB for the velocity block at
// 420k unknowns), its own and others' parts into `own`, `other` (their values block after block,
// each block by columns).
Mat blocked_matrix(MPI_Comm comm, bool distributed, const SparsePattern& pattern, int bs, Mat& own, Mat& other) {
  const int n = pattern.rows;
  const std::vector<PetscInt> start(pattern.row_start.begin(), pattern.row_start.end()),
      index(pattern.columns.begin(), pattern.columns.end());
  Mat m = nullptr;
  check(MatCreate(comm, &m), "MatCreate");
  check(MatSetSizes(m, bs * n, bs * n, bs * pattern.total_rows(), bs * pattern.total_rows()), "MatSetSizes");
  check(MatSetType(m, distributed ? MATMPIBAIJ : MATSEQBAIJ), "MatSetType");
  check(MatSetBlockSize(m, bs), "MatSetBlockSize");
  if (distributed) {
    check(MatMPIBAIJSetPreallocationCSR(m, bs, start.data(), index.data(), nullptr), "preallocation");
    check(MatMPIBAIJGetSeqBAIJ(m, &own, &other, nullptr), "MatMPIBAIJGetSeqBAIJ");
  } else {
    check(MatSeqBAIJSetPreallocationCSR(m, bs, start.data(), index.data(), nullptr), "preallocation");
    own = m;
    other = nullptr;
  }
  check_parts(pattern, own, other, static_cast<long>(bs) * bs);
  check(MatSetOption(m, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  return m;
}

// A part's values (AIJ or BAIJ) out of PETSc and back.
bool blocked(Mat part) { return of_type(part, MATSEQBAIJ); }
void get_values(Mat part, double** values) {
  check(blocked(part) ? MatSeqBAIJGetArray(part, values) : MatSeqAIJGetArray(part, values), "MatSeqAIJGetArray");
}
void restore_values(Mat part, double** values) {
  check(blocked(part) ? MatSeqBAIJRestoreArray(part, values) : MatSeqAIJRestoreArray(part, values),
        "MatSeqAIJRestoreArray");
}

}  // namespace

// y = A x + sum_k c_k u_k (u_k^T x): the low-rank term's operator (set_low_rank_columns).
PetscErrorCode LinearSolver::Impl::low_rank_product(Mat shell, Vec x, Vec y) {
  Impl* s = nullptr;
  PetscCall(MatShellGetContext(shell, &s));
  PetscCall(MatMult(s->matrix, x, y));
  const PetscInt k = static_cast<PetscInt>(s->low_rank.size());
  std::vector<PetscScalar> dots(static_cast<size_t>(k));
  PetscCall(VecMDot(x, k, s->low_rank.data(), dots.data()));
  for (PetscInt j = 0; j < k; ++j) dots[j] *= s->low_rank_c[j];
  PetscCall(VecMAXPY(y, k, dots.data(), s->low_rank.data()));
  return 0;
}

void LinearSolver::Impl::make_matrix(MPI_Comm comm) {
  const int bs = block_size, c = bs - 1;
  if (!split) {
    matrix = expanded_matrix(comm, distributed, pattern, bs, bs, own_part[0][0], other_part[0][0]);
  } else {
    for (int f = 0; f < 2; ++f)
      for (int g = 0; g < 2; ++g)
        blocks[f][g] = f == 0 && g == 0 ? blocked_matrix(comm, distributed, pattern, c, own_part[0][0], other_part[0][0])
                                        : expanded_matrix(comm, distributed, pattern, f ? 1 : c, g ? 1 : c,
                                                          own_part[f][g], other_part[f][g]);
    // The fields' rows in the whole: a process's first c x its points, then its points' last.
    const PetscInt first = bs * pattern.first_row, n = pattern.rows;
    IS fields[2] = {};
    check(ISCreateStride(comm, c * n, first, 1, &fields[0]), "ISCreateStride");
    check(ISCreateStride(comm, n, first + c * n, 1, &fields[1]), "ISCreateStride");
    if (user_schur) schur = expanded_matrix(comm, distributed, pattern, 1, 1, schur_own, schur_other);
    Mat list[4] = {blocks[0][0], blocks[0][1], blocks[1][0], blocks[1][1]};
    const PetscErrorCode code = MatCreateNest(comm, 2, fields, 2, fields, list, &matrix);
    ISDestroy(&fields[0]);
    ISDestroy(&fields[1]);
    check(code, "MatCreateNest");
  }
  // The vectors: PETSc's own kind (a nest's would be split too), in the matrix's rows.
  if (distributed)
    check(VecCreateMPI(comm, rows, bs * pattern.total_rows(), &solution), "VecCreateMPI");
  else
    check(VecCreateSeq(comm, rows, &solution), "VecCreateSeq");
  check(VecDuplicate(solution, &rhs), "VecDuplicate");
}

void LinearSolver::Impl::make_ghost_scatter() {
  // Every process's first point and point count: a ghost point's rows in PETSc's numbering.
  const int ranks = parallel::process_count();
  std::vector<int> first(ranks), count(ranks);
  MPI_Allgather(&pattern.first_row, 1, MPI_INT, first.data(), 1, MPI_INT, PETSC_COMM_WORLD);
  MPI_Allgather(&pattern.rows, 1, MPI_INT, count.data(), 1, MPI_INT, PETSC_COMM_WORLD);
  const int bs = block_size, c = bs - 1;
  std::vector<PetscInt> wanted;
  wanted.reserve(static_cast<size_t>(bs) * pattern.ghost_rows.size());
  for (int g : pattern.ghost_rows) {
    const int r = static_cast<int>(std::upper_bound(first.begin(), first.end(), g) - first.begin()) - 1;
    VM_CHECK(r >= 0 && g < first[r] + count[r], "a ghost point some process owns");
    for (int i = 0; i < bs; ++i)
      wanted.push_back(!split ? bs * g + i
                       : i < c ? bs * first[r] + c * (g - first[r]) + i
                               : bs * first[r] + c * count[r] + (g - first[r]));
  }
  IS is = nullptr;
  check(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(wanted.size()), wanted.data(), PETSC_COPY_VALUES, &is),
        "ISCreateGeneral");
  check(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(wanted.size()), &ghost_values), "VecCreateSeq");
  const PetscErrorCode code = VecScatterCreate(solution, is, ghost_values, nullptr, &ghosts);
  ISDestroy(&is);
  check(code, "VecScatterCreate (ghost rows)");
}

void LinearSolver::Impl::copy_out(std::vector<double>& x) {
  const PetscScalar* r = nullptr;
  check(VecGetArrayRead(solution, &r), "VecGetArrayRead");
  if (split)
    for (int row = 0; row < rows; ++row) x[row] = r[petsc_row(row)];
  else
    std::memcpy(x.data(), r, static_cast<size_t>(rows) * sizeof(double));
  check(VecRestoreArrayRead(solution, &r), "VecRestoreArrayRead");
  if (distributed) {  // the ghosts' values from the processes that own them
    check(VecScatterBegin(ghosts, solution, ghost_values, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    check(VecScatterEnd(ghosts, solution, ghost_values, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    check(VecGetArrayRead(ghost_values, &r), "VecGetArrayRead");
    std::memcpy(x.data() + rows, r, static_cast<size_t>(block_size) * pattern.ghost_rows.size() * sizeof(double));
    check(VecRestoreArrayRead(ghost_values, &r), "VecRestoreArrayRead");
  }
}

LinearSolver::LinearSolver(SparsePattern pattern, int block_size, const std::string& defaults,
                           const std::string& options)
    : impl_(std::make_unique<Impl>()) {
  ensure_petsc();
  Impl& s = *impl_;
  s.pattern = std::move(pattern);
  s.block_size = block_size;
  const int n = s.pattern.rows;
  s.rows = block_size * n;
  VM_CHECK(static_cast<int>(s.pattern.row_start.size()) == n + 1, "pattern row offsets");
  VM_CHECK(block_size >= 1, "a block size");

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
    parallel::take_petsc_message();
    throw OptionError(fmt::format("PETSc cannot read the solver options \"{}\"", options));
  }

  s.distributed = parallel::process_count() > 1;
  const MPI_Comm comm = s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
  VM_CHECK(s.distributed || (s.pattern.total_rows() == n && s.pattern.first_row == 0), "one process holds every row");
  static_assert(std::is_same_v<PetscInt, int>, "PETSc with 32-bit indices, as the pattern's");
  // A field split of points' blocks works on the matrix's field blocks (a nest), not on copies.
  char pc_type[64] = "";
  PetscBool given = PETSC_FALSE;
  check(PetscOptionsGetString(nullptr, nullptr, "-pc_type", pc_type, sizeof pc_type, &given), "-pc_type");
  s.split = block_size > 1 && given && std::string(pc_type) == PCFIELDSPLIT;
  char schur_pre[64] = "";
  check(PetscOptionsGetString(nullptr, nullptr, "-pc_fieldsplit_schur_precondition", schur_pre, sizeof schur_pre,
                              &given),
        "-pc_fieldsplit_schur_precondition");
  s.user_schur = s.split && given && std::string(schur_pre) == "user";
  s.make_matrix(comm);
  // Each point row's own column points (sorted, consecutive in it) and the counts before it.
  const int first = s.pattern.first_row;
  s.own_begin.resize(n);
  s.own_count.resize(n);
  s.own_before.assign(n + 1, 0);
  s.other_before.assign(n + 1, 0);
  for (int a = 0; a < n; ++a) {
    const auto row = s.pattern.columns.begin() + s.pattern.row_start[a],
               end = s.pattern.columns.begin() + s.pattern.row_start[a + 1];
    const auto begin_own = std::lower_bound(row, end, first), end_own = std::lower_bound(row, end, first + n);
    s.own_begin[a] = static_cast<int>(begin_own - row);
    s.own_count[a] = static_cast<int>(end_own - begin_own);
    s.own_before[a + 1] = s.own_before[a] + s.own_count[a];
    s.other_before[a + 1] = s.other_before[a] + static_cast<int>(end - row) - s.own_count[a];
  }
  std::vector<int>().swap(s.pattern.columns);  // PETSc's matrix has them
  if (s.distributed) s.make_ghost_scatter();
  else VM_CHECK(s.pattern.ghost_rows.empty(), "ghost rows on one process");

  check(KSPCreate(comm, &s.ksp), "KSPCreate");
  check(KSPSetOperators(s.ksp, s.matrix, s.matrix), "KSPSetOperators");
  check(KSPSetInitialGuessNonzero(s.ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
  if (KSPSetFromOptions(s.ksp) != 0) {
    const std::string why = parallel::take_petsc_message();
    throw OptionError(fmt::format("PETSc refused the solver options: {}", why));
  }
  PC pc = nullptr;
  check(KSPGetPC(s.ksp, &pc), "KSPGetPC");
  if (of_type(pc, PCFIELDSPLIT) && block_size > 1) {
    IS fields[2] = {};
    if (s.split) {  // the nest's own (the preconditioner then takes its blocks as they are)
      IS columns[2] = {};
      check(MatNestGetISs(s.matrix, fields, columns), "MatNestGetISs");
    } else {
      std::vector<PetscInt> u, p;
      for (PetscInt i = block_size * first; i < block_size * (first + n); ++i)
        (i % block_size == block_size - 1 ? p : u).push_back(i);
      check(ISCreateGeneral(comm, static_cast<PetscInt>(u.size()), u.data(), PETSC_COPY_VALUES, &s.velocity), "IS");
      check(ISCreateGeneral(comm, static_cast<PetscInt>(p.size()), p.data(), PETSC_COPY_VALUES, &s.pressure), "IS");
      fields[0] = s.velocity;
      fields[1] = s.pressure;
    }
    check(PCFieldSplitSetIS(pc, "u", fields[0]), "PCFieldSplitSetIS");
    check(PCFieldSplitSetIS(pc, "p", fields[1]), "PCFieldSplitSetIS");
    if (s.schur) check(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_USER, s.schur), "PCFieldSplitSetSchurPre");
  }
}

LinearSolver::~LinearSolver() = default;

const SparsePattern& LinearSolver::pattern() const { return impl_->pattern; }

SolveStats LinearSolver::solve(const std::vector<double>& values, const std::vector<double>& rhs,
                               std::vector<double>& x) {
  const Impl& s = *impl_;
  const int bs = s.block_size, n = s.pattern.rows;
  VM_CHECK(values.size() == static_cast<size_t>(bs) * bs * s.pattern.row_start[n], "matrix values do not match the pattern");
  const MatrixValues m = begin_assembly();
  const double* v = values.data();
  for (int a = 0; a < n; ++a) {
    const int length = s.pattern.row_start[a + 1] - s.pattern.row_start[a];
    for (int i = 0; i < bs; ++i)
      for (int k = 0; k < length; ++k, v += bs) {
        const bool own = k >= s.own_begin[a] && k < s.own_begin[a] + s.own_count[a];
        const EntryPlace at =
            own ? entry_place(m, bs, true, s.own_before[a], s.own_count[a], i, k - s.own_begin[a])
                : entry_place(m, bs, false, s.other_before[a], length - s.own_count[a], i,
                              k < s.own_begin[a] ? k : k - s.own_count[a]);
        for (int j = 0; j < bs; ++j) at[j] = v[j];
      }
  }
  end_assembly();
  return solve_assembled(rhs, x);
}

MatrixValues LinearSolver::begin_assembly() {
  Impl& s = *impl_;
  VM_CHECK(!s.out, "begin_assembly twice");
  MatrixValues& m = s.assembling;
  m = MatrixValues{};
  m.split = s.split;
  for (int f = 0; f < (s.split ? 2 : 1); ++f)
    for (int g = 0; g < (s.split ? 2 : 1); ++g) {
      double*& own = s.split ? m.split_own[f][g] : m.own;
      double*& other = s.split ? m.split_other[f][g] : m.other;
      for (auto [part, values] : {std::pair{s.own_part[f][g], &own}, std::pair{s.other_part[f][g], &other}}) {
        if (!part) continue;
        get_values(part, values);
        MatInfo info{};  // its entries' count
        check(MatGetInfo(part, MAT_LOCAL, &info), "MatGetInfo");
        std::fill(*values, *values + static_cast<size_t>(info.nz_used), 0.0);
      }
    }
  for (auto [part, values] : {std::pair{s.schur_own, &m.schur_own}, std::pair{s.schur_other, &m.schur_other}}) {
    if (!part) continue;
    get_values(part, values);
    MatInfo info{};
    check(MatGetInfo(part, MAT_LOCAL, &info), "MatGetInfo");
    std::fill(*values, *values + static_cast<size_t>(info.nz_used), 0.0);
  }
  s.out = true;
  return m;
}

void LinearSolver::end_assembly() {
  Impl& s = *impl_;
  VM_CHECK(s.out, "end_assembly without begin_assembly");
  MatrixValues& m = s.assembling;
  // The Schur complement's preconditioning matrix: the caller's part plus the pressure block (the
  // same pattern, the same order).
  for (auto [part, values, block] : {std::tuple{s.schur_own, &m.schur_own, m.split_own[1][1]},
                                     std::tuple{s.schur_other, &m.schur_other, m.split_other[1][1]}}) {
    if (!part) continue;
    MatInfo info{};
    check(MatGetInfo(part, MAT_LOCAL, &info), "MatGetInfo");
    for (size_t k = 0; k < static_cast<size_t>(info.nz_used); ++k) (*values)[k] += block[k];
    restore_values(part, values);
  }
  if (s.schur) {
    check(MatAssemblyBegin(s.schur, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(s.schur, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  }
  for (int f = 0; f < (s.split ? 2 : 1); ++f)
    for (int g = 0; g < (s.split ? 2 : 1); ++g) {
      double*& own = s.split ? m.split_own[f][g] : m.own;
      double*& other = s.split ? m.split_other[f][g] : m.other;
      restore_values(s.own_part[f][g], &own);
      if (s.other_part[f][g]) restore_values(s.other_part[f][g], &other);
    }
  // The whole matrix changed (its preconditioner and field split see it by its state): an
  // assembly with nothing to send says so. (One matrix on one process: its state moved with its array.)
  if (s.distributed || s.split) {
    check(MatAssemblyBegin(s.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(s.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  }
  s.assembling = MatrixValues{};
  s.out = false;
}

void LinearSolver::Impl::load(const std::vector<double>& b, const std::vector<double>& x, const char* what) {
  VM_CHECK(!out, std::string(what) + " before end_assembly");
  VM_CHECK(static_cast<int>(b.size()) == rows && x.size() >= static_cast<size_t>(rows), "vector sizes");
  // The right-hand side and the initial guess (x's own rows) into PETSc's vectors.
  for (auto [vec, from] : {std::pair{rhs, b.data()}, std::pair{solution, x.data()}}) {
    PetscScalar* v = nullptr;
    check(VecGetArray(vec, &v), "VecGetArray");
    if (split)
      for (int row = 0; row < rows; ++row) v[petsc_row(row)] = from[row];
    else
      std::memcpy(v, from, static_cast<size_t>(rows) * sizeof(double));
    check(VecRestoreArray(vec, &v), "VecRestoreArray");
  }
}

SolveStats LinearSolver::solve_assembled_direct(const std::vector<double>& rhs, std::vector<double>& x) {
  Impl& s = *impl_;
  VM_CHECK(x.size() == s.rows + s.block_size * s.pattern.ghost_rows.size(), "the solution's size: own and ghost rows");
  s.load(rhs, x, "solve_assembled_direct");
  if (!s.direct) {  // kept: the next solves reuse its symbolic factorization (the same pattern)
    check(KSPCreate(s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF, &s.direct), "KSPCreate");
    PC pc = nullptr;
    check(KSPSetType(s.direct, KSPPREONLY), "KSPSetType");
    check(KSPGetPC(s.direct, &pc), "KSPGetPC");
    check(PCSetType(pc, PCLU), "PCSetType");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  }
  Mat a = s.matrix;
  if (s.split) {  // MUMPS factors one matrix: the blocks copied into one (the fallback of small systems)
    check(MatConvert(s.matrix, MATAIJ, s.converted ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &s.converted),
          "MatConvert (the field blocks into one matrix)");
    a = s.converted;
  }
  // With a low-rank term, A's LU preconditions GMRES on the whole operator (K + 1 iterations for
  // K columns, in exact arithmetic).
  if (s.whole) {
    check(KSPSetType(s.direct, KSPGMRES), "KSPSetType");
    check(KSPSetTolerances(s.direct, 1e-12, 0.0, PETSC_DEFAULT, 100), "KSPSetTolerances");
    check(KSPSetInitialGuessNonzero(s.direct, PETSC_TRUE), "KSPSetInitialGuessNonzero");
  }
  check(KSPSetOperators(s.direct, s.whole ? s.whole : a, a), "KSPSetOperators");
  check(KSPSolve(s.direct, s.rhs, s.solution), "KSPSolve (MUMPS)");
  KSPConvergedReason reason = KSP_DIVERGED_PC_FAILED;
  check(KSPGetConvergedReason(s.direct, &reason), "KSPGetConvergedReason");
  s.copy_out(x);
  SolveStats stats;
  PetscInt direct_iterations = 1;
  if (s.whole) check(KSPGetIterationNumber(s.direct, &direct_iterations), "KSPGetIterationNumber");
  stats.iterations = static_cast<int>(std::max<PetscInt>(direct_iterations, 1));
  stats.converged = reason > 0;
  stats.reason = KSPConvergedReasons[reason];
  s.least_iterations = -1;  // the iterative solver's preconditioner is built anew next time
  return stats;
}

PetscReal LinearSolver::Impl::residual_norm() const {
  Vec r = nullptr;
  check(VecDuplicate(rhs, &r), "VecDuplicate");
  check(MatMult(op(), solution, r), "MatMult");
  check(VecAXPY(r, -1.0, rhs), "VecAXPY");
  PetscReal residual = 0.0;
  check(VecNorm(r, NORM_2, &residual), "VecNorm");
  VecDestroy(&r);
  return residual;
}

void LinearSolver::Impl::project_guess(double rtol) {
  projected = nullptr;
  if (kept.empty()) return;
  const int k = 1 + static_cast<int>(kept.size());
  while (static_cast<int>(products.size()) < k + 1) {
    Vec v = nullptr;
    check(VecDuplicate(solution, &v), "VecDuplicate");
    products.push_back(v);
  }
  Vec guess = products[k];
  check(VecCopy(solution, guess), "VecCopy");
  const auto basis = [&](int j) { return j == 0 ? guess : kept[j - 1]; };
  // The guess's residual first: where it is within kProjectAbove times the tolerance the
  // combination is not tried (on the benchmark pipe's settling flow, 30 times, it cut the residual
  // 3-5 fold and the solves took 6 iterations where they took 4: what it leaves is in the modes the
  // preconditioner takes slowest, and its products with A cost a third of the solve).
  PetscScalar b_b = 0.0, b_a = 0.0, a_a = 0.0;
  check(MatMult(op(), guess, products[0]), "MatMult");
  check(VecDot(rhs, rhs, &b_b), "VecDot");
  check(VecDot(rhs, products[0], &b_a), "VecDot");
  check(VecDot(products[0], products[0], &a_a), "VecDot");
  const PetscScalar guess_left = b_b - 2.0 * b_a + a_a;  // ||b - A g||^2
  if (guess_left < kProjectAbove * kProjectAbove * rtol * rtol * b_b) return;
  // The products of the guess and the kept solutions with A made orthonormal (modified
  // Gram-Schmidt, twice: successive solutions are nearly parallel); a product left with less than
  // 1e-10 of its norm adds nothing and is dropped.
  std::vector<PetscScalar> r(static_cast<size_t>(k * k), 0.0);
  std::vector<char> used(k, 0);
  for (int j = 0; j < k; ++j) {
    Vec q = products[j];
    if (j > 0) check(MatMult(op(), basis(j), q), "MatMult");
    PetscReal before = 0.0, after = 0.0;
    check(VecNorm(q, NORM_2, &before), "VecNorm");
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i < j; ++i)
        if (used[i]) {
          PetscScalar d = 0.0;
          check(VecDot(q, products[i], &d), "VecDot");
          r[i * k + j] += d;
          check(VecAXPY(q, -d, products[i]), "VecAXPY");
        }
    check(VecNorm(q, NORM_2, &after), "VecNorm");
    if (after > 1e-10 * before) {
      used[j] = 1;
      r[j * k + j] = after;
      check(VecScale(q, 1.0 / after), "VecScale");
    }
  }
  // The least-residual combination, R c = Q^T b, taken where it leaves at most half the guess's
  // residual: one that barely lowers it leaves the rest in the slow modes too (the FDA nozzle at
  // Re 500 from its Stokes flow, CFL 50: the extrapolation leaves 0.21-0.40 of ||b||, the
  // combination 0.13-0.24, and the solves took 11 % more iterations).
  std::vector<PetscScalar> c(k, 0.0);
  PetscScalar left = b_b;  // ||b - A x||^2 at the combination: ||b||^2 less b's part in Q's span
  for (int i = 0; i < k; ++i)
    if (used[i]) {
      check(VecDot(rhs, products[i], &c[i]), "VecDot");
      left -= c[i] * c[i];
    }
  if (!(left < 0.25 * guess_left)) return;  // the guess as it was (still in `solution`)
  for (int i = k - 1; i >= 0; --i) {
    if (!used[i]) continue;
    for (int j = i + 1; j < k; ++j)
      if (used[j]) c[i] -= r[i * k + j] * c[j];
    c[i] /= r[i * k + i];
  }
  check(VecSet(solution, 0.0), "VecSet");
  for (int j = 0; j < k; ++j)
    if (used[j]) check(VecAXPY(solution, c[j], basis(j)), "VecAXPY");
  check(VecCopy(solution, guess), "VecCopy");  // kept for a solve made again (solve_assembled)
  projected = guess;
}

void LinearSolver::Impl::keep_solution() {
  if (keep_count <= 0) return;
  Vec v = nullptr;
  if (static_cast<int>(kept.size()) < keep_count) {
    check(VecDuplicate(solution, &v), "VecDuplicate");
  } else {
    v = kept.back();
    kept.pop_back();
  }
  check(VecCopy(solution, v), "VecCopy");
  kept.insert(kept.begin(), v);
}

void LinearSolver::Impl::forget_solutions() {
  for (Vec& v : kept) VecDestroy(&v);
  for (Vec& v : products) VecDestroy(&v);
  kept.clear();
  products.clear();
  projected = nullptr;
}

double LinearSolver::relative_residual(const std::vector<double>& rhs, const std::vector<double>& x) {
  Impl& s = *impl_;
  s.load(rhs, x, "relative_residual");
  const PetscReal residual = s.residual_norm();
  PetscReal scale = 0.0;
  check(VecNorm(s.rhs, NORM_2, &scale), "VecNorm");
  return scale > 0.0 ? residual / scale : residual;
}

SolveStats LinearSolver::solve_assembled(const std::vector<double>& rhs, std::vector<double>& x) {
  Impl& s = *impl_;
  VM_CHECK(x.size() == s.rows + s.block_size * s.pattern.ghost_rows.size(), "the solution's size: own and ghost rows");
  s.load(rhs, x, "solve_assembled");

  // Reuse the preconditioner while the solve before did not take much more than the fewest any
  // solve took with it; cap the reusing solve at twice that, and repeat it with a new
  // preconditioner if it fails.
  const int reuse_limit = std::max(s.least_iterations, 0) + kReuseSlack;
  const bool reuse = s.reuse && s.least_iterations >= 0 && s.last_iterations <= reuse_limit;
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
  s.project_guess(rtol);
  set_reuse(s.ksp, reuse, s.solved);
  if (reuse)
    check(KSPSetTolerances(s.ksp, rtol, abstol, dtol, std::min<PetscInt>(max_it, 2 * reuse_limit)), "KSPSetTolerances");
  const PetscReal initial = s.check_residual ? s.residual_norm() : 0.0;
  check(KSPSolve(s.ksp, s.rhs, s.solution), "KSPSolve");
  s.solved = true;
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(s.ksp, &reason), "KSPGetConvergedReason");
  bool built = !reuse;
  PetscInt failed_iterations = 0;  // of a capped solve that did not converge
  if (reuse) {
    check(KSPSetTolerances(s.ksp, rtol, abstol, dtol, max_it), "KSPSetTolerances");
    if (reason <= 0) {  // the old preconditioner no longer serves: start again with a new one
      check(KSPGetIterationNumber(s.ksp, &failed_iterations), "KSPGetIterationNumber");
      s.load(rhs, x, "solve_assembled");  // the initial guess again (as projected: the same start)
      if (s.projected) check(VecCopy(s.projected, s.solution), "VecCopy");
      set_reuse(s.ksp, false, true);
      check(KSPSolve(s.ksp, s.rhs, s.solution), "KSPSolve");
      built = true;
    }
  }

  s.copy_out(x);
  s.keep_solution();

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
  // GMRES tests the residual its recurrence estimates; unstable preconditioners (ILU's factors of
  // Newton's velocity block on the FDA nozzle at Re 500: 4e-10 estimated, 21 true) leave the true
  // one far above it. Such a solve did not converge.
  if (s.check_residual && stats.converged) {
    PetscReal b = 0.0;  // (the test is relative to the initial residual or to ||b||: the larger)
    check(VecNorm(s.rhs, NORM_2, &b), "VecNorm");
    const PetscReal target = std::max<PetscReal>(rtol * std::max(initial, b), abstol), residual = s.residual_norm();
    if (residual > kTrueResidualSlack * target) {
      stats.converged = false, stats.true_residual_missed = true;
      stats.reason = fmt::format("{} by its own estimate ({:.3g}), but its true residual is {:.3g}, {:.3g} times the "
                                 "tolerance", stats.reason, norm, residual, residual / target);
    }
  }
  s.least_iterations = built ? static_cast<int>(iterations) : std::min(s.least_iterations, static_cast<int>(iterations));
  s.last_iterations = static_cast<int>(iterations);
  return stats;
}

void LinearSolver::set_low_rank_columns(const std::vector<std::vector<double>>& columns) {
  Impl& s = *impl_;
  VM_CHECK(s.low_rank.empty(), "the low-rank columns are set once");
  if (columns.empty()) return;
  for (const std::vector<double>& column : columns) {
    VM_CHECK(static_cast<int>(column.size()) == s.rows, "a low-rank column of this process's rows");
    Vec v = nullptr;
    check(VecDuplicate(s.solution, &v), "VecDuplicate");
    PetscScalar* a = nullptr;
    check(VecGetArray(v, &a), "VecGetArray");
    for (int row = 0; row < s.rows; ++row) a[s.petsc_row(row)] = column[row];
    check(VecRestoreArray(v, &a), "VecRestoreArray");
    s.low_rank.push_back(v);
  }
  s.low_rank_c.assign(columns.size(), 0.0);
  const PetscInt global = s.block_size * s.pattern.total_rows();
  check(MatCreateShell(s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF, s.rows, s.rows, global, global, &s,
                       &s.whole),
        "MatCreateShell");
  check(MatShellSetOperation(s.whole, MATOP_MULT, reinterpret_cast<void (*)(void)>(Impl::low_rank_product)),
        "MatShellSetOperation");
  // The Krylov method on the whole operator, the preconditioner built from the matrix alone.
  check(KSPSetOperators(s.ksp, s.whole, s.matrix), "KSPSetOperators");
}

void LinearSolver::set_low_rank_coefficients(const std::vector<double>& coefficients) {
  Impl& s = *impl_;
  VM_CHECK(coefficients.size() == s.low_rank.size(), "a coefficient per low-rank column");
  // (The shell reads them at each product; the preconditioner is the matrix's, whose assembly
  // tells PETSc it changed.)
  std::copy(coefficients.begin(), coefficients.end(), s.low_rank_c.begin());
}

void LinearSolver::reuse_preconditioner(bool on) { impl_->reuse = on; }

void LinearSolver::keep_solutions(int count) {
  VM_CHECK(count >= 0, "keep_solutions: a count of solutions");
  impl_->keep_count = count;
  forget_solutions();
}

void LinearSolver::forget_solutions() { impl_->forget_solutions(); }

void LinearSolver::set_residual_floor(double relative) { impl_->residual_floor = relative; }
void LinearSolver::set_residual_check(bool on) { impl_->check_residual = on; }
void LinearSolver::scale_tolerance(double factor) { impl_->tolerance_factor = factor; }
void LinearSolver::rebuild_preconditioner() { impl_->least_iterations = -1; }

bool LinearSolver::sweep_velocity_blocks() {
  Impl& s = *impl_;
  PC pc = nullptr, velocity = nullptr;
  if (s.ksp && s.solved) check(KSPGetPC(s.ksp, &pc), "KSPGetPC");
  if (pc && of_type(pc, PCFIELDSPLIT)) {
    PetscInt count = 0;
    KSP* inner = nullptr;
    check(PCFieldSplitGetSubKSP(pc, &count, &inner), "PCFieldSplitGetSubKSP");
    check(KSPGetPC(inner[0], &velocity), "KSPGetPC");
    PetscFree(inner);
  }
  bool changed = false;
  if (velocity && of_type(velocity, PCBJACOBI)) {
    PetscInt blocks = 0, first = 0;
    KSP* block = nullptr;
    check(PCBJacobiGetSubKSP(velocity, &blocks, &first, &block), "PCBJacobiGetSubKSP");
    for (PetscInt k = 0; k < blocks; ++k) {
      PC sub = nullptr;
      check(KSPGetPC(block[k], &sub), "KSPGetPC");
      if (!of_type(sub, PCILU)) continue;
      check(PCSetType(sub, PCSOR), "PCSetType");
      changed = true;
    }
  }
  if (changed) s.least_iterations = -1;  // built anew at the next solve
  return parallel::any_process(changed);
}

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
