#include "flow/navier_stokes.h"

#include "flow/womersley.h"
#include "mesh/error.h"
#include "mesh/reorder.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

namespace vesselmesh::flow {
namespace {

constexpr int kBlock = 4;     // u, v, w, p per node
constexpr double kCI = 36.0;  // inverse-estimate constant of linear tetrahedra

using Clock = std::chrono::steady_clock;

// The first of the points process `rank` of `ranks` owns (consecutive ranges of equal size).
int range_begin(int points, int rank, int ranks) {
  return static_cast<int>(static_cast<long long>(points) * rank / ranks);
}
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// What a boundary triangle needs: its points, outward unit normal and area (SI).
struct BoundaryFace {
  Triangle v;
  Vec3 normal;
  double area;
};

// One tagged boundary and its condition.
struct Boundary {
  BoundaryCondition condition;
  std::vector<BoundaryFace> faces;
  std::vector<int> nodes;  // every point of its faces
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
  std::vector<Vec3> points;  // m
  std::vector<Tet> tets;
  std::vector<std::array<Vec3, 4>> gradients;
  std::vector<double> volumes;
  std::vector<double> least_height;
  // Node graph (sorted neighbours, self included) and each tet's 16 positions in it.
  std::vector<int> node_start, node_columns;
  std::vector<std::array<int, 16>> tet_slots;
  SparsePattern pattern;  // sizes only (no columns: the solver has them)
  int nonzeros = 0;       // this process's matrix entries
  SparsePattern columns_pattern() const;
  std::vector<Boundary> boundaries;
  std::vector<char> fixed;  // per dof: Dirichlet
  std::unique_ptr<LinearSolver> solver;

  // The solver's own numbering of the points (mesh::cuthill_mckee_order: neighbours near each
  // other in memory, and each process's consecutive range a compact piece of the lumen):
  // mesh_point[k] is the mesh's number of point k; everything inside is in this numbering, the
  // public interface in the mesh's.
  std::vector<int> mesh_point;
  std::vector<Vec3> u_mesh;  // u in the mesh's numbering (velocity())
  void publish() {
    u_mesh.resize(u.size());
    for (size_t k = 0; k < u.size(); ++k) u_mesh[mesh_point[k]] = u[k];
  }

  // State.
  double t = 0.0;
  int step_count = 0;
  std::vector<Vec3> u, u_old;  // u^n, u^{n-1}
  std::vector<double> p;       // kinematic pressure p / rho
  std::vector<double> rhs, x, dirichlet;
  void make_solver();
  std::vector<double> resistance_pressure;  // per boundary: Pa / rho, from the last step's outflow

  int n() const { return static_cast<int>(points.size()); }

  // This process's rows: the points node_begin .. node_end (all of them on one process).
  int node_begin = 0, node_end = 0, first_row = 0, value_base = 0;
  bool owns(int a) const { return a >= node_begin && a < node_end; }

  // Offset (among this process's values) of entry (node a's component i, node b's component
  // j) from a's position k of b, j = 0.
  int value_index(int a, int i, int k) const {
    const int degree = node_start[a + 1] - node_start[a];
    return kBlock * kBlock * node_start[a] + i * kBlock * degree + kBlock * (k - node_start[a]) - value_base;
  }
  // Position of b among a's neighbours in the node graph.
  int slot(int a, int b) const {
    const auto first = node_columns.begin() + node_start[a], last = node_columns.begin() + node_start[a + 1];
    return static_cast<int>(std::lower_bound(first, last, b) - node_columns.begin());
  }

  void build(const TetMesh& mesh);
  void build_boundaries(const TetMesh& mesh);
  void set_dirichlet(double time);
  void assemble(const std::vector<Vec3>& advect, const std::vector<Vec3>& history, double mass_coefficient,
                double dt);
  void solve_system(StepReport& report, const std::string& where);
  double cfl(const std::vector<Vec3>& advect, double dt) const;
  double flux(const Boundary& b, const std::vector<Vec3>& velocity) const;
  // The resistance boundaries' pressure (over rho) from the current outflow.
  void update_resistance();
  // Copies the solved x into velocity and pressure; returns the velocity's relative change.
  double take_solution(std::vector<Vec3>& velocity, std::vector<double>& pressure) const;
  void check_finite(const StepReport& report) const;
};

void NavierStokes::Impl::build(const TetMesh& mesh) {
  const double s = fc.length_scale;
  points.resize(mesh.points.size());
  for (size_t i = 0; i < points.size(); ++i) points[i] = mesh.points[i] * s;
  tets = mesh::all_tetrahedra(mesh);
  if (tets.empty()) throw InputError(fmt::format("{}: the mesh has no tetrahedra", fc.mesh));

  gradients.resize(tets.size());
  volumes.resize(tets.size());
  least_height.resize(tets.size());
  for (size_t e = 0; e < tets.size(); ++e) {
    const Tet& t4 = tets[e];
    double v6 = 0.0;
    gradients[e] = mesh::barycentric_gradients(points[t4[0]], points[t4[1]], points[t4[2]], points[t4[3]], v6);
    if (!(v6 > 0.0))
      throw InputError(fmt::format("{}: the tetrahedron of points {}, {}, {}, {} is inverted or flat (six times its "
                                   "volume {:.3g} m3, at ({:.4g}, {:.4g}, {:.4g}) in mesh units): mend the mesh first",
                                   fc.mesh, mesh_point[t4[0]], mesh_point[t4[1]], mesh_point[t4[2]],
                                   mesh_point[t4[3]], v6, mesh.points[t4[0]].x(), mesh.points[t4[0]].y(),
                                   mesh.points[t4[0]].z()));
    volumes[e] = v6 / 6.0;
    double largest = 0.0;
    for (const Vec3& g : gradients[e]) largest = std::max(largest, g.norm());
    least_height[e] = 1.0 / largest;
  }

  // Node graph: neighbours through tetrahedra, sorted, the node itself included.
  const int nn = n();
  std::vector<std::vector<int>> adjacency(nn);
  for (const Tet& t4 : tets)
    for (int a : t4)
      for (int b : t4) adjacency[a].push_back(b);
  node_start.assign(nn + 1, 0);
  for (int a = 0; a < nn; ++a) {
    auto& list = adjacency[a];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    if (list.empty()) list.push_back(a);  // a point no tetrahedron uses keeps its own row
    node_start[a + 1] = node_start[a] + static_cast<int>(list.size());
  }
  node_columns.reserve(node_start[nn]);
  for (auto& list : adjacency) {
    node_columns.insert(node_columns.end(), list.begin(), list.end());
    std::vector<int>().swap(list);
  }
  tet_slots.resize(tets.size());
  for (size_t e = 0; e < tets.size(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) tet_slots[e][a * 4 + b] = slot(tets[e][a], tets[e][b]);

  // This process's points: consecutive ranges of equal size over the processes.
  const int ranks = process_count(), rank = process_rank();
  node_begin = range_begin(nn, rank, ranks);
  node_end = range_begin(nn, rank + 1, ranks);
  first_row = kBlock * node_begin;
  value_base = kBlock * kBlock * node_start[node_begin];

  // The dof pattern's sizes; its columns are made when the solver is (columns_pattern()).
  pattern.rows = kBlock * (node_end - node_begin);
  pattern.first_row = first_row;
  pattern.global_rows = kBlock * nn;
  nonzeros = kBlock * kBlock * (node_start[node_end] - node_start[node_begin]);
}

// The dof pattern whole: row (a, i) holds every neighbour's four components. Made for the linear
// solver, which keeps it (the assembly finds its places from the node graph).
SparsePattern NavierStokes::Impl::columns_pattern() const {
  SparsePattern full = pattern;
  full.row_start.assign(pattern.rows + 1, 0);
  full.columns.resize(nonzeros);
  for (int a = node_begin; a < node_end; ++a)
    for (int i = 0; i < kBlock; ++i) {
      const int row = kBlock * a + i - first_row;
      int at = value_index(a, i, node_start[a]);
      full.row_start[row] = at;
      for (int k = node_start[a]; k < node_start[a + 1]; ++k)
        for (int j = 0; j < kBlock; ++j) full.columns[at++] = kBlock * node_columns[k] + j;
      full.row_start[row + 1] = at;
    }
  return full;
}

void NavierStokes::Impl::build_boundaries(const TetMesh& mesh) {
  const std::map<int, std::string> tag_name = mesh::boundary_tag_names(mesh);
  std::vector<std::string> names;
  for (const auto& [tag, name] : tag_name) names.push_back(name);
  check_tags(fc, names);

  std::map<std::string, int> index;
  for (const BoundaryCondition& c : fc.boundaries) {
    index[c.tag] = static_cast<int>(boundaries.size());
    boundaries.emplace_back();
    boundaries.back().condition = c;
  }
  for (size_t f = 0; f < mesh.boundary.size(); ++f) {
    Boundary& b = boundaries[index.at(tag_name.at(mesh.boundary_tags[f]))];
    const Triangle& tri = mesh.boundary[f];
    const Vec3 area2 = (points[tri[1]] - points[tri[0]]).cross(points[tri[2]] - points[tri[0]]);
    const double area = 0.5 * area2.norm();
    b.faces.push_back({tri, area > 0.0 ? Vec3(area2.normalized()) : Vec3::Zero(), area});
    b.area += area;
    b.center += area * (points[tri[0]] + points[tri[1]] + points[tri[2]]) / 3.0;
    b.normal += 0.5 * area2;
  }

  std::vector<char> on_wall(n(), 0);
  for (const Boundary& b : boundaries)
    if (b.condition.type == BoundaryType::wall)
      for (const BoundaryFace& f : b.faces)
        for (int v : f.v) on_wall[v] = 1;

  fixed.assign(pattern.total_rows(), 0);
  for (Boundary& b : boundaries) {
    std::set<int> nodes;
    for (const BoundaryFace& f : b.faces) nodes.insert(f.v.begin(), f.v.end());
    b.nodes.assign(nodes.begin(), nodes.end());
    if (b.area > 0.0) b.center /= b.area;
    if (b.normal.norm() > 0.0) b.normal.normalize();
    if (b.condition.type == BoundaryType::wall || b.condition.type == BoundaryType::velocity)
      for (int v : b.nodes)
        for (int i = 0; i < 3; ++i) fixed[kBlock * v + i] = 1;
    if (b.condition.type != BoundaryType::velocity) continue;

    // The profile: per point its distance from the end's centre over the radius of a disc of
    // the end's area (wall points: none), each shape scaled to a unit discrete flux.
    const double radius = std::sqrt(b.area / M_PI);
    std::map<int, int> local;  // point -> index in b.nodes
    std::vector<double> rho(b.nodes.size(), -1.0);
    for (size_t k = 0; k < b.nodes.size(); ++k) {
      const int v = b.nodes[k];
      local[v] = static_cast<int>(k);
      const Vec3 d = points[v] - b.center;
      if (!on_wall[v]) rho[k] = (d - d.dot(b.normal) * b.normal).norm() / radius;
    }
    const auto unit_flux = [&](auto shape) {  // shape: per node of b.nodes, real or complex
      auto flux = shape[0] * 0.0;
      for (const BoundaryFace& f : b.faces)
        flux += f.area / 3.0 * (shape[local[f.v[0]]] + shape[local[f.v[1]]] + shape[local[f.v[2]]]);
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
    natural |= b.condition.type == BoundaryType::traction || b.condition.type == BoundaryType::resistance;
  if (!natural) {
    fixed[3] = 1;  // point 0's pressure
  }
  resistance_pressure.assign(boundaries.size(), 0.0);
}

void NavierStokes::Impl::set_dirichlet(double time) {
  dirichlet.assign(pattern.total_rows(), 0.0);
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

double NavierStokes::Impl::flux(const Boundary& b, const std::vector<Vec3>& velocity) const {
  double q = 0.0;
  for (const BoundaryFace& f : b.faces)
    q += f.area / 3.0 * (velocity[f.v[0]] + velocity[f.v[1]] + velocity[f.v[2]]).dot(f.normal);
  return q;
}

void NavierStokes::Impl::update_resistance() {
  for (size_t k = 0; k < boundaries.size(); ++k)
    if (boundaries[k].condition.type == BoundaryType::resistance)
      resistance_pressure[k] = boundaries[k].condition.resistance * flux(boundaries[k], u) / fc.density;
}

double NavierStokes::Impl::take_solution(std::vector<Vec3>& velocity, std::vector<double>& pressure) const {
  double change = 0.0, size = 0.0;
  for (int a = 0; a < n(); ++a) {
    const Vec3 v(x[kBlock * a], x[kBlock * a + 1], x[kBlock * a + 2]);
    change += (v - velocity[a]).squaredNorm();
    size += v.squaredNorm();
    velocity[a] = v;
    pressure[a] = x[kBlock * a + 3];
  }
  return size > 0.0 ? std::sqrt(change / size) : 0.0;
}

double NavierStokes::Impl::cfl(const std::vector<Vec3>& advect, double dt) const {
  double worst = 0.0;
  for (size_t e = 0; e < tets.size(); ++e) {
    const Tet& t4 = tets[e];
    const Vec3 mean = 0.25 * (advect[t4[0]] + advect[t4[1]] + advect[t4[2]] + advect[t4[3]]);
    worst = std::max(worst, mean.norm() * dt / least_height[e]);
  }
  return worst;
}

// mass_coefficient: alpha_0 / dt (0 for a steady solve); history: the BDF history over dt.
void NavierStokes::Impl::assemble(const std::vector<Vec3>& advect, const std::vector<Vec3>& history,
                                  double mass_coefficient, double dt) {
  make_solver();
  double* const values = solver->begin_assembly();  // the matrix's own values, zeroed
  rhs.assign(pattern.rows, 0.0);
  std::vector<double> diagonal(pattern.rows, 0.0);
  const double m = mass_coefficient;
  const double time_term = dt > 0.0 ? 4.0 / (dt * dt) : 0.0;

  double K[16][16];
  double F[16];
  for (size_t e = 0; e < tets.size(); ++e) {
    const Tet& t4 = tets[e];
    if (!owns(t4[0]) && !owns(t4[1]) && !owns(t4[2]) && !owns(t4[3])) continue;
    const auto& g = gradients[e];
    const double V = volumes[e];
    Vec3 ubar = Vec3::Zero(), hbar = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      ubar += advect[t4[a]];
      hbar += history[t4[a]];
    }
    ubar *= 0.25;
    hbar *= 0.25;
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 4; ++a) G += g[a] * g[a].transpose();
    const double tau_m =
        1.0 / std::sqrt(time_term + ubar.dot(G * ubar) + kCI * nu * nu * G.squaredNorm());
    const double tau_c = 1.0 / (tau_m * G.trace());
    double c[4];
    for (int a = 0; a < 4; ++a) c[a] = ubar.dot(g[a]);

    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const double mass = V / 20.0 * (a == b ? 2.0 : 1.0);
        const double diag = m * mass + V / 4.0 * c[b] + nu * V * g[a].dot(g[b]) + tau_m * V * c[a] * (m / 4.0 + c[b]);
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) K[4 * a + i][4 * b + j] = tau_c * V * g[a][i] * g[b][j];
          K[4 * a + i][4 * b + i] += diag;
          K[4 * a + i][4 * b + 3] = -g[a][i] * V / 4.0 + tau_m * V * c[a] * g[b][i];
          K[4 * a + 3][4 * b + i] = g[b][i] * V / 4.0 + tau_m * V * g[a][i] * (m / 4.0 + c[b]);
        }
        K[4 * a + 3][4 * b + 3] = tau_m * V * g[a].dot(g[b]);
      }
      // Right-hand side: the BDF history, in the Galerkin and the stabilization terms.
      Vec3 mh = Vec3::Zero();
      for (int b = 0; b < 4; ++b) mh += V / 20.0 * (a == b ? 2.0 : 1.0) * history[t4[b]];
      for (int i = 0; i < 3; ++i) F[4 * a + i] = mh[i] + tau_m * c[a] * V * hbar[i];
      F[4 * a + 3] = tau_m * V * g[a].dot(hbar);
    }

    // Scatter, moving known Dirichlet values to the right-hand side.
    for (int a = 0; a < 4; ++a) {
      const int na = t4[a];
      if (!owns(na)) continue;
      for (int i = 0; i < kBlock; ++i) {
        const int row = kBlock * na + i;
        if (fixed[row]) {
          diagonal[row - first_row] += K[4 * a + i][4 * a + i];
          continue;
        }
        rhs[row - first_row] += F[4 * a + i];
        for (int b = 0; b < 4; ++b) {
          const int base = value_index(na, i, tet_slots[e][a * 4 + b]);
          const int nb = t4[b];
          for (int j = 0; j < kBlock; ++j) {
            const int column = kBlock * nb + j;
            if (fixed[column]) rhs[row - first_row] -= K[4 * a + i][4 * b + j] * dirichlet[column];
            else values[base + j] += K[4 * a + i][4 * b + j];
          }
        }
      }
    }
  }

  // Natural boundaries: backflow stabilization and the resistance's traction.
  for (size_t k = 0; k < boundaries.size(); ++k) {
    const Boundary& b = boundaries[k];
    if (b.condition.type != BoundaryType::traction && b.condition.type != BoundaryType::resistance) continue;
    for (const BoundaryFace& f : b.faces) {
      const Vec3 mean = (advect[f.v[0]] + advect[f.v[1]] + advect[f.v[2]]) / 3.0;
      const double inflow = std::max(0.0, -mean.dot(f.normal));
      const double beta = 0.5 * fc.backflow * inflow;
      for (int a = 0; a < 3; ++a) {
        const int na = f.v[a];
        if (!owns(na)) continue;
        for (int i = 0; i < 3; ++i) {
          const int row = kBlock * na + i;
          if (fixed[row]) continue;
          rhs[row - first_row] -= resistance_pressure[k] * f.normal[i] * f.area / 3.0;
          if (beta == 0.0) continue;
          for (int bb = 0; bb < 3; ++bb) {
            const int nb = f.v[bb];
            if (fixed[kBlock * nb + i]) continue;
            values[value_index(na, i, slot(na, nb)) + i] += beta * f.area / 12.0 * (a == bb ? 2.0 : 1.0);
          }
        }
      }
    }
  }

  // Dirichlet rows: the diagonal the elements gave them, times the known value.
  for (int a = node_begin; a < node_end; ++a)
    for (int i = 0; i < kBlock; ++i) {
      const int row = kBlock * a + i;
      if (!fixed[row]) continue;
      double d = std::abs(diagonal[row - first_row]);
      if (!(d > 0.0)) d = 1.0;
      values[value_index(a, i, slot(a, a)) + i] = d;
      rhs[row - first_row] = d * dirichlet[row];
    }
  solver->end_assembly();
}

void NavierStokes::Impl::make_solver() {
  if (solver) return;
  solver = std::make_unique<LinearSolver>(columns_pattern(), kBlock,
                                          fc.steady ? saddle_point_options() : time_step_options(), fc.petsc_options);
  solver->reuse_preconditioner(!fc.steady && fc.reuse_preconditioner);
}

void NavierStokes::Impl::solve_system(StepReport& report, const std::string& where) {
  x.assign(pattern.total_rows(), 0.0);
  for (int a = 0; a < n(); ++a) {
    for (int i = 0; i < 3; ++i) x[kBlock * a + i] = u[a][i];
    x[kBlock * a + 3] = p[a];
  }
  const auto start = Clock::now();
  const SolveStats stats = solver->solve_assembled(rhs, x);
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
  double largest = 0.0;
  for (const Vec3& v : u) {
    if (!v.allFinite()) {
      largest = INFINITY;
      break;
    }
    largest = std::max(largest, v.norm());
  }
  if (std::isfinite(largest)) return;
  throw ComputationError(fmt::format("step {} (t = {:.6g} s) diverged: the velocity is no longer finite; the CFL "
                                     "number was {:.3g} (above ~1 the semi-implicit scheme may blow up: take a "
                                     "smaller dt), or flow entering through a traction boundary (backflow) grew",
                                     report.step, report.time, report.max_cfl));
}

NavierStokes::NavierStokes(const TetMesh& mesh, const FlowCase& flow_case, const Reporter& reporter)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.fc = flow_case;
  s.reporter = &reporter;
  s.nu = flow_case.viscosity / flow_case.density;
  {
    s.mesh_point = mesh::cuthill_mckee_order(mesh);
    const TetMesh ordered = mesh::renumbered(mesh, s.mesh_point);
    s.build(ordered);
    s.build_boundaries(ordered);
  }
  s.u.assign(s.n(), Vec3::Zero());
  s.u_old = s.u;
  s.p.assign(s.n(), 0.0);
  s.publish();
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
  s.update_resistance();
  s.set_dirichlet(t_next);
  report.max_cfl = s.cfl(advect, dt);
  report.time = t_next;

  std::vector<Vec3> next = s.u;
  std::vector<double> next_p = s.p;
  for (int iteration = 0; iteration <= s.fc.picard; ++iteration) {
    const auto assembly = Clock::now();
    s.assemble(advect, history, alpha0 / dt, dt);
    report.assembly_seconds += seconds_since(assembly);
    s.solve_system(report, fmt::format("step {} (t = {:.6g} s)", report.step, t_next));
    report.change = s.take_solution(next, next_p);
    advect = next;
  }
  s.u_old = std::move(s.u);
  s.u = std::move(next);
  s.p = std::move(next_p);
  s.t = t_next;
  s.step_count += 1;
  s.publish();
  report.seconds = seconds_since(start);
  s.check_finite(report);
  return report;
}

StepReport NavierStokes::solve_steady() {
  Impl& s = *impl_;
  const auto start = Clock::now();
  StepReport report;
  s.set_dirichlet(0.0);
  std::vector<Vec3> advect(s.n(), Vec3::Zero()), none(s.n(), Vec3::Zero());
  // Pseudo time steps (pseudo_transient): the step length, 0 for a Picard iteration; the first
  // iteration is the Stokes solve either way.
  double pseudo_dt = 0.0, last_rate = 0.0, resume_dt = 0.0;
  bool settled = false;
  for (int iteration = 0; iteration < s.fc.steady_iterations; ++iteration) {
    s.update_resistance();
    const double used_dt = pseudo_dt;
    const auto assembly = Clock::now();
    std::vector<Vec3> history = none;
    if (pseudo_dt > 0.0)
      for (int a = 0; a < s.n(); ++a) history[a] = s.u[a] / pseudo_dt;
    s.assemble(advect, history, pseudo_dt > 0.0 ? 1.0 / pseudo_dt : 0.0, pseudo_dt);
    report.assembly_seconds += seconds_since(assembly);
    const std::string what = pseudo_dt > 0.0 ? "pseudo time step" : "Picard iteration";
    s.solve_system(report, fmt::format("steady {} {}", what, iteration + 1));
    report.change = s.take_solution(s.u, s.p);
    s.publish();
    report.step = iteration + 1;
    s.check_finite(report);
    s.reporter->info(fmt::format("steady iteration {} ({}{}): velocity change {:.3e}, {} linear iterations",
                                 iteration + 1, what,
                                 pseudo_dt > 0.0 ? fmt::format(", CFL {:.3g}", s.cfl(advect, pseudo_dt)) : "",
                                 report.change, report.linear_iterations));
    advect = s.u;
    const bool small = report.change < s.fc.steady_tolerance;
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
  if (!settled) {
    const std::string advice = s.fc.pseudo_transient
                                   ? "run it in time, or raise time.steady_iterations"
                                   : "try time.steady_method = \"pseudo-transient\", run it in time, or raise "
                                     "time.steady_iterations";
    throw ComputationError(fmt::format("the steady solve did not settle in {} iterations (last relative change "
                                       "{:.3g} > {:.3g}): the flow may be unsteady at this Reynolds number; {}",
                                       s.fc.steady_iterations, report.change, s.fc.steady_tolerance, advice));
  }
  report.seconds = seconds_since(start);
  return report;
}

StepReport NavierStokes::start_from_stokes() {
  Impl& s = *impl_;
  const auto start = Clock::now();
  StepReport report;
  s.update_resistance();
  s.set_dirichlet(s.t);
  const std::vector<Vec3> none(s.n(), Vec3::Zero());
  const auto assembly = Clock::now();
  s.assemble(none, none, 0.0, 0.0);
  report.assembly_seconds = seconds_since(assembly);
  s.solve_system(report, fmt::format("the Stokes start (t = {:.6g} s)", s.t));
  s.solver->rebuild_preconditioner();  // the time steps' system has a mass term
  report.change = s.take_solution(s.u, s.p);
  s.publish();
  s.u_old = s.u;
  s.step_count = 0;
  report.time = s.t;
  report.seconds = seconds_since(start);
  s.check_finite(report);
  return report;
}

void NavierStokes::set_state(const std::vector<Vec3>& velocity, double time) {
  Impl& s = *impl_;
  if (velocity.size() != s.u.size())
    throw InputError(fmt::format("initial velocity: {} values for {} points", velocity.size(), s.u.size()));
  for (int k = 0; k < s.n(); ++k) s.u[k] = velocity[s.mesh_point[k]];
  s.u_old = s.u;
  s.publish();
  s.t = time;
  s.step_count = 0;
}

FlowState NavierStokes::state() const {
  const Impl& s = *impl_;
  FlowState out;
  out.time = s.t;
  out.steps = s.step_count;
  out.velocity.resize(s.n());
  out.previous.resize(s.n());
  out.kinematic_pressure.resize(s.n());
  for (int k = 0; k < s.n(); ++k) {
    out.velocity[s.mesh_point[k]] = s.u[k];
    out.previous[s.mesh_point[k]] = s.u_old[k];
    out.kinematic_pressure[s.mesh_point[k]] = s.p[k];
  }
  return out;
}

void NavierStokes::restore(const FlowState& state) {
  Impl& s = *impl_;
  const size_t n = s.u.size();
  if (state.velocity.size() != n || state.previous.size() != n || state.kinematic_pressure.size() != n)
    throw InputError(fmt::format("the saved state has {} points, the mesh {}", state.velocity.size(), n));
  for (size_t k = 0; k < n; ++k) {
    s.u[k] = state.velocity[s.mesh_point[k]];
    s.u_old[k] = state.previous[s.mesh_point[k]];
    s.p[k] = state.kinematic_pressure[s.mesh_point[k]];
  }
  s.t = state.time;
  s.step_count = state.steps;
  s.publish();
}

double NavierStokes::time() const { return impl_->t; }
int NavierStokes::steps() const { return impl_->step_count; }
int NavierStokes::dofs() const { return impl_->pattern.total_rows(); }
const std::vector<Vec3>& NavierStokes::velocity() const { return impl_->u_mesh; }

std::vector<double> NavierStokes::pressure() const {
  std::vector<double> out(impl_->p.size());
  for (size_t k = 0; k < out.size(); ++k) out[impl_->mesh_point[k]] = impl_->p[k] * impl_->fc.density;
  return out;
}

std::vector<BoundaryFlow> NavierStokes::boundary_flows() const {
  const Impl& s = *impl_;
  std::vector<BoundaryFlow> out;
  for (const Boundary& b : s.boundaries) {
    BoundaryFlow f;
    f.tag = b.condition.tag;
    f.flux = s.flux(b, s.u);
    f.area = b.area;
    double weighted = 0.0;
    for (const BoundaryFace& face : b.faces)
      weighted += face.area / 3.0 * (s.p[face.v[0]] + s.p[face.v[1]] + s.p[face.v[2]]);
    f.mean_pressure = b.area > 0.0 ? weighted / b.area * s.fc.density : 0.0;
    out.push_back(f);
  }
  return out;
}

PartitionReport NavierStokes::partition() const {
  const Impl& s = *impl_;
  const int ranks = process_count(), nn = s.n();
  std::vector<int> begin(ranks + 1);
  for (int r = 0; r <= ranks; ++r) begin[r] = range_begin(nn, r, ranks);
  const auto owner = [&](int a) {
    return static_cast<int>(std::upper_bound(begin.begin(), begin.end(), a) - begin.begin()) - 1;
  };
  // (point, process) where the process assembles a cell with the point and does not own it.
  std::vector<std::pair<int, int>> ghosts;
  for (const Tet& t4 : s.tets) {
    int owners[4];
    for (int a = 0; a < 4; ++a) owners[a] = owner(t4[a]);
    for (int r : owners)
      for (int a = 0; a < 4; ++a)
        if (owners[a] != r) ghosts.emplace_back(t4[a], r);
  }
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  PartitionReport out;
  out.owned_points.resize(ranks);
  out.ghost_points.assign(ranks, 0);
  for (int r = 0; r < ranks; ++r) out.owned_points[r] = begin[r + 1] - begin[r];
  std::vector<std::set<int>> next(ranks);
  for (const auto& [a, r] : ghosts) {
    ++out.ghost_points[r];
    next[r].insert(owner(a));
  }
  for (int r = 0; r < ranks; ++r) out.neighbours.push_back(static_cast<int>(next[r].size()));
  return out;
}

std::string NavierStokes::solver_description() const {
  return impl_->solver ? impl_->solver->description() : "(no solve yet)";
}

}  // namespace vesselmesh::flow
