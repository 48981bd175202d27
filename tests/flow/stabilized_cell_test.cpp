#include "flow/stabilized_cell.h"

#include "mesh/tetmesh.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

namespace vesselmesh::flow {
namespace {

using Corners = std::array<Vec3, 4>;

// Four cells of different shapes and sizes (m), a velocity field and a history field (SI).
const std::array<Corners, 4> kCells = {{
    {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(0, 1e-3, 0), Vec3(0, 0, 1e-3)},
    {Vec3(1e-3, 2e-3, 0), Vec3(1.4e-3, 2.1e-3, 0.2e-3), Vec3(1.1e-3, 2.5e-3, 0.1e-3), Vec3(1.2e-3, 2.2e-3, 0.6e-3)},
    {Vec3(0, 0, 0), Vec3(2e-4, 0, 0), Vec3(1e-4, 1.7e-4, 0), Vec3(1e-4, 0.6e-4, 1e-5)},  // a thin layer cell
    {Vec3(-1e-3, 0, 2e-3), Vec3(-0.2e-3, 0.3e-3, 2.1e-3), Vec3(-0.8e-3, 0.9e-3, 1.9e-3),
     Vec3(-0.5e-3, 0.4e-3, 2.8e-3)},
}};
Vec3 velocity(const Vec3& x) { return Vec3(0.1 + 30.0 * x.y(), -0.05 + 20.0 * x.z(), 0.3 - 40.0 * x.x()); }
Vec3 history(const Vec3& x) { return Vec3(2.0 - 500.0 * x.z(), 1.0 + 300.0 * x.x(), -4.0 + 100.0 * x.y()); }

// The corners of `order`'s cells, cell order[l] in lane l.
CellCorners corners_of(const std::array<int, kCellLanes>& order, bool still = false) {
  CellCorners c;
  for (int l = 0; l < kCellLanes; ++l)
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        const Vec3& x = kCells[order[l]][a];
        c.x[a][i][l] = x[i];
        c.u[a][i][l] = still ? 0.0 : velocity(x)[i];
        c.h[a][i][l] = still ? 0.0 : history(x)[i];
      }
  return c;
}

const CellParameters kParameters{.mass = 1.5e3, .dt = 1e-3, .viscosity = 3.3e-6};

// Cell l's shape functions' gradients and volume by mesh::barycentric_gradients.
std::array<Vec3, 4> gradients_of(int l, double& volume) {
  const Corners& x = kCells[l];
  double v6 = 0.0;
  const std::array<Vec3, 4> g = mesh::barycentric_gradients(x[0], x[1], x[2], x[3], v6);
  volume = v6 / 6.0;
  return g;
}

// The volume and gradients are mesh::barycentric_gradients's, to the bit (the same operations).
TEST(StabilizedCell, VolumeAndGradientsAreTheMeshsOwn) {
  CellSystems s;
  stabilized_cells(corners_of({0, 1, 2, 3}), kParameters, s);
  for (int l = 0; l < kCellLanes; ++l) {
    double volume = 0.0;
    const std::array<Vec3, 4> g = gradients_of(l, volume);
    EXPECT_EQ(s.volume[l], volume) << l;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) EXPECT_EQ(s.g[a][i][l], g[a][i]) << l;
  }
}

// Cell l's metric G = sum_a g_a g_a^T, mean velocity ubar and largest |g_a|, worked out with Eigen.
struct CellMetric {
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
  Vec3 ubar = Vec3::Zero();
  double largest = 0.0;
  // (C_t / dt^2 + ubar.G.ubar + 36 nu^2 G:G)^(-1/2), at kParameters' dt and viscosity.
  double tau_m(double time_coefficient) const {
    const double dt = kParameters.dt, nu = kParameters.viscosity;
    return 1.0 / std::sqrt(time_coefficient / (dt * dt) + ubar.dot(G * ubar) + 36.0 * nu * nu * G.squaredNorm());
  }
};
CellMetric metric_of(int l) {
  double volume = 0.0;
  const std::array<Vec3, 4> g = gradients_of(l, volume);
  CellMetric m;
  for (int a = 0; a < 4; ++a) {
    m.G += g[a] * g[a].transpose();
    m.ubar += velocity(kCells[l][a]) / 4.0;
    m.largest = std::max(m.largest, g[a].norm());
  }
  return m;
}

// tau_M = (4/dt^2 + ubar.G.ubar + 36 nu^2 G:G)^(-1/2), tau_C = 1 / (tau_M tr G), the CFL number
// |ubar| dt max_a |g_a|, each against its definition worked out with Eigen (1e-14 relative).
TEST(StabilizedCell, StabilizationParametersFollowTheirDefinitions) {
  CellSystems s;
  stabilized_cells(corners_of({0, 1, 2, 3}), kParameters, s);
  for (int l = 0; l < kCellLanes; ++l) {
    const CellMetric m = metric_of(l);
    const double dt = kParameters.dt, tau_m = m.tau_m(4.0), trace = m.G.trace(), speed = m.ubar.norm();
    EXPECT_NEAR(s.tau_m[l], tau_m, 1e-14 * tau_m) << l;
    EXPECT_NEAR(s.tau_c[l], 1.0 / (tau_m * trace), 1e-14 / (tau_m * trace)) << l;
    EXPECT_NEAR(s.cfl[l], speed * dt * m.largest, 1e-14 * speed * dt * m.largest) << l;
    EXPECT_LT(s.tau_m[l], dt / 2.0);  // the time step bounds it
  }
  CellSystems steady;  // dt 0: no time term, no CFL number
  stabilized_cells(corners_of({0, 1, 2, 3}), {.mass = 0.0, .dt = 0.0, .viscosity = 3.3e-6}, steady);
  for (int l = 0; l < kCellLanes; ++l) {
    EXPECT_GT(steady.tau_m[l], s.tau_m[l]);
    EXPECT_EQ(steady.cfl[l], 0.0);
  }
}

// The case's factors (FlowCase::tau_c_factor, tau_m_time): tau_M's time term C_t / dt^2 and tau_C times
// f_C, against the same definitions (1e-14); C_t = 0 is the steady flow's tau_M, and the Schur
// complement's preconditioning weight sees the smaller tau_C.
TEST(StabilizedCell, TheCasesFactorsScaleTauCAndTauMsTimeTerm) {
  CellSystems base, scaled, steady;
  stabilized_cells(corners_of({0, 1, 2, 3}), kParameters, base);
  CellParameters p = kParameters;
  p.time_coefficient = 16.0;
  p.tau_c_factor = 0.1;
  stabilized_cells(corners_of({0, 1, 2, 3}), p, scaled);
  p.time_coefficient = 0.0;
  p.tau_c_factor = 1.0;
  stabilized_cells(corners_of({0, 1, 2, 3}), p, steady);
  CellSystems no_dt;
  stabilized_cells(corners_of({0, 1, 2, 3}), {.mass = 1.5e3, .dt = 0.0, .viscosity = 3.3e-6}, no_dt);
  for (int l = 0; l < kCellLanes; ++l) {
    const CellMetric m = metric_of(l);
    const double tau_m = m.tau_m(16.0), trace = m.G.trace(), steady_tau_m = m.tau_m(0.0);
    EXPECT_NEAR(scaled.tau_m[l], tau_m, 1e-14 * tau_m) << l;
    EXPECT_LT(scaled.tau_m[l], kParameters.dt / 4.0) << l;  // C_t = 16 bounds it by dt / 4
    EXPECT_NEAR(scaled.tau_c[l], 0.1 / (tau_m * trace), 1e-14 * 0.1 / (tau_m * trace)) << l;
    EXPECT_LT(scaled.momentum[l], base.momentum[l]) << l;
    EXPECT_NEAR(steady.tau_m[l], steady_tau_m, 1e-14 * steady_tau_m) << l;
    EXPECT_EQ(steady.tau_m[l], no_dt.tau_m[l]) << l;  // C_t = 0: as without a time step
    EXPECT_EQ(steady.cfl[l], base.cfl[l]) << l;        // the CFL number is the time step's still
  }
}

// The discrete operators' consistency, per row: without a mass term the momentum rows give a
// uniform velocity no force (viscosity, convection, LSIC and SUPG all vanish: sum_b g_b = 0) and a
// uniform pressure the Galerkin force -V g_a; the continuity rows see neither a uniform velocity
// nor a uniform pressure. With the mass term alone (at rest, no viscosity), a uniform velocity's
// row is m V/4 (the consistent mass's row sum). 1e-12 of the rows' largest entry.
TEST(StabilizedCell, RowsOfUniformFieldsAreTheContinuousOnes) {
  CellSystems s;
  stabilized_cells(corners_of({0, 1, 2, 3}), {.mass = 0.0, .dt = 1e-3, .viscosity = 3.3e-6}, s);
  CellSystems mass;
  stabilized_cells(corners_of({0, 1, 2, 3}, true), {.mass = 1.5e3, .dt = 1e-3, .viscosity = 0.0}, mass);
  for (int l = 0; l < kCellLanes; ++l)
    for (int a = 0; a < 4; ++a) {
      double scale = 0.0;
      for (int b = 0; b < 4; ++b)
        for (int i = 0; i < 4; ++i)
          for (int j = 0; j < 4; ++j) scale = std::max(scale, std::abs(s.block[a][b][i][j][l]));
      const double V = s.volume[l];
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          double sum = 0.0, mass_sum = 0.0;
          for (int b = 0; b < 4; ++b) sum += s.block[a][b][i][j][l], mass_sum += mass.block[a][b][i][j][l];
          const double expected = i < 3 && j == 3 ? -V * s.g[a][i][l] : 0.0;
          EXPECT_NEAR(sum, expected, 1e-12 * scale) << "cell " << l << " corner " << a << " row " << i << " column " << j;
          if (i < 3 && j < 3) {
            const double m = i == j ? 1.5e3 * V / 4.0 : 0.0;
            EXPECT_NEAR(mass_sum, m, 1e-12 * 1.5e3 * V) << "cell " << l << " corner " << a;
          }
        }
    }
}

// A cell's system is the same to the bit in any lane, whatever the other lanes hold.
TEST(StabilizedCell, EachLaneIsItsCellWhateverTheOthers) {
  CellSystems in_order, reversed, repeated;
  stabilized_cells(corners_of({0, 1, 2, 3}), kParameters, in_order);
  stabilized_cells(corners_of({3, 2, 1, 0}), kParameters, reversed);
  stabilized_cells(corners_of({2, 2, 2, 2}), kParameters, repeated);
  const auto same = [](const CellSystems& p, int lp, const CellSystems& q, int lq) {
    const double* x = reinterpret_cast<const double*>(&p);
    const double* y = reinterpret_cast<const double*>(&q);
    for (size_t k = 0; k < sizeof(CellSystems) / sizeof(double); k += kCellLanes)
      if (std::memcmp(&x[k + lp], &y[k + lq], sizeof(double)) != 0) return false;
    return true;
  };
  for (int l = 0; l < kCellLanes; ++l) EXPECT_TRUE(same(in_order, l, reversed, 3 - l)) << l;
  for (int l = 0; l < kCellLanes; ++l) EXPECT_TRUE(same(in_order, 2, repeated, l)) << l;
}

}  // namespace
}  // namespace vesselmesh::flow
