#include "post/wss.h"

#include "analysis/open_ends.h"
#include "synth/shapes.h"
#include "volume/volume_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::post {
namespace {

struct Pipe {
  TetMesh mesh;
  std::vector<Tet> all;
  WallSurface wall;
  std::vector<Vec3> si;  // points in metres
};

// A pipe of radius R mm along +z with 4 layers; its wall extracted.
Pipe pipe(double R) {
  Pipe p;
  const TriMesh surface = synth::cylinder({.radius = R, .length = 6.0, .resolution = 0.25});
  p.mesh = volume::build_volume(surface, analysis::open_ends(surface), std::vector<double>(surface.points.size(), R), {})
               .mesh;
  p.all = mesh::all_tetrahedra(p.mesh);
  int wall = 0;
  for (const auto& [tag, name] : p.mesh.tag_names)
    if (name == "wall") wall = tag;
  p.wall = extract_wall(p.mesh, p.all, {wall});
  for (const Vec3& x : p.mesh.points) p.si.push_back(x * 1e-3);
  return p;
}

TEST(WallShearStress, ExtractsTheWallWithItsTetrahedra) {
  const Pipe p = pipe(2.0);
  ASSERT_FALSE(p.wall.mesh.triangles.empty());
  for (size_t f = 0; f < p.wall.mesh.triangles.size(); ++f) {
    const Tet& t = p.all[p.wall.tet[f]];
    int shared = 0;
    for (int v : p.wall.mesh.triangles[f])
      shared += std::count(t.begin(), t.end(), p.wall.volume_point[v]);
    EXPECT_EQ(shared, 3) << "wall triangle " << f;
  }
  for (size_t v = 0; v < p.wall.mesh.points.size(); ++v)
    EXPECT_NEAR(std::hypot(p.wall.mesh.points[v].x(), p.wall.mesh.points[v].y()), 2.0, 1e-9);
}

// A linear field u = (0, 0, g x) has a constant gradient, which P1 holds exactly: on a wall
// face with normal n (into the fluid) t = mu g (n_x e_z + n_z e_x) and tau = t - (t.n) n; a point
// gets the area-weighted mean of its faces'.
TEST(WallShearStress, ExactForALinearField) {
  const Pipe p = pipe(2.0);
  const double g = 100.0, mu = 0.0035;  // 1/s, Pa s
  std::vector<Vec3> u(p.mesh.points.size());
  for (size_t i = 0; i < u.size(); ++i) u[i] = Vec3(0.0, 0.0, g * p.si[i].x());
  const std::vector<Vec3> tau = wall_shear_stress(p.wall, p.all, p.si, u, mu);

  std::vector<Vec3> exact(tau.size(), Vec3::Zero());
  std::vector<double> weight(tau.size(), 0.0);
  for (const Triangle& f : p.wall.mesh.triangles) {
    const std::vector<Vec3>& x = p.wall.mesh.points;
    const Vec3 area2 = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
    const Vec3 n = -area2.normalized();
    const Vec3 t = mu * g * Vec3(n.z(), 0.0, n.x());
    for (int v : f) {
      exact[v] += 0.5 * area2.norm() * (t - t.dot(n) * n);
      weight[v] += 0.5 * area2.norm();
    }
  }
  double worst = 0.0, largest = 0.0;
  for (size_t v = 0; v < tau.size(); ++v) {
    worst = std::max(worst, (tau[v] - exact[v] / weight[v]).norm());
    largest = std::max(largest, tau[v].norm());
  }
  EXPECT_LT(worst, 1e-9 * mu * g);
  EXPECT_NEAR(largest, mu * g, 0.01 * mu * g);  // |n_x| reaches 1 on the x axis
}

// Poiseuille's velocity put on the mesh: the wall shear stress 4 mu Q / (pi R^3) along the
// flow, to the first-order error of a P1 gradient over the first layer (h / 2R = 1.25 % here).
TEST(WallShearStress, PoiseuilleFieldWithinTwoPercent) {
  const double R = 2.0;
  const Pipe p = pipe(R);
  const double mu = 0.0035, peak = 0.2, r = R * 1e-3;  // Pa s, m/s, m
  std::vector<Vec3> u(p.mesh.points.size());
  for (size_t i = 0; i < u.size(); ++i) {
    const double s = (p.si[i].x() * p.si[i].x() + p.si[i].y() * p.si[i].y()) / (r * r);
    u[i] = Vec3(0.0, 0.0, peak * std::max(0.0, 1.0 - s));
  }
  const double exact = 2.0 * mu * peak / r;  // = 4 mu Q / (pi R^3) with Q = pi R^2 peak / 2
  const std::vector<Vec3> tau = wall_shear_stress(p.wall, p.all, p.si, u, mu);
  int count = 0;
  for (size_t v = 0; v < tau.size(); ++v) {
    if (p.wall.mesh.points[v].z() < 0.5 || p.wall.mesh.points[v].z() > 5.5) continue;
    EXPECT_NEAR(tau[v].z(), exact, 0.02 * exact);
    EXPECT_LT(std::hypot(tau[v].x(), tau[v].y()), 1e-3 * exact);
    ++count;
  }
  EXPECT_GT(count, 100);
}

}  // namespace
}  // namespace vesselmesh::post
