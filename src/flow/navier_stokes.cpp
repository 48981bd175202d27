#include "flow/navier_stokes.h"

#include "flow/stabilized_cell.h"
#include "flow/womersley.h"
#include "mesh/error.h"
#include "parallel/processes.h"

#include <fmt/format.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <map>
#include <set>
#include <type_traits>

namespace vesselmesh::flow {
namespace {

constexpr int kBlock = 4;     // u, v, w, p per node

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
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
};

}  // namespace

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

  // Every process's copy of the whole flow in the mesh's numbering (velocity(), pressure()),
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
  std::vector<Vec3> u, u_old;  // u^n, u^{n-1}
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
  // Solves the assembled system from an initial guess: `guess`'s velocity with the current
  // pressure (null: the current flow). `direct_fallback`: when the iterative solver does not
  // converge and the system has at most NavierStokes::kDirectFallbackUnknowns unknowns, solve it
  // directly (MUMPS), said (steady solves).
  void solve_system(StepReport& report, const std::string& where, bool direct_fallback = false,
                    const std::vector<Vec3>* guess = nullptr);
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

void NavierStokes::Impl::build(MeshPart part) {
  total_points = part.total_points;
  process_begin = std::move(part.process_begin);
  owned = part.owned;
  node_begin = process_begin[parallel::process_rank()];
  local_global = std::move(part.local_global);
  mesh_point = std::move(part.mesh_point);
  global_mesh_point = std::move(part.global_mesh_point);
  tets = std::move(part.tets);
  const double s = fc.length_scale;
  points = std::move(part.points);
  for (Vec3& point : points) point *= s;
  build_boundaries(part);

  // Node graph of the owned points: neighbours through cells (global numbers), sorted, the node
  // itself included.
  std::vector<std::vector<int>> adjacency(owned);
  for (const Tet& t4 : tets)
    for (int a : t4)
      if (owns(a))
        for (int b : t4) adjacency[a].push_back(local_global[b]);
  node_start.assign(owned + 1, 0);
  for (int a = 0; a < owned; ++a) {
    auto& list = adjacency[a];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    if (list.empty()) list.push_back(local_global[a]);  // a point no tetrahedron uses keeps its own row
    node_start[a + 1] = node_start[a] + static_cast<int>(list.size());
  }
  node_columns.reserve(node_start[owned]);
  for (auto& list : adjacency) {
    node_columns.insert(node_columns.end(), list.begin(), list.end());
    std::vector<int>().swap(list);
  }
  own_start.assign(owned + 1, 0);
  other_start.assign(owned + 1, 0);
  place.resize(node_columns.size());
  for (int a = 0; a < owned; ++a) {
    int own = 0, other = 0;
    for (int k = node_start[a]; k < node_start[a + 1]; ++k)
      place[k] = owned_global(node_columns[k]) ? own++ : other++;
    own_start[a + 1] = own_start[a] + own;
    other_start[a + 1] = other_start[a] + other;
  }
  int widest = 0;
  for (int a = 0; a < owned; ++a) widest = std::max(widest, node_start[a + 1] - node_start[a]);
  if (widest <= 256) {
    tet_slots.resize(tets.size());
    for (size_t e = 0; e < tets.size(); ++e)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          tet_slots[e][a * 4 + b] =
              owns(tets[e][a]) ? static_cast<std::uint8_t>(slot(tets[e][a], tets[e][b]) - node_start[tets[e][a]]) : 0;
  }
  split_for_threads();
}

void NavierStokes::Impl::split_for_threads() {
  // Automatic: the machine's cores on one process; one thread a process under MPI (a process a
  // core is how a cluster job is laid out).
  threads = fc.threads > 0 ? fc.threads : parallel::process_count() > 1 ? 1 : tbb::info::default_concurrency();
  // (More threads than cores: as many ranges, run by the cores; the same result.)
  const int chunks = std::max(1, std::min(threads, owned / 64));
  chunk_begin.assign(1, 0);
  const long long entries = node_start[owned];
  for (int a = 0, k = 1; a < owned && k < chunks; ++a)
    if (static_cast<long long>(node_start[a + 1]) * chunks >= entries * k) {
      chunk_begin.push_back(a + 1);
      ++k;
    }
  chunk_begin.push_back(owned);
  chunk_cells.assign(chunks > 1 ? chunks : 0, {});
  if (chunks > 1) {
    for (size_t e = 0; e < tets.size(); ++e) {
      int last = -1;
      std::array<int, 4> in{};
      for (int a = 0; a < 4; ++a)
        in[a] = owns(tets[e][a]) ? static_cast<int>(std::upper_bound(chunk_begin.begin(), chunk_begin.end(),
                                                                     tets[e][a]) - chunk_begin.begin()) - 1
                                 : -1;
      std::sort(in.begin(), in.end());
      for (int k : in)
        if (k >= 0 && k != last) {
          chunk_cells[k].push_back(static_cast<int>(e));
          last = k;
        }
    }
    arena = std::make_unique<tbb::task_arena>(std::min(threads, tbb::info::default_concurrency()));
  }
}

SparsePattern NavierStokes::Impl::point_pattern() const {
  SparsePattern graph;
  graph.rows = owned;
  graph.first_row = node_begin;
  graph.global_rows = total_points;
  graph.row_start = node_start;
  graph.columns = node_columns;
  graph.ghost_rows.assign(local_global.begin() + owned, local_global.end());
  return graph;
}

// The part's boundary triangles (their points all local, one owned) and its local points' tags.
void NavierStokes::Impl::build_boundaries(const MeshPart& part) {
  const std::map<int, std::string>& tag_name = part.tag_names;
  std::vector<std::string> names;
  for (const auto& [tag, name] : tag_name) names.push_back(name);
  check_tags(fc, names);

  std::map<std::string, int> index;
  for (const BoundaryCondition& c : fc.boundaries) {
    index[c.tag] = static_cast<int>(boundaries.size());
    boundaries.emplace_back();
    boundaries.back().condition = c;
  }
  // Per boundary: its triangles with a point this process owns, counted in sums by the owner of
  // their first point (`counted`), and every local point on it.
  std::vector<std::vector<char>> on(boundaries.size(), std::vector<char>(n(), 0));
  for (const auto& [a, tag] : part.point_tags) on[index.at(tag_name.at(tag))][a] = 1;
  std::vector<std::vector<char>> counted(boundaries.size());
  std::vector<double> sums(7 * boundaries.size(), 0.0);  // area, area-weighted centre, area vector
  for (size_t f = 0; f < part.boundary.size(); ++f) {
    const int k = index.at(tag_name.at(part.boundary_tags[f]));
    const Triangle& tri = part.boundary[f];
    Boundary& b = boundaries[k];
    const Vec3 area2 = (points[tri[1]] - points[tri[0]]).cross(points[tri[2]] - points[tri[0]]);
    const double area = 0.5 * area2.norm();
    b.faces.push_back({tri, area > 0.0 ? Vec3(area2.normalized()) : Vec3::Zero(), area});
    counted[k].push_back(owns(tri[0]) ? 1 : 0);
    if (!owns(tri[0])) continue;
    const Vec3 centre = area * (points[tri[0]] + points[tri[1]] + points[tri[2]]) / 3.0;
    double* sum = &sums[7 * k];
    sum[0] += area;
    for (int i = 0; i < 3; ++i) {
      sum[1 + i] += centre[i];
      sum[4 + i] += 0.5 * area2[i];
    }
  }
  sums = parallel::sum_all(std::move(sums));
  for (size_t k = 0; k < boundaries.size(); ++k) {
    Boundary& b = boundaries[k];
    b.counted = std::move(counted[k]);
    b.area = sums[7 * k];
    b.center = Vec3(sums[7 * k + 1], sums[7 * k + 2], sums[7 * k + 3]);
    b.normal = Vec3(sums[7 * k + 4], sums[7 * k + 5], sums[7 * k + 6]);
    for (int a = 0; a < n(); ++a)
      if (on[k][a]) b.nodes.push_back(a);
  }

  std::vector<char> on_wall(n(), 0);
  for (size_t k = 0; k < boundaries.size(); ++k)
    if (boundaries[k].condition.type == BoundaryType::wall)
      for (int a = 0; a < n(); ++a) on_wall[a] |= on[k][a];
  std::vector<std::vector<char>>().swap(on);

  fixed.assign(kBlock * n(), 0);
  for (Boundary& b : boundaries) {
    if (b.area > 0.0) b.center /= b.area;
    if (b.normal.norm() > 0.0) b.normal.normalize();
    if (b.condition.type == BoundaryType::wall || b.condition.type == BoundaryType::velocity)
      for (int v : b.nodes)
        for (int i = 0; i < 3; ++i) fixed[kBlock * v + i] = 1;
    if (b.condition.type != BoundaryType::velocity) continue;

    // The profile: per point its distance from the end's centre over the radius of a disc of
    // the end's area (wall points: none), each shape scaled to a unit discrete flux (summed over
    // the processes).
    const double radius = std::sqrt(b.area / M_PI);
    std::map<int, int> at;  // local point -> index in b.nodes
    std::vector<double> rho(b.nodes.size(), -1.0);
    for (size_t k = 0; k < b.nodes.size(); ++k) {
      const int v = b.nodes[k];
      at[v] = static_cast<int>(k);
      const Vec3 d = points[v] - b.center;
      if (!on_wall[v]) rho[k] = (d - d.dot(b.normal) * b.normal).norm() / radius;
    }
    const auto unit_flux = [&](auto shape) {  // shape: per node of b.nodes, real or complex
      typename decltype(shape)::value_type flux{};
      for (size_t f = 0; f < b.faces.size(); ++f)
        if (b.counted[f]) {
          const Triangle& v = b.faces[f].v;
          flux += b.faces[f].area / 3.0 * (shape[at[v[0]]] + shape[at[v[1]]] + shape[at[v[2]]]);
        }
      const std::vector<double> total = parallel::sum_all({std::real(flux), std::imag(flux)});
      if constexpr (std::is_same_v<decltype(flux), double>) flux = total[0];
      else flux = Complex(total[0], total[1]);
      if (!(std::abs(flux) > 0.0))
        throw InputError(fmt::format("{}: velocity boundary \"{}\" has no point off the wall: its profile would carry "
                                     "no flow (is the tag on the end's cap?)",
                                     fc.path, b.condition.tag));
      for (auto& value : shape) value /= flux;
      return shape;
    };
    std::vector<double> shape(b.nodes.size(), 0.0);
    for (size_t k = 0; k < b.nodes.size(); ++k)
      if (rho[k] >= 0.0)
        shape[k] = b.condition.profile == Profile::plug ? 1.0 : std::max(0.0, 1.0 - rho[k] * rho[k]);
    b.shape = unit_flux(shape);

    if (b.condition.profile == Profile::womersley) {
      const Womersley w = Womersley::from_waveform(b.condition.flow, b.condition.harmonics, radius, nu);
      b.harmonic_flow = w.coefficients();
      b.omega = w.omega();
      for (int h = 0; h < w.harmonics(); ++h) {
        std::vector<Complex> nodal(b.nodes.size(), Complex(0.0));
        for (size_t k = 0; k < b.nodes.size(); ++k)
          if (rho[k] >= 0.0) nodal[k] = w.shape(h, std::min(1.0, rho[k]));
        b.harmonic_shape.push_back(unit_flux(nodal));
      }
      reporter->info(fmt::format("boundary {}: Womersley profile, alpha {:.3g}, {} harmonics of period {:.4g} s",
                                 b.condition.tag, w.alpha(), w.harmonics() - 1,
                                 w.omega() > 0.0 ? 2.0 * M_PI / w.omega() : 0.0));
    }
  }

  bool natural = false;
  for (const Boundary& b : boundaries)
    natural |= is_natural(b.condition.type);
  if (!natural) {  // the pressure of global point 0, wherever it is local
    for (int a = 0; a < n(); ++a)
      if (local_global[a] == 0) fixed[kBlock * a + 3] = 1;
  }
  resistance_pressure.assign(boundaries.size(), 0.0);
  resistance_coefficient.assign(boundaries.size(), 0.0);
  capacitor_gain.assign(boundaries.size(), 0.0);
  capacitor_base.assign(boundaries.size(), 0.0);
  capacitor_pressure.assign(boundaries.size(), 0.0);
  for (size_t k = 0; k < boundaries.size(); ++k) {
    const BoundaryCondition& c = boundaries[k].condition;
    if (c.type == BoundaryType::rcr) capacitor_pressure[k] = c.initial_pressure.value_or(c.distal_pressure);
    if (c.type == BoundaryType::rcr || c.type == BoundaryType::resistance) resistive.push_back(static_cast<int>(k));
  }
}

void NavierStokes::Impl::set_dirichlet(double time) {
  dirichlet.assign(kBlock * n(), 0.0);
  for (const Boundary& b : boundaries) {
    if (b.condition.type != BoundaryType::velocity) continue;
    const double q = b.condition.flow(time) * 1e-6;  // mL/s -> m3/s, positive into the domain
    std::vector<Complex> phase;
    for (size_t h = 0; h < b.harmonic_flow.size(); ++h)
      phase.push_back(b.harmonic_flow[h] * std::exp(Complex(0.0, static_cast<double>(h) * b.omega * time)));
    for (size_t k = 0; k < b.nodes.size(); ++k) {
      if (b.shape[k] == 0.0) continue;  // wall points keep 0
      double speed = q * b.shape[k];
      if (!phase.empty()) {
        speed = 0.0;
        for (size_t h = 0; h < phase.size(); ++h) speed += (phase[h] * b.harmonic_shape[h][k]).real();
      }
      const Vec3 value = -speed * b.normal;
      for (int i = 0; i < 3; ++i) dirichlet[kBlock * b.nodes[k] + i] = value[i];
    }
  }
}

std::vector<double> NavierStokes::Impl::fluxes(const std::vector<Vec3>& velocity) const {
  std::vector<double> q(boundaries.size(), 0.0);
  for (size_t k = 0; k < boundaries.size(); ++k) {
    const Boundary& b = boundaries[k];
    for (size_t f = 0; f < b.faces.size(); ++f)
      if (b.counted[f]) {
        const BoundaryFace& face = b.faces[f];
        q[k] += face.area / 3.0 * (velocity[face.v[0]] + velocity[face.v[1]] + velocity[face.v[2]]).dot(face.normal);
      }
  }
  return parallel::sum_all(std::move(q));
}

// Implicit coupling: the end's pressure P = R Q (resistance) or P = R_p Q + P_c' (rcr) with the
// outflow Q of the flow being solved, the capacitor by backward Euler, C (P_c' - P_c) / dt = Q -
// (P_c' - P_d) / R_d, so P_c' = g Q + b with g = (dt / C) / (1 + dt / (R_d C)) and b = (P_c + dt
// P_d / (R_d C)) / (1 + dt / (R_d C)): unconditionally stable however small R_d C is against dt (a
// stiff circuit relaxes to its steady P_d + R_d Q, it does not oscillate), exact at steady state
// (g = R_d, b = P_d). Coupled explicitly (P from the last step's Q) several ends of resistances
// far above the vessel's diverged (issue 32's note: 1.00 -> 2.92 in six steady iterations on a Y
// at Murray's resistances); implicitly each solve gives the ends' flows and pressures together.
void NavierStokes::Impl::update_resistance(double dt) {
  for (size_t k = 0; k < boundaries.size(); ++k) {
    const BoundaryCondition& c = boundaries[k].condition;
    if (c.type == BoundaryType::resistance) {
      resistance_coefficient[k] = c.resistance / fc.density;
      resistance_pressure[k] = 0.0;
    }
    if (c.type != BoundaryType::rcr) continue;
    double gain = 0.0, base = capacitor_pressure[k];
    if (fc.steady) {
      gain = c.distal_resistance;
      base = c.distal_pressure;
    } else if (dt > 0.0) {
      const double relax = 1.0 + dt / (c.distal_resistance * c.capacitance);
      gain = dt / c.capacitance / relax;
      base = (capacitor_pressure[k] + dt * c.distal_pressure / (c.distal_resistance * c.capacitance)) / relax;
    }
    capacitor_gain[k] = gain;
    capacitor_base[k] = base;
    resistance_coefficient[k] = (c.proximal_resistance + gain) / fc.density;
    resistance_pressure[k] = base / fc.density;
  }
}

void NavierStokes::Impl::settle_capacitors() {
  bool any = false;
  for (const Boundary& b : boundaries) any |= b.condition.type == BoundaryType::rcr;
  if (!any) return;
  const std::vector<double> q = fluxes(u);
  for (size_t k = 0; k < boundaries.size(); ++k)
    if (boundaries[k].condition.type == BoundaryType::rcr)
      capacitor_pressure[k] = capacitor_gain[k] * q[k] + capacitor_base[k];
}

double NavierStokes::Impl::take_solution(std::vector<Vec3>& velocity, std::vector<double>& pressure) const {
  double change = 0.0, size = 0.0;
  for (int a = 0; a < n(); ++a) {
    const Vec3 v(x[kBlock * a], x[kBlock * a + 1], x[kBlock * a + 2]);
    if (owns(a)) {
      change += (v - velocity[a]).squaredNorm();
      size += v.squaredNorm();
    }
    velocity[a] = v;
    pressure[a] = x[kBlock * a + 3];
  }
  const std::vector<double> sums = parallel::sum_all({change, size});
  return sums[1] > 0.0 ? std::sqrt(sums[0] / sums[1]) : 0.0;
}

std::vector<double> NavierStokes::Impl::state_rows(const std::vector<Vec3>& velocity,
                                                   const std::vector<double>& pressure) const {
  std::vector<double> w(kBlock * n(), 0.0);
  for (int a = 0; a < n(); ++a) {
    for (int i = 0; i < 3; ++i) w[kBlock * a + i] = velocity[a][i];
    w[kBlock * a + 3] = pressure[a];
  }
  return w;
}

double NavierStokes::Impl::steady_residual(const std::vector<double>& w) {
  std::vector<Vec3> velocity(n());
  for (int a = 0; a < n(); ++a) velocity[a] = Vec3(w[kBlock * a], w[kBlock * a + 1], w[kBlock * a + 2]);
  assemble(velocity, std::vector<Vec3>(n(), Vec3::Zero()), 0.0, 0.0);
  return solver->relative_residual(rhs, w);
}

double NavierStokes::Impl::residual_and_assemble(const std::vector<Vec3>& advect, const std::vector<Vec3>& history,
                                                 double pseudo_dt, Linearization linearization, double known) {
  // Before Newton's iterations the steady system's residual at the iterate, assembled in Picard's
  // form as the line search measures its trial flows: Newton's own system gives the same
  // ||A(u) u - b|| but relative to another ||b|| (4.5 % larger on the FDA nozzle at half its
  // inflow, as much as Armijo's test asks of a step cut to 1/16).
  const double newton = linearization == Linearization::picard ? -1.0 : known >= 0.0 ? known : steady_residual(x);
  assemble(advect, history, pseudo_dt > 0.0 ? 1.0 / pseudo_dt : 0.0, pseudo_dt, linearization);
  // Else the system assembled at the iterate, times it, less its right-hand side: the steady
  // residual of the iterate (a pseudo time term cancels there).
  return newton >= 0.0 ? newton : solver->relative_residual(rhs, x);
}

double NavierStokes::Impl::line_search(double before, StepReport& report, double& after) {
  const std::vector<double> newton = x, from = state_rows(u, p);
  const auto assembly = Clock::now();
  double lambda = 1.0;
  for (;; lambda *= 0.5) {
    if (lambda < NavierStokes::kLeastStep) {
      x = newton;
      lambda = 0.0;
      after = -1.0;
      break;
    }
    for (size_t r = 0; r < x.size(); ++r) x[r] = from[r] + lambda * (newton[r] - from[r]);
    after = steady_residual(x);
    if (after < (1.0 - 1e-4 * lambda) * before) break;
  }
  report.assembly_seconds += seconds_since(assembly);
  return lambda;
}

double NavierStokes::Impl::cfl(const std::vector<Vec3>& advect, double dt) const {
  double worst = 0.0;
  for (size_t e = 0; e < tets.size(); ++e) {
    const Tet& t4 = tets[e];
    const Vec3 mean = 0.25 * (advect[t4[0]] + advect[t4[1]] + advect[t4[2]] + advect[t4[3]]);
    double volume = 0.0, largest = 0.0;
    for (const Vec3& g : cell_gradients(e, volume)) largest = std::max(largest, g.norm());
    worst = std::max(worst, mean.norm() * dt * largest);
  }
  const std::vector<double> all = parallel::gather_all(worst);
  return *std::max_element(all.begin(), all.end());
}

double NavierStokes::Impl::assembled_cfl() const {
  const std::vector<double> all = parallel::gather_all(*std::max_element(chunk_cfl.begin(), chunk_cfl.end()));
  return *std::max_element(all.begin(), all.end());
}

std::vector<double> NavierStokes::Impl::gather_points(const std::vector<double>& mine, int width) const {
  const std::vector<double> all = parallel::gather_to_first(mine);
  if (global_mesh_point.empty()) return {};
  std::vector<double> out(all.size());
  for (int g = 0; g < total_points; ++g)
    for (int i = 0; i < width; ++i) out[width * global_mesh_point[g] + i] = all[width * g + i];
  return out;
}

void NavierStokes::Impl::publish() const {
  // Every process's own points placed in a whole-size array, summed over the processes: the
  // whole flow on each (a caller of velocity() need not know which process it is on; 32 bytes a
  // point). The distributed post-processing does without (local_velocity()).
  if (published) return;
  published = true;
  std::vector<double> all(static_cast<size_t>(kBlock) * total_points, 0.0);
  for (int a = 0; a < owned; ++a) {
    double* at = &all[static_cast<size_t>(kBlock) * mesh_point[a]];
    for (int i = 0; i < 3; ++i) at[i] = u[a][i];
    at[3] = p[a] * fc.density;
  }
  all = parallel::sum_all(std::move(all));
  u_mesh.resize(all.size() / kBlock);
  p_mesh.resize(all.size() / kBlock);
  for (size_t k = 0; k < u_mesh.size(); ++k) {
    u_mesh[k] = Vec3(all[kBlock * k], all[kBlock * k + 1], all[kBlock * k + 2]);
    p_mesh[k] = all[kBlock * k + 3];
  }
}

// mass_coefficient: alpha_0 / dt (0 for a steady solve); history: the BDF history over dt.
void NavierStokes::Impl::assemble(const std::vector<Vec3>& advect, const std::vector<Vec3>& history,
                                  double mass_coefficient, double dt, Linearization linearization) {
  const bool newton = linearization != Linearization::picard;
  const bool stabilization_jacobian = linearization == Linearization::full;
  make_solver();
  values = solver->begin_assembly();  // the matrix's own values, zeroed
  rhs.assign(kBlock * owned, 0.0);
  std::vector<double> diagonal(kBlock * owned, 0.0);
  // Per owned point, its share of its elements' momentum diagonal (the Schur complement's
  // preconditioning matrix at the open ends, below).
  std::vector<double> momentum_share(values.schur_own ? owned : 0, 0.0);
  const double m = mass_coefficient;

  // The cells' systems, added to the rows of the owned points in [lo, hi) (a chunk of the
  // threads' split, chunk_cells): each row's in the cells' order, whatever the chunk.
  const int chunks = static_cast<int>(chunk_begin.size()) - 1;
  chunk_cfl.assign(static_cast<size_t>(chunks), 0.0);
  const CellParameters parameters{.mass = m, .dt = dt, .viscosity = nu};
  // Newton's terms on cell (lane l of `cells`)'s system K and right-hand side F.
  const auto add_newton_terms = [&](const CellSystems& cells, int l, const Tet& t4, double K[16][16], double F[16]) {
    const double V = cells.volume[l], tau_m = cells.tau_m[l], tau_c = cells.tau_c[l];
    std::array<Vec3, 4> g;
    double c[4];
    for (int a = 0; a < 4; ++a) {
      g[a] = Vec3(cells.g[a][0][l], cells.g[a][1][l], cells.g[a][2][l]);
      c[a] = cells.c[a][l];
    }
    const Vec3 ubar(cells.ubar[0][l], cells.ubar[1][l], cells.ubar[2][l]);
    const Vec3 hbar(cells.hbar[0][l], cells.hbar[1][l], cells.hbar[2][l]);
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 4; ++a) G += g[a] * g[a].transpose();
    // The element's convection is V/4 (ubar . grad) u in each row, ubar the mean of its corners'
    // velocities: its derivative in u_b beyond the Picard part is V/16 grad u (every a, b), and
    // Newton's right-hand side gains that part applied to the current flow, V/4 (grad u) ubar.
    // The stabilization's terms are tau_m V c_a r (momentum, SUPG) and tau_m V g_a . r
    // (continuity, PSPG), r = m u + (ubar . grad) u + grad p - h the element's strong residual,
    // c_a = ubar . g_a: their derivatives in u_b through ubar (tau_m held; its own derivative
    // below) are tau_m V/4 (g_a[j] r_i + c_a grad(i, j)) and tau_m V/4 (g_a . grad(:, j)),
    // and Newton's right-hand side gains them applied to the current flow. (Without them Newton's
    // iterations converged only linearly where the stabilization weighs: 0.7 a step on a carotid
    // bifurcation at Re 300.)
    Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();  // grad(i, j) = d u_i / d x_j
    Vec3 grad_p = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      grad += advect[t4[a]] * g[a].transpose();
      grad_p += p[t4[a]] * g[a];
    }
    const Vec3 convection = grad * ubar;
    const Vec3 r = m * ubar + convection + grad_p - hbar;
    const double held = stabilization_jacobian ? tau_m : 0.0;
    const Vec3 extra = V / 4.0 * convection;
    // And the parameters' own derivatives (full): tau_m = (time_term + ubar.G ubar + ...)^-1/2
    // gives d tau_m / d u_b = -tau_m^3 G ubar / 4, and, tau_c being 1 / (tau_m tr G),
    // d tau_c / d u_b = tau_c tau_m^2 G ubar / 4: rank-one terms on the SUPG and PSPG rows (their residuals
    // V c_a r and V g_a . r) and the LSIC rows (V g_a div u). (Held, Newton's last steps cut
    // the residual 4-27-fold on a carotid bifurcation at Re 300.)
    const Vec3 dtau = stabilization_jacobian ? Vec3(-tau_m * tau_m * tau_m / 4.0 * (G * ubar)) : Vec3::Zero();
    const double dtau_c_over_dtau = -tau_c / tau_m, divergence = grad.trace(), along = 4.0 * dtau.dot(ubar);
    for (int a = 0; a < 4; ++a) {
      const Vec3 pspg = g[a].transpose() * grad;  // (g_a . grad(:, j))_j
      Vec3 momentum_tau;  // per row i, what multiplies d tau_m / d u_b
      for (int i = 0; i < 3; ++i)
        momentum_tau[i] = V * (c[a] * r[i] + dtau_c_over_dtau * g[a][i] * divergence);
      const double continuity_tau = V * g[a].dot(r);
      for (int b = 0; b < 4; ++b)
        for (int j = 0; j < 3; ++j) {
          for (int i = 0; i < 3; ++i)
            K[4 * a + i][4 * b + j] += V / 16.0 * grad(i, j) + held * V / 4.0 * (g[a][j] * r[i] + c[a] * grad(i, j)) +
                                       momentum_tau[i] * dtau[j];
          K[4 * a + 3][4 * b + j] += held * V / 4.0 * pspg[j] + continuity_tau * dtau[j];
        }
      for (int i = 0; i < 3; ++i)
        F[4 * a + i] += extra[i] + held * V * c[a] * (r[i] + convection[i]) + momentum_tau[i] * along;
      F[4 * a + 3] += held * V * g[a].dot(convection) + continuity_tau * along;
    }
  };
  // Lane l of `cells`'s systems (cell e): into the matrix and right-hand side, moving known
  // Dirichlet values to the right-hand side and giving known rows only their diagonal. (cfl: the
  // chunk's largest cell CFL number so far, a local of its thread's: written to chunk_cfl once
  // the chunk is done, not at each cell, whose other entries share a cache line with it: 13 % of
  // the assembly's samples at 420k unknowns went to that line's passing between the two cores.)
  // (with_newton: std::true_type or std::false_type, each its own code: the entries are read from
  // K or from the lane without a test at each.)
  const auto add_cell = [&](auto with_newton, const CellSystems& cells, int l, size_t e, int lo, int hi, double& cfl) {
    constexpr bool kNewton = decltype(with_newton)::value;
    const Tet& t4 = tets[e];
    if (dt > 0.0) cfl = std::max(cfl, cells.cfl[l]);
    if (values.schur_own)
      for (int a = 0; a < 4; ++a)
        if (t4[a] >= lo && t4[a] < hi) momentum_share[t4[a]] += cells.momentum[l] / 4.0;
    // The cell's system whole where Newton's terms are added to it; else the lane's blocks as they are.
    double K[16][16];
    double F[16];
    if constexpr (kNewton) {
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) K[4 * a + i][4 * b + j] = cells.block[a][b][i][j][l];
            F[4 * a + i] = cells.rhs[a][i][l];
          }
      add_newton_terms(cells, l, t4, K, F);
    }
    const auto block = [&](int a, int b, int i, int j) {
      if constexpr (kNewton) return K[4 * a + i][4 * b + j];
      else return cells.block[a][b][i][j][l];
    };
    const auto cell_rhs = [&](int a, int i) {
      if constexpr (kNewton) return F[4 * a + i];
      else return cells.rhs[a][i][l];
    };
    bool any_fixed = false;
    for (int b = 0; b < 4; ++b)
      for (int j = 0; j < kBlock; ++j) any_fixed = any_fixed || fixed[kBlock * t4[b] + j];
    for (int a = 0; a < 4; ++a) {
      const int na = t4[a];
      if (na < lo || na >= hi) continue;
      const char* row_fixed = &fixed[kBlock * na];
      for (int i = 0; i < kBlock; ++i)
        if (row_fixed[i]) diagonal[kBlock * na + i] += block(a, a, i, i);
        else rhs[kBlock * na + i] += cell_rhs(a, i);
      for (int b = 0; b < 4; ++b) {
        const int nb = t4[b];
        const char* column_fixed = &fixed[kBlock * nb];
        if (values.split) {
          // The field split's blocks: the point pair's entries found once (entry_place's layout,
          // written out), block by block where the cell has no known value (most cells).
          const SplitPairPlace to = pair_entries(na, cell_slot(e, a, b));
          if (!any_fixed) {
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) to.velocity[i + 3 * j] += block(a, b, i, j);
              to.gradient[i * to.count] += block(a, b, i, 3);
            }
            for (int j = 0; j < 3; ++j) to.divergence[j] += block(a, b, 3, j);
            *to.pressure += block(a, b, 3, 3);
            if (to.schur) *to.schur += cells.schur[a][b][l];
            continue;
          }
          for (int i = 0; i < kBlock; ++i) {
            if (row_fixed[i]) continue;
            for (int j = 0; j < kBlock; ++j) {
              if (column_fixed[j]) rhs[kBlock * na + i] -= block(a, b, i, j) * dirichlet[kBlock * nb + j];
              else if (i < 3) (j < 3 ? to.velocity[i + 3 * j] : to.gradient[i * to.count]) += block(a, b, i, j);
              else (j < 3 ? to.divergence[j] : *to.pressure) += block(a, b, i, j);
            }
            if (i == 3 && to.schur && !column_fixed[3]) *to.schur += cells.schur[a][b][l];
          }
          continue;
        }
        for (int i = 0; i < kBlock; ++i) {  // one matrix (a caller's preconditioner other than the field split)
          if (row_fixed[i]) continue;
          const EntryPlace place_b = entry(na, i, cell_slot(e, a, b));
          for (int j = 0; j < kBlock; ++j) {
            if (column_fixed[j]) rhs[kBlock * na + i] -= block(a, b, i, j) * dirichlet[kBlock * nb + j];
            else place_b[j] += block(a, b, i, j);
          }
        }
      }
    }
  };
  // The cells kCellLanes at a time: their corners gathered, the field split's entries of their
  // point pairs fetched into the cache while the systems are worked out (the scatter waited on
  // them), then each cell added in turn.
  const auto add_cells = [&](const int* cell, int count, int lo, int hi, double& cfl) {
    CellCorners corners;
    for (int l = 0; l < kCellLanes; ++l) {
      const Tet& t4 = tets[static_cast<size_t>(cell[std::min(l, count - 1)])];
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) {
          corners.x[a][i][l] = points[t4[a]][i];
          corners.u[a][i][l] = advect[t4[a]][i];
          corners.h[a][i][l] = history[t4[a]][i];
        }
    }
    if (values.split)
      for (int l = 0; l < count; ++l) {
        const size_t e = static_cast<size_t>(cell[l]);
        for (int a = 0; a < 4; ++a) {
          if (tets[e][a] < lo || tets[e][a] >= hi) continue;
          for (int b = 0; b < 4; ++b) {
            const SplitPairPlace to = pair_entries(tets[e][a], cell_slot(e, a, b));
            __builtin_prefetch(to.velocity, 1);
            __builtin_prefetch(to.velocity + 8, 1);
            __builtin_prefetch(to.divergence, 1);
            __builtin_prefetch(to.pressure, 1);
          }
        }
      }
    CellSystems systems;
    stabilized_cells(corners, parameters, systems);
    for (int l = 0; l < count; ++l)
      if (newton) add_cell(std::true_type{}, systems, l, static_cast<size_t>(cell[l]), lo, hi, cfl);
      else add_cell(std::false_type{}, systems, l, static_cast<size_t>(cell[l]), lo, hi, cfl);
  };
  const auto add_chunk = [&](int k) {  // one chunk: every cell in its order
    const size_t cells = chunks == 1 ? tets.size() : chunk_cells[static_cast<size_t>(k)].size();
    const int lo = chunks == 1 ? 0 : chunk_begin[k], hi = chunks == 1 ? owned : chunk_begin[k + 1];
    double cfl = 0.0;
    int group[kCellLanes];
    for (size_t i = 0; i < cells; i += kCellLanes) {
      const int count = static_cast<int>(std::min<size_t>(kCellLanes, cells - i));
      for (int l = 0; l < count; ++l)
        group[l] = chunks == 1 ? static_cast<int>(i) + l : chunk_cells[static_cast<size_t>(k)][i + static_cast<size_t>(l)];
      add_cells(group, count, lo, hi, cfl);
    }
    chunk_cfl[static_cast<size_t>(k)] = cfl;
  };
  if (chunks == 1) add_chunk(0);
  else arena->execute([&] { tbb::parallel_for(0, chunks, add_chunk); });

  // The Schur complement at the open ends: there the velocity's divergence B^T q of a pressure q
  // has a boundary part, q n dS, which the Laplacian above lacks (it leaves a constant pressure
  // free, which the open ends fix); B D^-1 B^T's share of it, per point its (free components')
  // area vector a squared over its momentum diagonal, |a|^2 / D.
  if (values.schur_own) {
    std::vector<Vec3> area(owned, Vec3::Zero());
    for (const Boundary& b : boundaries) {
      if (!is_natural(b.condition.type)) continue;
      for (const BoundaryFace& f : b.faces)
        for (int a = 0; a < 3; ++a)
          if (owns(f.v[a])) area[f.v[a]] += f.area / 3.0 * f.normal;
    }
    for (int a = 0; a < owned; ++a) {
      double squared = 0.0;
      for (int i = 0; i < 3; ++i) squared += fixed[kBlock * a + i] ? 0.0 : area[a][i] * area[a][i];
      if (squared > 0.0 && !fixed[kBlock * a + 3] && momentum_share[a] > 0.0)
        *entry(a, 3, slot(a, a)).schur += squared / momentum_share[a];
    }
  }

  // Natural boundaries: backflow stabilization and the resistance's traction.
  for (size_t k = 0; k < boundaries.size(); ++k) {
    const Boundary& b = boundaries[k];
    if (!is_natural(b.condition.type)) continue;
    for (const BoundaryFace& f : b.faces) {
      const Vec3 mean = (advect[f.v[0]] + advect[f.v[1]] + advect[f.v[2]]) / 3.0;
      const double inflow = std::max(0.0, -mean.dot(f.normal));
      const double beta = 0.5 * fc.backflow * inflow;
      for (int a = 0; a < 3; ++a) {
        const int na = f.v[a];
        if (!owns(na)) continue;
        // Newton's: the term beta(u) M_f u's derivative through beta too, (M_f u)_a,i times
        // d beta / d u_c,j = -backflow n_j / 6 where flow enters, and Newton's right-hand side
        // that part applied to the current flow, beta (M_f u)_a,i (without it Newton's iterations
        // converged linearly wherever a jet reached an open end: 32 iterations against 12 on the
        // nozzle of NavierStokes.NewtonSettlesSuperlinearlyWhereFlowEntersAnOpenEnd).
        Vec3 mass_u = Vec3::Zero();  // (M_f u)_a
        for (int bb = 0; bb < 3; ++bb) mass_u += f.area / 12.0 * (a == bb ? 2.0 : 1.0) * advect[f.v[bb]];
        const bool newton_backflow = newton && beta > 0.0;
        for (int i = 0; i < 3; ++i) {
          const int row = kBlock * na + i;
          if (fixed[row]) continue;
          rhs[row] -= resistance_pressure[k] * f.normal[i] * f.area / 3.0;
          if (beta == 0.0) continue;
          for (int bb = 0; bb < 3; ++bb) {
            const int nb = f.v[bb];
            if (!fixed[kBlock * nb + i]) entry(na, i, slot(na, nb))[i] += beta * f.area / 12.0 * (a == bb ? 2.0 : 1.0);
            if (!newton_backflow) continue;
            for (int j = 0; j < 3; ++j) {
              const double derivative = mass_u[i] * -0.5 * fc.backflow * f.normal[j] / 3.0;
              if (fixed[kBlock * nb + j]) rhs[row] -= derivative * dirichlet[kBlock * nb + j];
              else entry(na, i, slot(na, nb))[j] += derivative;
            }
          }
          if (newton_backflow) rhs[row] += beta * mass_u[i];
        }
      }
    }
  }

  // Dirichlet rows: the diagonal the elements gave them, times the known value.
  for (int a = 0; a < owned; ++a)
    for (int i = 0; i < kBlock; ++i) {
      const int row = kBlock * a + i;
      if (!fixed[row]) continue;
      double d = std::abs(diagonal[row]);
      if (!(d > 0.0)) d = 1.0;
      const EntryPlace diagonal_place = entry(a, i, slot(a, a));
      diagonal_place[i] = d;
      rhs[row] = d * dirichlet[row];
    }
  solver->end_assembly();
  values = MatrixValues{};
  if (!resistive.empty()) {  // the resistive ends' implicit part, as update_resistance left it
    std::vector<double> coefficients;
    for (int k : resistive) coefficients.push_back(resistance_coefficient[k]);
    solver->set_low_rank_coefficients(coefficients);
  }
}

void NavierStokes::Impl::make_solver() {
  if (solver) return;
  const std::string defaults =
      fc.steady ? saddle_point_options() : stokes_start ? stokes_start_options() : time_step_options();
  solver = std::make_unique<LinearSolver>(point_pattern(), kBlock, defaults, fc.petsc_options);
  solver->reuse_preconditioner(!fc.steady && fc.reuse_preconditioner);
  // The resistive ends' columns: per end, at each of its points this process owns, the area
  // vector of its triangles there (a third of each's area times its outward normal) in the free
  // velocity rows, so that a column times the flow is the end's outflow (fluxes()).
  if (!resistive.empty()) {
    std::vector<std::vector<double>> columns;
    for (int k : resistive) {
      std::vector<double> column(kBlock * owned, 0.0);
      for (const BoundaryFace& f : boundaries[k].faces)
        for (int a = 0; a < 3; ++a)
          if (owns(f.v[a]))
            for (int i = 0; i < 3; ++i)
              if (!fixed[kBlock * f.v[a] + i]) column[kBlock * f.v[a] + i] += f.area / 3.0 * f.normal[i];
      columns.push_back(std::move(column));
    }
    solver->set_low_rank_columns(columns);
  }
  // A steady iteration's solve cuts the residual it starts from 1000-fold (saddle_point_options),
  // and does nothing once that residual is a hundredth of the change tolerance (of ||b||): the
  // last iterations cost nothing more, as they did when the tolerance was relative to ||b||.
  if (fc.steady) solver->set_residual_floor(1e-2 * fc.steady_tolerance);
  solver->set_residual_check(fc.steady);
}

void NavierStokes::Impl::solve_system(StepReport& report, const std::string& where, bool direct_fallback,
                                      const std::vector<Vec3>* guess) {
  const auto initial_guess = [&] { x = state_rows(guess ? *guess : u, p); };
  initial_guess();
  const auto start = Clock::now();
  // Once a steady solve has needed the direct solver, the next ones go to it at once (the
  // iterative one would spend its 1000 iterations again).
  SolveStats stats =
      direct_fallback && direct_now ? solver->solve_assembled_direct(rhs, x) : solver->solve_assembled(rhs, x);
  // A solve made again after one that failed, the warning saying why and how; the iterations of
  // both counted.
  const auto again = [&](const char* failed, const char* how, bool direct) {
    reporter->warning(fmt::format("{}: the iterative solver {} ({} after {} iterations): {}", where, failed, stats.reason,
                                  stats.iterations, how));
    const int iterative = stats.iterations;
    initial_guess();
    stats = direct ? solver->solve_assembled_direct(rhs, x) : solver->solve_assembled(rhs, x);
    stats.iterations += iterative;
  };
  // An answer whose true residual missed, or a steady solve that failed (unstable ILU factors of the
  // velocity block: on the FDA nozzle's 1.0M-unknown mesh GMRES broke down after 200 iterations at
  // half the inflow): again with SOR sweeps there, as the iterations after it
  // (LinearSolver::sweep_velocity_blocks).
  if ((stats.true_residual_missed || (!stats.converged && direct_fallback)) && solver->sweep_velocity_blocks())
    again(stats.true_residual_missed ? "missed the answer" : "did not converge",
          "the velocity block's ILU factors may be unstable here; solved again with SOR sweeps instead of them, and "
          "so the steady iterations after it", false);
  if (!stats.converged && direct_fallback && !direct_now &&
      kBlock * total_points <= NavierStokes::kDirectFallbackUnknowns) {
    direct_now = true;
    again("did not converge", "solved directly (MUMPS's LU) instead, and so the steady iterations after it; the "
          "steady preconditioner is weak where convection dominates", true);
  }
  report.solve_seconds += seconds_since(start);
  report.linear_iterations += stats.iterations;
  report.solves += 1;
  report.solver_reason = stats.reason;
  if (!stats.converged)
    throw ComputationError(fmt::format("{}: the linear solver did not converge ({} after {} iterations); the mesh "
                                       "or the time step may be too coarse, or pass other [solver] petsc_options",
                                       where, stats.reason, stats.iterations));
}

void NavierStokes::Impl::check_finite(const StepReport& report) const {
  bool finite = true;
  for (const Vec3& v : u) finite = finite && v.allFinite();
  if (!parallel::any_process(!finite)) return;
  throw ComputationError(fmt::format("step {} (t = {:.6g} s) diverged: the velocity is no longer finite; the CFL "
                                     "number was {:.3g} (above ~1 the semi-implicit scheme may blow up: take a "
                                     "smaller dt), or flow entering through a traction boundary (backflow) grew",
                                     report.step, report.time, report.max_cfl));
}

NavierStokes::NavierStokes(const TetMesh& mesh, const FlowCase& flow_case, const Reporter& reporter)
    : NavierStokes(distribute_mesh(parallel::process_rank() == 0 ? &mesh : nullptr, flow_case.mesh), flow_case, reporter) {}

NavierStokes::NavierStokes(MeshPart part, const FlowCase& flow_case, const Reporter& reporter)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.fc = flow_case;
  s.reporter = &reporter;
  s.nu = flow_case.viscosity / flow_case.density;
  s.build(std::move(part));
  s.u.assign(s.n(), Vec3::Zero());
  s.u_old = s.u;
  s.p.assign(s.n(), 0.0);
  s.published = false;
}

NavierStokes::~NavierStokes() = default;

StepReport NavierStokes::step() {
  Impl& s = *impl_;
  VM_CHECK(!s.fc.steady, "step() on a steady case");
  const auto start = Clock::now();
  StepReport report;
  report.step = s.step_count + 1;
  const double dt = s.fc.dt;
  const double t_next = s.t + dt;
  const bool first = s.step_count == 0;
  const double alpha0 = first ? 1.0 : 1.5;
  std::vector<Vec3> history(s.n()), advect(s.n());
  for (int a = 0; a < s.n(); ++a) {
    history[a] = (first ? s.u[a] : Vec3(2.0 * s.u[a] - 0.5 * s.u_old[a])) / dt;
    advect[a] = first ? s.u[a] : Vec3(2.0 * s.u[a] - s.u_old[a]);
  }
  s.update_resistance(dt);
  s.set_dirichlet(t_next);
  report.time = t_next;

  std::vector<Vec3> next = s.u;
  std::vector<double> next_p = s.p;
  for (int iteration = 0; iteration <= s.fc.picard; ++iteration) {
    const auto assembly = Clock::now();
    s.assemble(advect, history, alpha0 / dt, dt);
    report.assembly_seconds += seconds_since(assembly);
    if (iteration == 0) report.max_cfl = s.assembled_cfl();  // at the extrapolated velocity, as the step convects
    // From the velocity extrapolated to the new time (the convecting one: 2 u^n - u^(n-1) after the
    // first step), whose residual is O(dt^2) where the last step's is O(dt).
    s.solve_system(report, fmt::format("step {} (t = {:.6g} s)", report.step, t_next), false, &advect);
    report.change = s.take_solution(next, next_p);
    advect = next;
  }
  s.u_old = std::move(s.u);
  s.u = std::move(next);
  s.p = std::move(next_p);
  s.settle_capacitors();
  s.t = t_next;
  s.step_count += 1;
  s.published = false;
  report.seconds = seconds_since(start);
  s.check_finite(report);
  return report;
}

std::string NavierStokes::Impl::not_settled(double change) const {
  // What was tried, in the user's words, and the other methods to try next (running in time the last resort).
  const std::string tried =
      fc.newton ? fmt::format("Newton's method (the inflow in stages of {:g}, {:g} and {:g}, each step cut back until the "
                              "residual fell)",
                              kInflowStages[0], kInflowStages[1], kInflowStages[2])
      : fc.pseudo_transient ? std::string("pseudo time steps (their length grown as the flow settled)")
                            : std::string("Picard's iterations");
  std::vector<std::string> next;
  if (!fc.newton) next.push_back("time.steady_method = \"newton\"");
  if (!fc.pseudo_transient) next.push_back("time.steady_method = \"pseudo-transient\"");
  double first = -1.0, least = -1.0, last = -1.0;
  for (const SteadyIteration& k : steady_history)
    if (k.residual >= 0.0) {
      if (first < 0.0) first = k.residual;
      least = least < 0.0 ? k.residual : std::min(least, k.residual);
      last = k.residual;
    }
  const std::string residuals =
      last >= 0.0 ? fmt::format("; its residual went from {:.3g} to {:.3g} (least {:.3g})", first, last, least) : "";
  return fmt::format("the steady solve by {} did not settle in {} iterations (last relative change {:.3g} > {:.3g}{}): "
                     "the flow may be unsteady at this Reynolds number; try {}run the case in time (time.steady = "
                     "false, to an end that washes out the start), or raise time.steady_iterations (summary.json's "
                     "steady_history holds every iteration)",
                     tried, fc.steady_iterations, change, fc.steady_tolerance, residuals,
                     next.empty() ? std::string() : fmt::format("{}, ", fmt::join(next, " or ")));
}

const std::vector<SteadyIteration>& NavierStokes::steady_history() const { return impl_->steady_history; }

void NavierStokes::Impl::start_next_stage(size_t stage, std::vector<Vec3>& stage_u, std::vector<double>& stage_p) {
  // A secant through this stage's flow and the last one's (from rest, zero flow at zero inflow,
  // for the first), taken to the next stage's inflow.
  const auto& stages = NavierStokes::kInflowStages;
  const double before = stage > 0 ? stages[stage - 1] : 0.0, now = stages[stage];
  const double factor = (stages[stage + 1] - now) / (now - before);
  for (int a = 0; a < n(); ++a) {
    const Vec3 was = u[a];
    const double was_p = p[a];
    u[a] += factor * (was - stage_u[a]);
    p[a] += factor * (was_p - stage_p[a]);
    stage_u[a] = was;
    stage_p[a] = was_p;
  }
  x = state_rows(u, p);
}

StepReport NavierStokes::solve_steady() {
  Impl& s = *impl_;
  const auto start = Clock::now();
  StepReport report;
  // Newton's iterations (fc.newton) go up the inflow in stages (NavierStokes::kInflowStages): each
  // stage's flow, to a loose change, extrapolated to the next one's start (below: the residual
  // there 0.06-0.2 instead of the 0.5 of the last stage's flow with the new inflow).
  size_t stage = s.fc.newton ? 0 : kInflowStages.size() - 1;
  s.steady_history.clear();
  int linear_before = 0;  // the linear iterations before this iteration's (report's are the solve's)
  const auto set_inflow = [&] {
    s.set_dirichlet(0.0);
    for (size_t row = 0; row < s.dirichlet.size(); ++row)
      if (s.fixed[row]) s.dirichlet[row] *= kInflowStages[stage];
  };
  set_inflow();
  std::vector<Vec3> advect(s.n(), Vec3::Zero()), none(s.n(), Vec3::Zero());
  std::vector<Vec3> stage_u(s.n(), Vec3::Zero());  // the last stage's flow (rest before the first)
  std::vector<double> stage_p(s.n(), 0.0);
  // Pseudo time steps (pseudo_transient): the step length, 0 for a Picard iteration (the first
  // iteration the Stokes solve either way). known: the iterate's steady residual, where a line search measured it.
  double pseudo_dt = 0.0, last_rate = 0.0, resume_dt = 0.0, known = -1.0;
  bool settled = false;
  using Linearization = Impl::Linearization;
  Linearization level = Linearization::picard;  // the Stokes solve, then Newton's (fc.newton) or Picard's
  s.direct_now = false;
  for (int iteration = 0; iteration < s.fc.steady_iterations; ++iteration) {
    s.update_resistance(0.0);
    const double used_dt = pseudo_dt;
    const auto assembly = Clock::now();
    std::vector<Vec3> history = none;
    if (pseudo_dt > 0.0)
      for (int a = 0; a < s.n(); ++a) history[a] = s.u[a] / pseudo_dt;
    const double residual = iteration > 0 ? s.residual_and_assemble(advect, history, pseudo_dt, level, known) : -1.0;
    if (iteration == 0) s.assemble(advect, history, 0.0, 0.0, level);
    report.assembly_seconds += seconds_since(assembly);
    const auto name = [](Linearization l) {
      return l == Linearization::full         ? "Newton iteration"
             : l == Linearization::convection ? "Newton iteration on the convection"
                                              : "Picard iteration";
    };
    const std::string what = pseudo_dt > 0.0 ? "pseudo time step" : name(level);
    // The Stokes solve from rest 1000 times tighter than the iterations after it (to 1e-6 of ||b||
    // by default): a loose start costs more in the Picard iterations it adds (measured: 260 linear
    // iterations against 175 on a 117k-unknown pipe, 114 when the solves stopped at 1e-6 of ||b|| and
    // the residual with them).
    s.solver->scale_tolerance(iteration == 0 ? 1e-3 : 1.0);
    s.solve_system(report, fmt::format("steady {} {}", what, iteration + 1), /*direct_fallback=*/true);
    // Newton's step cut back until the residual falls; where none does (far from the answer,
    // where the linearization misleads), the iteration again from the same flow with the
    // linearization below (Newton's on the convection alone, then Picard's), from which the next
    // iteration goes up again after a whole step.
    double lambda = 1.0;
    double reached = -1.0;  // the steady residual of the state taken, where the line search measured it
    std::string taken;
    if (level != Linearization::picard) {
      lambda = s.line_search(residual, report, reached);
      while (lambda == 0.0) {
        taken += ", its step raised the residual";
        level = level == Linearization::full ? Linearization::convection : Linearization::picard;
        const auto again = Clock::now();
        s.assemble(advect, history, 0.0, 0.0, level);
        report.assembly_seconds += seconds_since(again);
        s.solve_system(report, fmt::format("steady {} {} (again)", name(level), iteration + 1), true);
        lambda = level == Linearization::picard ? 1.0 : s.line_search(residual, report, reached);
        taken += fmt::format(": a {} instead", name(level));
      }
      if (lambda < 1.0) taken += fmt::format(", its step times {:g}", lambda);
    }
    report.change = s.take_solution(s.u, s.p);
    known = reached;  // the state taken is the line search's last trial
    s.published = false;
    report.step = iteration + 1;
    s.check_finite(report);
    s.reporter->info(fmt::format("steady iteration {} ({}{}{}{}): {}velocity change {:.3e}, {} linear iterations",
                                 iteration + 1, what,
                                 stage + 1 < kInflowStages.size()
                                     ? fmt::format(" at {:g} of the inflow", kInflowStages[stage])
                                     : "",
                                 taken,
                                 pseudo_dt > 0.0 ? fmt::format(", CFL {:.3g}", s.cfl(advect, pseudo_dt)) : "",
                                 residual >= 0.0 ? fmt::format("residual before it {:.3e}, ", residual) : "",
                                 report.change, report.linear_iterations));
    s.steady_history.push_back({iteration + 1, iteration == 0 ? std::string("Stokes") : what + taken,
                                kInflowStages[stage], residual, report.change,
                                report.linear_iterations - linear_before});
    linear_before = report.linear_iterations;
    advect = s.u;
    // Newton's iterations (fc.newton) from the first after the Stokes solve, on the convection;
    // after a whole step, with the stabilization's terms too (near the answer superlinear: 9, 99
    // and 1040-fold on the bend of the tests, where the convection's alone converged linearly, 0.7
    // a step on a carotid bifurcation at Re 300).
    if (s.fc.newton && lambda == 1.0)
      level = level == Linearization::picard ? Linearization::convection : Linearization::full;
    // Settled when the step (Newton's whole step where it was cut back) is under the tolerance; a
    // stage below the whole inflow when it is under kStageTolerance: the next stage from its flow.
    const double step_change = report.change / (lambda > 0.0 ? lambda : 1.0);
    if (stage + 1 < kInflowStages.size() && iteration > 0 && step_change < kStageTolerance) {
      s.start_next_stage(stage, stage_u, stage_p);
      known = -1.0;
      advect = s.u;
      ++stage;
      set_inflow();
      continue;
    }
    // (Or when the residual Newton's step reached is under the tolerance: no iteration to confirm it.)
    const bool small = stage + 1 == kInflowStages.size() &&
                       (step_change < s.fc.steady_tolerance || (reached >= 0.0 && reached < s.fc.steady_tolerance));
    if (!s.fc.pseudo_transient) {
      if (iteration > 0 && small) {
        settled = true;
        break;
      }
      continue;
    }
    if (iteration > 0 && pseudo_dt == 0.0 && small) {  // a Picard iteration confirmed it
      settled = true;
      break;
    }
    if (iteration > 0 && pseudo_dt > 0.0 && small) {
      resume_dt = pseudo_dt;  // confirm with a Picard iteration
      pseudo_dt = 0.0;
    } else if (iteration == 0 || pseudo_dt == 0.0) {
      // After Stokes a step at kPseudoCflStart (cfl() is linear in the step); after a Picard
      // iteration that did not confirm, the step before it.
      const double cfl_per_second = s.cfl(advect, 1.0);
      pseudo_dt = resume_dt > 0.0 ? resume_dt : cfl_per_second > 0.0 ? kPseudoCflStart / cfl_per_second : 0.0;
    } else {
      // The change per unit pseudo time measures the steady residual: lengthen the step by the
      // rate's fall (at least 1.2x while it falls, at most 2x), shorten it (at most 2x) when it
      // rises.
      const double rate = report.change / used_dt;
      if (last_rate > 0.0)
        pseudo_dt *= rate <= last_rate ? std::clamp(last_rate / rate, 1.2, 2.0) : std::max(0.5, last_rate / rate);
    }
    last_rate = used_dt > 0.0 ? report.change / used_dt : 0.0;
  }
  if (!settled) throw ComputationError(s.not_settled(report.change));
  // The answer's residual: the steady system assembled at it once more (Picard's form).
  s.update_resistance(0.0);
  const auto assembly = Clock::now();
  s.assemble(s.u, none, 0.0, 0.0);
  report.assembly_seconds += seconds_since(assembly);
  report.residual = s.solver->relative_residual(s.rhs, s.x);
  s.settle_capacitors();  // P_d + R_d Q at the answer
  s.reporter->info(fmt::format("steady residual {:.3e} (relative: ||A(u) u - b|| / ||b||) after {} iterations",
                               report.residual, report.step));
  report.seconds = seconds_since(start);
  return report;
}

StepReport NavierStokes::start_from_stokes() {
  Impl& s = *impl_;
  const auto start = Clock::now();
  StepReport report;
  s.update_resistance(0.0);
  s.set_dirichlet(s.t);
  const std::vector<Vec3> none(s.n(), Vec3::Zero());
  const auto assembly = Clock::now();
  s.solver.reset();
  s.stokes_start = true;
  // With the time steps' stabilization parameter (tau_M's 4/dt^2 term; no mass term): the
  // viscous limit's tau_M, 20 times theirs on a 0.48 mm pipe at dt 1 ms, relaxed the continuity
  // equation's PSPG part so differently that the first step had to project the flow anew, its
  // pressure a spike (inlet 30.3 Pa, then 2.4, 11.4 against 11.4 settled) and its solves 13-23
  // iterations; now 11.39, 11.34, 11.36 and 11-16.
  s.assemble(none, none, 0.0, s.fc.dt);
  s.stokes_start = false;
  report.assembly_seconds = seconds_since(assembly);
  s.solve_system(report, fmt::format("the Stokes start (t = {:.6g} s)", s.t));
  // The time steps' system has a mass term: a new solver for it, made once this one is gone (its
  // preconditioner and the Stokes solve's Krylov vectors: 250 MB of the peak at 420k unknowns).
  s.solver.reset();
  report.change = s.take_solution(s.u, s.p);
  s.published = false;
  s.u_old = s.u;
  s.step_count = 0;
  report.time = s.t;
  report.seconds = seconds_since(start);
  s.check_finite(report);
  return report;
}

void NavierStokes::set_state(const std::vector<Vec3>& velocity, double time) {
  Impl& s = *impl_;
  if (static_cast<int>(velocity.size()) != s.total_points)
    throw InputError(fmt::format("initial velocity: {} values for {} points", velocity.size(), s.total_points));
  for (int k = 0; k < s.n(); ++k) s.u[k] = velocity[s.mesh_point[k]];
  s.u_old = s.u;
  s.published = false;
  s.t = time;
  s.step_count = 0;
}

FlowState NavierStokes::state() const {
  const Impl& s = *impl_;
  FlowState out = own_state();  // its fields gathered whole onto the first process
  std::vector<double> mine(7 * s.owned);
  for (int k = 0; k < s.owned; ++k) {
    for (int i = 0; i < 3; ++i) {
      mine[7 * k + i] = out.velocity[k][i];
      mine[7 * k + 3 + i] = out.previous[k][i];
    }
    mine[7 * k + 6] = out.kinematic_pressure[k];
  }
  out.points.clear();
  const std::vector<double> all = s.gather_points(mine, 7);
  const size_t n = all.size() / 7;
  out.velocity.resize(n);
  out.previous.resize(n);
  out.kinematic_pressure.resize(n);
  for (size_t k = 0; k < n; ++k) {
    out.velocity[k] = Vec3(all[7 * k], all[7 * k + 1], all[7 * k + 2]);
    out.previous[k] = Vec3(all[7 * k + 3], all[7 * k + 4], all[7 * k + 5]);
    out.kinematic_pressure[k] = all[7 * k + 6];
  }
  return out;
}

FlowState NavierStokes::own_state() const {
  const Impl& s = *impl_;
  FlowState out;
  out.time = s.t;
  out.steps = s.step_count;
  out.capacitor_pressure = s.capacitor_pressure;
  out.points.assign(s.mesh_point.begin(), s.mesh_point.begin() + s.owned);
  out.velocity.assign(s.u.begin(), s.u.begin() + s.owned);
  out.previous.assign(s.u_old.begin(), s.u_old.begin() + s.owned);
  out.kinematic_pressure.assign(s.p.begin(), s.p.begin() + s.owned);
  return out;
}

const std::vector<int>& NavierStokes::local_points() const { return impl_->mesh_point; }

void NavierStokes::restore(const FlowState& state) {
  Impl& s = *impl_;
  const size_t n = state.points.empty() ? static_cast<size_t>(s.total_points) : state.points.size();
  if (state.velocity.size() != n || state.previous.size() != n || state.kinematic_pressure.size() != n)
    throw InputError(fmt::format("the saved state has {} points, the mesh {}", state.velocity.size(), n));
  if (state.capacitor_pressure.size() != s.boundaries.size())
    throw InputError(fmt::format("the saved state has {} boundaries, the case {}", state.capacitor_pressure.size(),
                                 s.boundaries.size()));
  // Per local point its entry of the state.
  std::vector<int> entry(s.n());
  if (state.points.empty()) {
    entry = s.mesh_point;
  } else {
    std::vector<int> order(n);
    for (size_t k = 0; k < n; ++k) order[k] = static_cast<int>(k);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return state.points[a] < state.points[b]; });
    for (int k = 0; k < s.n(); ++k) {
      const auto it = std::lower_bound(order.begin(), order.end(), s.mesh_point[k],
                                       [&](int e, int m) { return state.points[e] < m; });
      if (it == order.end() || state.points[*it] != s.mesh_point[k])
        throw InputError(fmt::format("the saved state has no values at mesh point {}", s.mesh_point[k]));
      entry[k] = *it;
    }
  }
  s.capacitor_pressure = state.capacitor_pressure;
  for (int k = 0; k < s.n(); ++k) {
    s.u[k] = state.velocity[entry[k]];
    s.u_old[k] = state.previous[entry[k]];
    s.p[k] = state.kinematic_pressure[entry[k]];
  }
  s.t = state.time;
  s.step_count = state.steps;
  s.published = false;
}

double NavierStokes::time() const { return impl_->t; }
int NavierStokes::steps() const { return impl_->step_count; }
int NavierStokes::dofs() const { return kBlock * impl_->total_points; }
const std::vector<Vec3>& NavierStokes::velocity() const {
  impl_->publish();
  return impl_->u_mesh;
}
const std::vector<double>& NavierStokes::pressure() const {
  impl_->publish();
  return impl_->p_mesh;
}
const std::vector<Vec3>& NavierStokes::local_velocity() const { return impl_->u; }
std::vector<double> NavierStokes::local_pressure() const {
  std::vector<double> pressure(impl_->p.size());
  for (size_t a = 0; a < pressure.size(); ++a) pressure[a] = impl_->p[a] * impl_->fc.density;
  return pressure;
}

std::vector<BoundaryFlow> NavierStokes::boundary_flows() const {
  const Impl& s = *impl_;
  std::vector<double> weighted(s.boundaries.size(), 0.0);
  for (size_t k = 0; k < s.boundaries.size(); ++k) {
    const Boundary& b = s.boundaries[k];
    for (size_t f = 0; f < b.faces.size(); ++f)
      if (b.counted[f]) {
        const BoundaryFace& face = b.faces[f];
        weighted[k] += face.area / 3.0 * (s.p[face.v[0]] + s.p[face.v[1]] + s.p[face.v[2]]);
      }
  }
  weighted = parallel::sum_all(std::move(weighted));
  const std::vector<double> q = s.fluxes(s.u);
  std::vector<BoundaryFlow> out;
  for (size_t k = 0; k < s.boundaries.size(); ++k) {
    const Boundary& b = s.boundaries[k];
    BoundaryFlow f;
    f.tag = b.condition.tag;
    f.flux = q[k];
    f.area = b.area;
    f.mean_pressure = b.area > 0.0 ? weighted[k] / b.area * s.fc.density : 0.0;
    f.capacitor_pressure = s.capacitor_pressure[k];
    out.push_back(f);
  }
  return out;
}

PartitionReport NavierStokes::partition() const {
  const Impl& s = *impl_;
  const int ranks = parallel::process_count();
  std::vector<int> owners;  // the processes owning this process's ghosts
  for (int a = s.owned; a < s.n(); ++a)
    owners.push_back(static_cast<int>(std::upper_bound(s.process_begin.begin(), s.process_begin.end(),
                                                       s.local_global[a]) -
                                      s.process_begin.begin()) -
                     1);
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
  const std::vector<double> ghosts = parallel::gather_all(s.n() - s.owned);
  const std::vector<double> neighbours = parallel::gather_all(static_cast<double>(owners.size()));
  PartitionReport out;
  out.threads = s.threads;
  for (int r = 0; r < ranks; ++r) {
    out.owned_points.push_back(s.process_begin[r + 1] - s.process_begin[r]);
    out.ghost_points.push_back(static_cast<int>(ghosts[r]));
    out.neighbours.push_back(static_cast<int>(neighbours[r]));
  }
  return out;
}

std::string NavierStokes::solver_description() const {
  return impl_->solver ? impl_->solver->description() : "(no solve yet)";
}

}  // namespace vesselmesh::flow
