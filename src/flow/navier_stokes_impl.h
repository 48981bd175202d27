// NavierStokes's insides (not a public header): the solver's state, NavierStokes::Impl, shared by
// its files, each holding one part of what it does:
//   navier_stokes.cpp           set-up: the part's numbering and matrix pattern, the threads' split,
//                               the boundaries, their Dirichlet values and fluxes, the resistance and
//                               RCR coupling; construction, the state saved and restored, the reports
//   navier_stokes_assembly.cpp  the state as solver rows, the steady residual and line search, the CFL
//                               number, the whole-field gather, and the assembly (Newton's terms too)
//   navier_stokes_solve.cpp     the linear solver made and its fallbacks, the time step, the steady
//                               driver (Picard, pseudo time, Newton's staged inflow), the Stokes start
#pragma once

#include "flow/navier_stokes.h"

#include "flow/inflow_perturbation.h"
#include "flow/stabilized_cell.h"
#include "flow/womersley.h"
#include "mesh/error.h"
#include "parallel/processes.h"

#include <fmt/format.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <type_traits>

namespace vesselmesh::flow {
// The solver's own helpers, shared by its files (named, not anonymous: NavierStokes::Impl holds
// them, and every file sees the one Impl).
namespace navier_stokes_parts {

inline constexpr int kBlock = 4;     // u, v, w, p per node

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// What a boundary triangle needs: its (local) points, outward unit normal and area (SI).
struct BoundaryFace {
  Triangle v;
  Vec3 normal;
  double area;
};

// One tagged boundary and its condition.
struct Boundary {
  BoundaryCondition condition;
  std::vector<BoundaryFace> faces;
  std::vector<int> nodes;  // every local point on it
  std::vector<char> counted;  // per face: this process counts it in sums (it owns its first point)
  double area = 0.0;
  Vec3 center = Vec3::Zero(), normal = Vec3::Zero();  // area-weighted, outward
  std::vector<double> shape;  // velocity boundaries: per node of `nodes`, unit flux, 0 on walls
  // Womersley profiles: the flow's Fourier coefficients (m3/s), its angular frequency, and per
  // harmonic the nodes' shape scaled to a unit discrete flux.
  std::vector<Complex> harmonic_flow;
  double omega = 0.0;
  std::vector<std::vector<Complex>> harmonic_shape;
  // Velocity boundaries with a perturbation: the disturbance, and per face its points' indices
  // in `nodes` (to remove the disturbance's net flow).
  std::optional<InflowPerturbation> perturbation;
  std::vector<std::array<int, 3>> face_nodes;
};

}  // namespace navier_stokes_parts
using namespace navier_stokes_parts;

struct NavierStokes::Impl {
  FlowCase fc;
  const Reporter* reporter = nullptr;
  double nu = 0.0;  // kinematic viscosity m2/s

  // Numberings. The solver's (global) numbering of the points: the mesh's points split among the
  // processes by PT-Scotch (partition_graph over the point graph), each process's points a
  // consecutive range, in reverse Cuthill-McKee order inside it (neighbours near each other in
  // memory); on one process the RCM order. A process holds its cells (those with a point it owns)
  // and their points, numbered locally: its own points first (global node_begin + local), then
  // its ghosts (the others' points of its cells), by global number. Everything inside is local;
  // the public interface is in the mesh's numbering.
  int total_points = 0;
  std::vector<int> process_begin;      // per process its first global point; one more: the total
  std::vector<int> local_global;       // per local point its global number
  std::vector<int> mesh_point;         // per local point its mesh number
  std::vector<int> global_mesh_point;  // on the first process: per global point its mesh number
  int owned = 0;                       // local points 0 .. owned - 1 are this process's
  int node_begin = 0;                  // the global number of local point 0
  bool owns(int a) const { return a < owned; }

  std::vector<Vec3> points;  // m, per local point
  std::vector<Tet> tets;     // this process's cells, local numbers
  // A cell's shape functions' gradients (1/m) and volume (m3), from its points: recomputed where
  // needed (three cross products) rather than kept (112 bytes a cell, 66 MB at 590k cells).
  std::array<Vec3, 4> cell_gradients(size_t e, double& volume) const {
    const Tet& t4 = tets[e];
    double v6 = 0.0;
    const std::array<Vec3, 4> g =
        mesh::barycentric_gradients(points[t4[0]], points[t4[1]], points[t4[2]], points[t4[3]], v6);
    volume = v6 / 6.0;
    return g;
  }
  // Node graph of the owned points (sorted global neighbours, self included) and each cell's
  // positions in it: for its corner a (an owned point) and corner b, b's place among a's
  // neighbours (node_start[a] + it is b's slot; 0 where a is not owned), in a byte: kept when
  // every row has at most 256 points (a tetrahedral mesh's have 10-40: 9 MB at 420k unknowns
  // where 16 bits took 18), else empty and searched for (cell_slot).
  std::vector<int> node_start, node_columns;
  std::vector<std::array<std::uint8_t, 16>> tet_slots;
  int cell_slot(size_t e, int a, int b) const {
    const Tet& t4 = tets[e];
    return tet_slots.empty() ? slot(t4[a], t4[b]) : node_start[t4[a]] + tet_slots[e][a * 4 + b];
  }
  // The assembly's threads: the owned points split into `threads` consecutive ranges of about
  // equal matrix entries (chunk k: chunk_begin[k] .. chunk_begin[k + 1] - 1), and per range the
  // cells with a point in it, in increasing order (empty for one range). A thread adds a cell's
  // system to its range's rows only, so each row gets its cells' terms in the cells' order: the
  // matrix and right-hand side are the one thread's to the bit, whatever the thread count. A
  // cell across ranges is computed by each (the ranges are slabs of the RCM order: few).
  int threads = 1;
  std::vector<int> chunk_begin;
  std::vector<std::vector<int>> chunk_cells;
  std::unique_ptr<tbb::task_arena> arena;
  void split_for_threads();
  // The solver's pattern: the node graph's rows of this process, with the ghost points.
  SparsePattern point_pattern() const;
  std::vector<Boundary> boundaries;
  std::vector<char> fixed;  // per local dof: Dirichlet
  std::unique_ptr<LinearSolver> solver;

  // Every process's copy of the whole flow in the mesh's numbering (gathered_velocity(), gathered_pressure()),
  // gathered when first asked for after a solve (`published` false until then).
  mutable std::vector<Vec3> u_mesh;
  mutable std::vector<double> p_mesh;  // Pa
  mutable bool published = false;
  void publish() const;
  // The whole of per-point values (`width` a point, this process's own points) on the first
  // process, in the mesh's numbering.
  std::vector<double> gather_points(const std::vector<double>& mine, int width) const;

  // State, per local point.
  double t = 0.0;
  int step_count = 0;
  double dt_next = 0.0, dt_last = 0.0;  // s: the next step's length and the last one's (0: fc.dt)
  std::vector<Vec3> u, u_old;  // u^n, u^{n-1}
  std::vector<double> p_old;  // p^{n-1}: the next step's pressure extrapolated (its initial guess)
  std::vector<double> p;       // kinematic pressure p / rho
  std::vector<double> rhs, x, dirichlet;
  void make_solver();
  bool stokes_start = false;  // the solver to make is the Stokes start's
  // The resistance and rcr ends, coupled implicitly: an end's pressure over rho is
  // resistance_coefficient x its outflow Q in the same solve (the solver's low-rank term, its
  // column the end's area vectors at its points) plus resistance_pressure; an rcr end's capacitor
  // then moves to capacitor_gain x Q + capacitor_base (update_resistance, settle_capacitors).
  std::vector<double> resistance_pressure;     // per boundary: Pa / rho, the part independent of Q
  std::vector<double> resistance_coefficient;  // per boundary: (Pa s/m3) / rho
  std::vector<double> capacitor_gain, capacitor_base;  // per rcr boundary: Pa s/m3, Pa
  std::vector<double> capacitor_pressure;   // per boundary: rcr ends' capacitor pressure P_c (Pa)
  std::vector<int> resistive;               // the resistance and rcr boundaries: the low-rank columns

  int n() const { return static_cast<int>(points.size()); }

  // Where owned node a's component row i holds its entries at its node-graph position k, in the
  // matrix's arrays during the assembly (flow/linear_solver.h, entry_place): per owned node its
  // owned and other neighbours before it, and per node-graph position its place among the node's
  // owned (or other) neighbours.
  std::vector<int> own_start, other_start, place;
  MatrixValues values;  // during the assembly
  bool owned_global(int g) const { return g >= node_begin && g < node_begin + owned; }
  // Where owned point a's rows hold their entries at slot k of its node graph row: whether the
  // column point is this process's, the entries of that kind in the rows before a's and in a's, and
  // its place among them (entry_place's arguments).
  struct RowPart {
    bool own;
    int before, count, place;
  };
  RowPart row_part(int a, int k) const {
    const bool own = owned_global(node_columns[k]);
    const std::vector<int>& start = own ? own_start : other_start;
    return {own, start[a], start[a + 1] - start[a], place[k]};
  }
  EntryPlace entry(int a, int i, int k) const {
    const RowPart r = row_part(a, k);
    return entry_place(values, kBlock, r.own, r.before, r.count, i, r.place);
  }
  // All of a's rows at slot k at once, when the matrix is held as the field split's blocks.
  SplitPairPlace pair_entries(int a, int k) const {
    const RowPart r = row_part(a, k);
    return split_pair_place(values, kBlock, r.own, r.before, r.count, r.place);
  }
  // Position of local point b among owned point a's neighbours in the node graph.
  int slot(int a, int b) const {
    const auto first = node_columns.begin() + node_start[a], last = node_columns.begin() + node_start[a + 1];
    return static_cast<int>(std::lower_bound(first, last, local_global[b]) - node_columns.begin());
  }

  void build(MeshPart part);
  void build_boundaries(const MeshPart& part);
  void set_dirichlet(double time);
  // How the convection is linearized at `advect`: Picard's (Oseen) form; Newton's on the Galerkin
  // convection (its (du . grad) u part and the right-hand side that goes with it), the
  // stabilization's terms in Picard's form; or Newton's on the stabilization's terms too (exact).
  enum class Linearization { picard, convection, full };
  void assemble(const std::vector<Vec3>& advect, const std::vector<Vec3>& history, double mass_coefficient,
                double dt, Linearization linearization = Linearization::picard);
  // assemble()'s parts after the cells: the Schur complement's preconditioning matrix at the open
  // ends (from each owned point's share of its cells' momentum diagonal), the open ends' backflow
  // stabilization and resistance traction, and the Dirichlet rows (the diagonal the cells gave them).
  void add_open_end_schur(const std::vector<double>& momentum_share);
  void add_open_ends(const std::vector<Vec3>& advect, bool newton);
  void set_dirichlet_rows(const std::vector<double>& diagonal);
  // assemble()'s cells, kCellLanes at a time: their corners, and their point pairs' entries prefetched.
  void gather_corners(const int* cell, int count, const std::vector<Vec3>& advect, const std::vector<Vec3>& history,
                      CellCorners& corners) const;
  void prefetch_pairs(const int* cell, int count, int lo, int hi) const;
  // Solves the assembled system from an initial guess: `guess`'s velocity with the current
  // pressure (null: the current flow). `direct_fallback`: when the iterative solver does not
  // converge and the system has at most NavierStokes::kDirectFallbackUnknowns unknowns, solve it
  // directly (MUMPS), said (steady solves).
  void solve_system(StepReport& report, const std::string& where, bool direct_fallback = false,
                    const std::vector<Vec3>* guess = nullptr, const std::vector<double>* pressure_guess = nullptr);
  bool direct_now = false;  // a steady solve went to the direct solver: its next iterations too
  // The largest cell CFL number (a cell's mean velocity over its least height, 1 over its largest
  // barycentric gradient, times dt) over the processes: a pass over the cells of its own, before an
  // assembly (the pseudo-transient step's choice); the assembly's own is assembled_cfl's.
  double cfl(const std::vector<Vec3>& advect, double dt) const;
  // Per assembly chunk, the largest cell CFL number of the last assembly with a time step (its
  // convecting velocity; 0 for a steady one), and their largest over the chunks and processes.
  std::vector<double> chunk_cfl;
  std::vector<SteadyIteration> steady_history;  // NavierStokes::steady_history
  double assembled_cfl() const;
  // x: the state (velocity, pressure) per local point, the solver's interleaved rows.
  std::vector<double> state_rows(const std::vector<Vec3>& velocity, const std::vector<double>& pressure) const;
  // The message of a steady solve that did not settle (its last change `change`): what was tried,
  // where the residual went (steady_history), what to try next.
  std::string not_settled(double change) const;
  // Newton's stages: the flow settled at `stage` (u, p) extrapolated to the next stage's inflow, the
  // start of its iterations (x too); stage_u, stage_p become this stage's flow (they held the last one's).
  void start_next_stage(size_t stage, std::vector<Vec3>& stage_u, std::vector<double>& stage_p);
  // The steady residual ||A(w) w - b|| / ||b|| at the state `w` (rows as x's; the system
  // assembled at its velocity in Picard's form, which leaves the solver's matrix so).
  double steady_residual(const std::vector<double>& w);
  // Newton's step from the current state to the solved x, cut back (1, 1/2, ... kLeastStep) until
  // the steady residual falls below (1 - 1e-4 lambda) `before` (Armijo's test); x becomes the
  // state taken, `after` its steady residual. Returns lambda, or 0 when no step passed (x left as
  // Newton's, `after` -1).
  double line_search(double before, StepReport& report, double& after);
  // A steady iteration's system assembled (the pseudo time step pseudo_dt, 0 for none), and the
  // steady residual of the iterate x it starts from.
  // (known: that residual where the last line search measured it at x, else -1.)
  double residual_and_assemble(const std::vector<Vec3>& advect, const std::vector<Vec3>& history, double pseudo_dt,
                               Linearization linearization, double known);
  // Every boundary's flux (m3/s) of `velocity`, summed over the processes (every process calls it).
  std::vector<double> fluxes(const std::vector<Vec3>& velocity) const;
  // The resistance and rcr boundaries' pressure (over rho) as a function of their outflow in the
  // next solve, a step of `dt` (0: an rcr end's capacitor stays; steady cases: its steady value).
  void update_resistance(double dt);
  // The rcr ends' capacitors at the solved flow (after update_resistance's solve).
  void settle_capacitors();
  // Copies the solved x into velocity and pressure; returns the velocity's relative change.
  double take_solution(std::vector<Vec3>& velocity, std::vector<double>& pressure) const;
  void check_finite(const StepReport& report) const;
};

}  // namespace vesselmesh::flow
