// NavierStokes: the state as the solver's rows, the steady residual and its line search, the CFL
// number, the whole-field gather, and the assembly of the stabilized system (Newton's terms too).
#include "flow/navier_stokes_impl.h"

namespace vesselmesh::flow {

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
  // whole flow on each (a caller of gathered_velocity() need not know which process it is on; 32 bytes a
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

namespace {

// Newton's terms on cell (lane l of `cells`)'s system K and right-hand side F, at the advecting
// velocity `advect` and pressure `p` (per local point), mass coefficient m; the stabilization's
// own derivatives too when `stabilization_jacobian` (Linearization::full).
void add_newton_terms(const CellSystems& cells, int l, const Tet& t4,
                      const std::vector<Vec3>& advect, const std::vector<double>& p, double m,
                      bool stabilization_jacobian, double K[16][16], double F[16]) {
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
  // d tau_c / d u_b = tau_c tau_m^2 G ubar / 4: rank-one terms on the SUPG and PSPG rows (their
  // residuals V c_a r and V g_a . r) and the LSIC rows (V g_a div u). (Held, Newton's last steps
  // cut the residual 4-27-fold on a carotid bifurcation at Re 300.)
  const Vec3 dtau =
      stabilization_jacobian ? Vec3(-tau_m * tau_m * tau_m / 4.0 * (G * ubar)) : Vec3::Zero();
  const double dtau_c_over_dtau = -tau_c / tau_m, divergence = grad.trace(),
               along = 4.0 * dtau.dot(ubar);
  for (int a = 0; a < 4; ++a) {
    const Vec3 pspg = g[a].transpose() * grad;  // (g_a . grad(:, j))_j
    Vec3 momentum_tau;                          // per row i, what multiplies d tau_m / d u_b
    for (int i = 0; i < 3; ++i)
      momentum_tau[i] = V * (c[a] * r[i] + dtau_c_over_dtau * g[a][i] * divergence);
    const double continuity_tau = V * g[a].dot(r);
    for (int b = 0; b < 4; ++b)
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i)
          K[4 * a + i][4 * b + j] += V / 16.0 * grad(i, j) +
                                     held * V / 4.0 * (g[a][j] * r[i] + c[a] * grad(i, j)) +
                                     momentum_tau[i] * dtau[j];
        K[4 * a + 3][4 * b + j] += held * V / 4.0 * pspg[j] + continuity_tau * dtau[j];
      }
    for (int i = 0; i < 3; ++i)
      F[4 * a + i] += extra[i] + held * V * c[a] * (r[i] + convection[i]) + momentum_tau[i] * along;
    F[4 * a + 3] += held * V * g[a].dot(convection) + continuity_tau * along;
  }
}

}  // namespace

// The corners of the cells `cell[0..count)` (the last repeated in the lanes beyond): their points,
// advecting velocity and BDF history.
void NavierStokes::Impl::gather_corners(const int* cell, int count, const std::vector<Vec3>& advect,
                                        const std::vector<Vec3>& history, CellCorners& corners) const {
  for (int l = 0; l < kCellLanes; ++l) {
    const Tet& t4 = tets[static_cast<size_t>(cell[std::min(l, count - 1)])];
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        corners.x[a][i][l] = points[t4[a]][i];
        corners.u[a][i][l] = advect[t4[a]][i];
        corners.h[a][i][l] = history[t4[a]][i];
      }
  }
}

// The field split's entries of those cells' point pairs in rows [lo, hi), fetched into the cache
// while the cells' systems are worked out (the scatter waited on them).
void NavierStokes::Impl::prefetch_pairs(const int* cell, int count, int lo, int hi) const {
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
  const CellParameters parameters{
      .mass = m, .dt = dt, .viscosity = nu, .time_coefficient = fc.tau_m_time, .tau_c_factor = fc.tau_c_factor};
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
      add_newton_terms(cells, l, t4, advect, p, m, stabilization_jacobian, K, F);
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
    gather_corners(cell, count, advect, history, corners);
    if (values.split) prefetch_pairs(cell, count, lo, hi);
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

  if (values.schur_own) add_open_end_schur(momentum_share);
  add_open_ends(advect, newton);
  set_dirichlet_rows(diagonal);
  solver->end_assembly();
  values = MatrixValues{};
  if (!resistive.empty()) {  // the resistive ends' implicit part, as update_resistance left it
    std::vector<double> coefficients;
    for (int k : resistive) coefficients.push_back(resistance_coefficient[k]);
    solver->set_low_rank_coefficients(coefficients);
  }
}

// The Schur complement at the open ends: there the velocity's divergence B^T q of a pressure q
// has a boundary part, q n dS, which the Laplacian above lacks (it leaves a constant pressure
// free, which the open ends fix); B D^-1 B^T's share of it, per point its (free components')
// area vector a squared over its momentum diagonal, |a|^2 / D.
void NavierStokes::Impl::add_open_end_schur(const std::vector<double>& momentum_share) {
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
void NavierStokes::Impl::add_open_ends(const std::vector<Vec3>& advect, bool newton) {
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
        for (int bb = 0; bb < 3; ++bb)
          mass_u += f.area / 12.0 * (a == bb ? 2.0 : 1.0) * advect[f.v[bb]];
        const bool newton_backflow = newton && beta > 0.0;
        for (int i = 0; i < 3; ++i) {
          const int row = kBlock * na + i;
          if (fixed[row]) continue;
          rhs[row] -= resistance_pressure[k] * f.normal[i] * f.area / 3.0;
          if (beta == 0.0) continue;
          for (int bb = 0; bb < 3; ++bb) {
            const int nb = f.v[bb];
            if (!fixed[kBlock * nb + i])
              entry(na, i, slot(na, nb))[i] += beta * f.area / 12.0 * (a == bb ? 2.0 : 1.0);
            if (!newton_backflow) continue;
            for (int j = 0; j < 3; ++j) {
              const double derivative = mass_u[i] * -0.5 * fc.backflow * f.normal[j] / 3.0;
              if (fixed[kBlock * nb + j])
                rhs[row] -= derivative * dirichlet[kBlock * nb + j];
              else
                entry(na, i, slot(na, nb))[j] += derivative;
            }
          }
          if (newton_backflow) rhs[row] += beta * mass_u[i];
        }
      }
    }
  }
}

// Dirichlet rows: the diagonal the elements gave them, times the known value.
void NavierStokes::Impl::set_dirichlet_rows(const std::vector<double>& diagonal) {
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
}

}  // namespace vesselmesh::flow
