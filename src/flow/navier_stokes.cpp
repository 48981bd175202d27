// NavierStokes: set-up (numbering, matrix pattern, threads, boundaries and their values, the
// resistance and RCR coupling), construction, the state saved and restored, the reports
// (flow/navier_stokes_impl.h lists the other parts).
#include "flow/navier_stokes_impl.h"

namespace vesselmesh::flow {
namespace {

// A velocity boundary's disturbance (flow/inflow_perturbation.h), its case's perturbation > 0:
// eddies up to the end's radius (m) passing at the flow's mean magnitude over its period (the flow,
// if constant) over the end's area; per face its points' indices in `nodes` (`at`: local point ->
// index), for its net flow.
void set_up_perturbation(Boundary& b, double radius, const std::map<int, int>& at, const Reporter& reporter) {
  double mean_flow = 0.0;  // m3/s
  const double period = b.condition.flow.period();
  for (int i = 0; i < 256; ++i) mean_flow += std::abs(b.condition.flow(period * i / 256.0)) * 1e-6 / 256.0;
  if (mean_flow > 0.0) b.perturbation.emplace(b.condition.perturbation, radius, mean_flow / b.area);
  for (const BoundaryFace& f : b.faces) b.face_nodes.push_back({at.at(f.v[0]), at.at(f.v[1]), at.at(f.v[2])});
  reporter.info(fmt::format("boundary {}: the inflow disturbed, each component's RMS {:g} % of the local speed, "
                            "eddies of {:.3g} to {:.3g} mm at about {:.3g} m/s",
                            b.condition.tag, 100.0 * b.condition.perturbation, 0.25e3 * radius, 1e3 * radius,
                            mean_flow / b.area));
}

// Adds a velocity boundary's disturbance at `time` to its nodes' values (m/s; `points` the local
// points, m): the local speed times the disturbance there, its net flow into the domain then removed
// along the profile's shape (of unit flow). Collective: every process calls it for the boundary.
void disturb(const Boundary& b, const std::vector<Vec3>& points, double time, std::vector<Vec3>& value) {
  std::vector<Vec3> added(b.nodes.size(), Vec3::Zero());
  for (size_t k = 0; k < b.nodes.size(); ++k)
    if (b.shape[k] != 0.0)
      added[k] = std::abs(value[k].dot(b.normal)) * (*b.perturbation)(points[b.nodes[k]] - b.center, time);
  double inflow = 0.0;
  for (size_t f = 0; f < b.faces.size(); ++f)
    if (b.counted[f]) {
      const std::array<int, 3>& v = b.face_nodes[f];
      inflow -= b.faces[f].area / 3.0 * (added[v[0]] + added[v[1]] + added[v[2]]).dot(b.normal);
    }
  inflow = parallel::sum_all({inflow})[0];
  for (size_t k = 0; k < b.nodes.size(); ++k) value[k] += added[k] + inflow * b.shape[k] * b.normal;
}

}  // namespace

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
    if (b.condition.perturbation > 0.0) set_up_perturbation(b, radius, at, *reporter);

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
    std::vector<Vec3> value(b.nodes.size(), Vec3::Zero());  // m/s; wall points keep 0
    for (size_t k = 0; k < b.nodes.size(); ++k) {
      if (b.shape[k] == 0.0) continue;
      double speed = q * b.shape[k];
      if (!phase.empty()) {
        speed = 0.0;
        for (size_t h = 0; h < phase.size(); ++h) speed += (phase[h] * b.harmonic_shape[h][k]).real();
      }
      value[k] = -speed * b.normal;
    }
    if (b.perturbation) disturb(b, points, time, value);
    for (size_t k = 0; k < b.nodes.size(); ++k)
      if (b.shape[k] != 0.0)
        for (int i = 0; i < 3; ++i) dirichlet[kBlock * b.nodes[k] + i] = value[k][i];
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
  s.p_old = s.p;
  s.published = false;
}

NavierStokes::~NavierStokes() = default;

const std::vector<SteadyIteration>& NavierStokes::steady_history() const { return impl_->steady_history; }

void NavierStokes::set_state(const std::vector<Vec3>& velocity, double time) {
  Impl& s = *impl_;
  if (static_cast<int>(velocity.size()) != s.total_points)
    throw InputError(fmt::format("initial velocity: {} values for {} points", velocity.size(), s.total_points));
  for (int k = 0; k < s.n(); ++k) s.u[k] = velocity[s.mesh_point[k]];
  s.u_old = s.u;
  s.p_old = s.p;
  if (s.solver) s.solver->forget_solutions();
  s.published = false;
  s.t = time;
  s.step_count = 0;
  s.dt_last = 0.0;
}

void NavierStokes::set_time_step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw OptionError(fmt::format("the time step must be a positive length of time in s (found {:g})", dt));
  impl_->dt_next = dt;
}

double NavierStokes::time_step() const { return impl_->dt_next > 0.0 ? impl_->dt_next : impl_->fc.dt; }

FlowState NavierStokes::gathered_state() const {
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
  out.time_step = s.dt_next;
  out.last_time_step = s.dt_last;
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
  s.p_old = s.p;  // (not saved: the next step's pressure guess is p^n, and no solutions are kept yet)
  if (s.solver) s.solver->forget_solutions();
  s.t = state.time;
  s.step_count = state.steps;
  s.dt_next = state.time_step;
  s.dt_last = state.last_time_step;
  s.published = false;
}

double NavierStokes::time() const { return impl_->t; }
int NavierStokes::steps() const { return impl_->step_count; }
int NavierStokes::dofs() const { return kBlock * impl_->total_points; }
const std::vector<Vec3>& NavierStokes::gathered_velocity() const {
  impl_->publish();
  return impl_->u_mesh;
}
const std::vector<double>& NavierStokes::gathered_pressure() const {
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
