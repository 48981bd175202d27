#include "flow/stabilized_cell.h"

#include <cmath>

namespace vesselmesh::flow {
namespace {

void lane_sqrt(CellLanes& v) {
  for (int l = 0; l < kCellLanes; ++l) v[l] = std::sqrt(v[l]);
}

}  // namespace

// Each product grouped as the one-cell code before it grouped them (the suite's figures were measured
// with those sums; G:G's sum alone is ordered otherwise than Eigen's was: the flow the same to 9 digits).
__attribute__((target_clones("avx2", "default"))) void stabilized_cells(const CellCorners& in,
                                                                        const CellParameters& parameters,
                                                                        CellSystems& out) {
  const double m = parameters.mass, dt = parameters.dt, nu = parameters.viscosity;
  const double time_term = dt > 0.0 ? parameters.time_coefficient / (dt * dt) : 0.0;
  // The shape functions' gradients: the rows of the inverse Jacobian (mesh::barycentric_gradients).
  CellLanes d[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) d[k][i] = in.x[k + 1][i] - in.x[0][i];
  const auto cross = [&](int p, int q, CellLanes r[3]) {
    r[0] = d[p][1] * d[q][2] - d[p][2] * d[q][1];
    r[1] = d[p][2] * d[q][0] - d[p][0] * d[q][2];
    r[2] = d[p][0] * d[q][1] - d[p][1] * d[q][0];
  };
  CellLanes c12[3], c23[3], c31[3];
  cross(0, 1, c12);
  cross(1, 2, c23);
  cross(2, 0, c31);
  const CellLanes v6 = c12[0] * d[2][0] + c12[1] * d[2][1] + c12[2] * d[2][2];
  CellLanes g[4][3];
  for (int i = 0; i < 3; ++i) {
    g[1][i] = c23[i] / v6;
    g[2][i] = c31[i] / v6;
    g[3][i] = c12[i] / v6;
    g[0][i] = -(g[1][i] + g[2][i] + g[3][i]);
  }
  const CellLanes V = v6 / 6.0;
  CellLanes ubar[3], hbar[3];
  for (int i = 0; i < 3; ++i) {
    ubar[i] = (in.u[0][i] + in.u[1][i] + in.u[2][i] + in.u[3][i]) * 0.25;
    hbar[i] = (in.h[0][i] + in.h[1][i] + in.h[2][i] + in.h[3][i]) * 0.25;
  }
  CellLanes dots[4][4];  // g_a . g_b
  for (int a = 0; a < 4; ++a)
    for (int b = a; b < 4; ++b) dots[a][b] = dots[b][a] = g[a][0] * g[b][0] + g[a][1] * g[b][1] + g[a][2] * g[b][2];
  CellLanes largest = dots[0][0], speed = ubar[0] * ubar[0] + ubar[1] * ubar[1] + ubar[2] * ubar[2];
  for (int a = 1; a < 4; ++a) largest = dots[a][a] > largest ? dots[a][a] : largest;
  lane_sqrt(largest);
  lane_sqrt(speed);
  out.cfl = speed * dt * largest;

  CellLanes G[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) G[i][j] = g[0][i] * g[0][j] + g[1][i] * g[1][j] + g[2][i] * g[2][j] + g[3][i] * g[3][j];
  CellLanes uGu = {}, GG = {};
  for (int i = 0; i < 3; ++i) uGu += ubar[i] * (G[i][0] * ubar[0] + G[i][1] * ubar[1] + G[i][2] * ubar[2]);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) GG += G[i][j] * G[i][j];
  CellLanes tau_m = time_term + uGu + kCI * nu * nu * GG;
  lane_sqrt(tau_m);
  tau_m = 1.0 / tau_m;
  const CellLanes tau_c = parameters.tau_c_factor / (tau_m * (G[0][0] + G[1][1] + G[2][2]));
  CellLanes c[4];
  for (int a = 0; a < 4; ++a) c[a] = ubar[0] * g[a][0] + ubar[1] * g[a][1] + ubar[2] * g[a][2];

  const CellLanes lsic_share = nu + tau_c / 3.0, twentieth = V / 20.0;
  CellLanes momentum = m * V;
  for (int a = 0; a < 4; ++a) momentum += V * (lsic_share * dots[a][a] + tau_m * c[a] * c[a]);
  const CellLanes w = V / momentum;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) out.schur[a][b] = w * V * dots[a][b];
  out.momentum = momentum;

  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      CellLanes(&B)[4][4] = out.block[a][b];
      const CellLanes mass = twentieth * (a == b ? 2.0 : 1.0);
      const CellLanes diag = m * mass + V / 4.0 * c[b] + nu * V * dots[a][b] + tau_m * V * c[a] * (m / 4.0 + c[b]);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) B[i][j] = tau_c * V * g[a][i] * g[b][j];
        B[i][i] += diag;
        B[i][3] = -g[a][i] * V / 4.0 + tau_m * V * c[a] * g[b][i];
        B[3][i] = g[b][i] * V / 4.0 + tau_m * V * g[a][i] * (m / 4.0 + c[b]);
      }
      B[3][3] = tau_m * V * dots[a][b];
    }
    CellLanes mh[3] = {};
    for (int b = 0; b < 4; ++b)
      for (int i = 0; i < 3; ++i) mh[i] += twentieth * (a == b ? 2.0 : 1.0) * in.h[b][i];
    for (int i = 0; i < 3; ++i) out.rhs[a][i] = mh[i] + tau_m * c[a] * V * hbar[i];
    out.rhs[a][3] = tau_m * V * (g[a][0] * hbar[0] + g[a][1] * hbar[1] + g[a][2] * hbar[2]);
  }

  out.volume = V;
  out.tau_m = tau_m;
  out.tau_c = tau_c;
  for (int i = 0; i < 3; ++i) out.ubar[i] = ubar[i], out.hbar[i] = hbar[i];
  for (int a = 0; a < 4; ++a) {
    out.c[a] = c[a];
    for (int i = 0; i < 3; ++i) out.g[a][i] = g[a][i];
  }
}

}  // namespace vesselmesh::flow
