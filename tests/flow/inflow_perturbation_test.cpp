#include "flow/inflow_perturbation.h"

#include "flow/navier_stokes.h"
#include "flow_test_cases.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::flow {
namespace {

// Each component's mean and RMS over time at a point: zero and the intensity (over 2000 of the
// largest eddies' passing times, 40 samples each: within 10 % and a tenth of the intensity).
TEST(InflowPerturbation, EachComponentHasTheAskedRmsAndNoMean) {
  const double intensity = 0.04, length = 6e-3, speed = 0.18;
  const InflowPerturbation p(intensity, length, speed);
  for (const Vec3& x : {Vec3(0.0, 0.0, 0.0), Vec3(1e-3, -2e-3, 0.0), Vec3(-4e-3, 3e-3, 0.0)}) {
    Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
    const int samples = 80000;
    const double dt = 0.025 * length / speed;
    for (int i = 0; i < samples; ++i) {
      const Vec3 v = p(x, i * dt);
      sum += v, sum2 += v.cwiseProduct(v);
    }
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(sum[c] / samples, 0.0, 0.1 * intensity) << "component " << c;
      EXPECT_NEAR(std::sqrt(sum2[c] / samples), intensity, 0.1 * intensity) << "component " << c;
    }
  }
}

// A function of the position and the time only: the same from two objects (and so on any
// process, after a restart, run after run), continuous in both, and not the same everywhere.
TEST(InflowPerturbation, TheSameAtTheSamePlaceAndTimeAndSmoothBetween) {
  const double length = 2e-3, speed = 0.5;
  const InflowPerturbation a(0.05, length, speed), b(0.05, length, speed);
  const Vec3 x(0.4e-3, 0.7e-3, 0.0), near = x + Vec3(0.01 * length, 0.0, 0.0);
  const double t = 0.3, later = t + 0.01 * length / speed;
  EXPECT_EQ(a(x, t), b(x, t));
  EXPECT_LT((a(x, t) - a(near, t)).norm(), 0.05 * 0.1);
  EXPECT_LT((a(x, t) - a(x, later)).norm(), 0.05 * 0.1);
  double differs = 0.0;
  for (int k = 1; k <= 8; ++k) differs = std::max(differs, (a(x, t) - a(-x * k, t)).norm());
  EXPECT_GT(differs, 0.05 * 0.5);
}

// In the solver (a pipe, perturbation = 0.05): the inlet carries the asked flow whatever the
// disturbance (it has no net flow; to the linear solver's tolerance, which the Dirichlet rows are
// solved to), its transverse velocity is the disturbance times the local speed of the undisturbed
// profile (the net flow's removal is along the normal only), and its wall points are at rest. Under
// mpirun the same: the disturbance is a function of the position and the time.
TEST(NavierStokes, ADisturbedInflowCarriesItsFlowAndIsTheDisturbanceTimesTheSpeed) {
  const double R = 2.0, L = 6.0, Q = 0.5;  // mm, mm, mL/s
  const TetMesh mesh = pipe_volume(R, L, 0.4);
  const std::string time = "dt = 0.002\nend = 0.01";
  const FlowCase quiet = pipe_case(time, fmt::format("flow = {}", Q), "case.toml");
  const FlowCase disturbed =
      pipe_case(time, fmt::format("flow = {}\nperturbation = 0.05", Q), "case.toml");
  NavierStokes a(mesh, quiet), b(mesh, disturbed);
  int inlet_tag = -1, wall_tag = -1;
  for (const auto& [tag, name] : mesh.tag_names) {
    if (name == "inlet") inlet_tag = tag;
    if (name == "wall") wall_tag = tag;
  }
  std::vector<char> on_inlet(mesh.num_points(), 0), on_wall(mesh.num_points(), 0);
  double area = 0.0;  // m2: the faceted inlet's, and its centre, as the solver takes them
  Vec3 centre = Vec3::Zero();
  for (size_t f = 0; f < mesh.boundary.size(); ++f) {
    const Triangle& t = mesh.boundary[f];
    for (int v : t) {
      if (mesh.boundary_tags[f] == inlet_tag) on_inlet[v] = 1;
      if (mesh.boundary_tags[f] == wall_tag) on_wall[v] = 1;
    }
    if (mesh.boundary_tags[f] != inlet_tag) continue;
    const Vec3 a0 = mesh.points[t[0]] * 1e-3, a1 = mesh.points[t[1]] * 1e-3,
               a2 = mesh.points[t[2]] * 1e-3;
    const double da = 0.5 * (a1 - a0).cross(a2 - a0).norm();
    area += da, centre += da * (a0 + a1 + a2) / 3.0;
  }
  centre /= area;
  const InflowPerturbation expected(0.05, std::sqrt(area / M_PI), Q * 1e-6 / area);
  const double speed = Q * 1e-6 / area;  // the mean speed, m/s
  for (int step = 1; step <= 3; ++step) {
    a.step(), b.step();
    const double t = step * 0.002;
    for (const BoundaryFlow& f : b.boundary_flows())
      if (f.tag == "inlet") {
        EXPECT_NEAR(f.flux, -Q * 1e-6, 1e-6 * Q * 1e-6) << "step " << step;
      }
    int inside = 0;
    double largest = 0.0;
    for (int v = 0; v < mesh.num_points(); ++v) {
      if (!on_inlet[v]) continue;
      const Vec3 u = b.gathered_velocity()[v], quiet_u = a.gathered_velocity()[v];
      if (on_wall[v]) {
        EXPECT_EQ(u.norm(), 0.0) << "wall point " << v;
        continue;
      }
      const Vec3 g = std::abs(quiet_u.z()) * expected(mesh.points[v] * 1e-3 - centre, t);
      EXPECT_NEAR(u.x(), g.x(), 1e-6 * speed) << "point " << v;
      EXPECT_NEAR(u.y(), g.y(), 1e-6 * speed) << "point " << v;
      largest = std::max(largest, std::abs(u.z() - quiet_u.z()) / std::abs(quiet_u.z()));
      ++inside;
    }
    EXPECT_GT(inside, 10);
    EXPECT_GT(largest, 0.01);  // the axial velocity disturbed too
    EXPECT_LT(largest, 0.5);
  }
}

}  // namespace
}  // namespace vesselmesh::flow
