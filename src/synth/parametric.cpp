#include "synth/parametric.h"

#include "mesh/error.h"
#include "synth/random.h"

#include <cmath>
#include <numbers>

namespace vesselmesh::synth {

TriMesh mesh_parametric(const ParametricGrid& grid, const GridOptions& options) {
  VM_CHECK(grid.nu >= 1 && grid.nv >= 1, "a parametric grid needs at least one cell");
  VM_CHECK(!grid.periodic_u || grid.nu >= 3, "a periodic direction needs three cells");
  VM_CHECK(!grid.periodic_v || grid.nv >= 3, "a periodic direction needs three cells");
  const int pu = grid.periodic_u ? grid.nu : grid.nu + 1;  // distinct points along u
  const int pv = grid.periodic_v ? grid.nv : grid.nv + 1;
  const double du = (grid.u1 - grid.u0) / grid.nu;
  const double dv = (grid.v1 - grid.v0) / grid.nv;
  Random random(options.seed);

  TriMesh mesh;
  mesh.points.reserve(static_cast<size_t>(pu) * pv);
  for (int j = 0; j < pv; ++j)
    for (int i = 0; i < pu; ++i) {
      double u = grid.u0 + i * du, v = grid.v0 + j * dv;
      if (options.jitter > 0.0) {
        const double angle = random.uniform(0.0, 2.0 * std::numbers::pi);
        const double amount = options.jitter * random.uniform();
        const bool u_edge = !grid.periodic_u && (i == 0 || i == grid.nu);
        const bool v_edge = !grid.periodic_v && (j == 0 || j == grid.nv);
        if (!u_edge) u += amount * std::cos(angle) * du;
        if (!v_edge) v += amount * std::sin(angle) * dv;
      }
      mesh.points.push_back(grid.position(u, v));
    }
  auto index = [&](int i, int j) { return (j % pv) * pu + (i % pu); };
  mesh.triangles.reserve(2 * static_cast<size_t>(grid.nu) * grid.nv);
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      const int a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
      const bool main_diagonal = options.random_diagonals ? random.coin() : ((i + j) % 2 == 0);
      if (main_diagonal) {
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      } else {
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({b, c, d});
      }
    }
  return mesh;
}

}  // namespace vesselmesh::synth
