#include "parallel/processes.h"

#include "parallel/petsc_start.h"

#include "mesh/error.h"

#include <fmt/format.h>
#include <petscmat.h>
// After PETSc's headers (scotch.h needs <cstdio> and <cstdint>, which they bring).
#include <scotch.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace vesselmesh::parallel {
namespace {

// PETSc reports errors through a handler: ours keeps the first message of the chain and returns
// the code, so that a failure becomes an exception with PETSc's words instead of a traceback.
thread_local std::string petsc_message;

PetscErrorCode keep_message(MPI_Comm, int, const char*, const char*, PetscErrorCode n, PetscErrorType p,
                            const char* message, void*) {
  if (p == PETSC_ERROR_INITIAL) petsc_message = message ? message : "";
  return n;
}

}  // namespace

std::string take_petsc_message() {
  std::string text;
  text.swap(petsc_message);
  return text;
}

void check_petsc(int code, const char* what) {
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
  check_petsc(PetscMalloc1(total + 1, &ia), "PetscMalloc1");
  check_petsc(PetscMalloc1(std::max<size_t>(neighbours.size(), 1), &ja), "PetscMalloc1");
  ia[0] = 0;
  for (int r = 0; r < total; ++r) {
    ia[r + 1] = ia[r];
    for (int k = start[r]; k < start[r + 1]; ++k)
      if (neighbours[k] != r) ja[ia[r + 1]++] = neighbours[k];
  }
  Mat adjacency = nullptr;
  check_petsc(MatCreateMPIAdj(PETSC_COMM_SELF, total, total, ia, ja, nullptr, &adjacency), "MatCreateMPIAdj");
  MatPartitioning partitioning = nullptr;
  IS owners = nullptr;
  check_petsc(MatPartitioningCreate(PETSC_COMM_SELF, &partitioning), "MatPartitioningCreate");
  check_petsc(MatPartitioningSetAdjacency(partitioning, adjacency), "MatPartitioningSetAdjacency");
  check_petsc(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH), "MatPartitioningSetType (PT-Scotch)");
  check_petsc(MatPartitioningSetNParts(partitioning, parts), "MatPartitioningSetNParts");
  check_petsc(MatPartitioningApply(partitioning, &owners), "MatPartitioningApply (PT-Scotch)");
  const PetscInt* owner = nullptr;
  check_petsc(ISGetIndices(owners, &owner), "ISGetIndices");
  std::copy(owner, owner + total, owner_of.begin());
  check_petsc(ISRestoreIndices(owners, &owner), "ISRestoreIndices");
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

void error_told_together(double seconds) {
  ensure_petsc();
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  constexpr int kTold = 7701;  // a tag of its own
  char word = 1;
  if (rank == 0) {
    std::fflush(stderr);
    for (int r = 1; r < size; ++r) MPI_Send(&word, 1, MPI_CHAR, r, kTold, PETSC_COMM_WORLD);  // eager: no wait
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  int arrived = 0;
  while (!arrived && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds) {
    MPI_Iprobe(0, kTold, PETSC_COMM_WORLD, &arrived, MPI_STATUS_IGNORE);
    if (!arrived) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (arrived) MPI_Recv(&word, 1, MPI_CHAR, 0, kTold, PETSC_COMM_WORLD, MPI_STATUS_IGNORE);
}

}  // namespace vesselmesh::parallel
