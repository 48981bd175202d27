#include "mesh/reorder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace vesselmesh::mesh {
namespace {

// A box of nx x ny x nz unit cubes, each cut into six positive tetrahedra (Kuhn), its points
// numbered in a shuffled order (as a mesher's insertion order may leave them), one point no cell
// uses, and its two end faces (z = 0, z = nz) as tagged boundary triangles.
TetMesh shuffled_box(int nx, int ny, int nz, unsigned seed) {
  const int n = (nx + 1) * (ny + 1) * (nz + 1);
  std::vector<int> label(n);
  std::iota(label.begin(), label.end(), 0);
  std::shuffle(label.begin(), label.end(), std::mt19937(seed));
  auto id = [&](int i, int j, int k) { return label[(k * (ny + 1) + j) * (nx + 1) + i]; };
  TetMesh m;
  m.points.resize(n + 1);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.points[id(i, j, k)] = Vec3(i, j, k);
  m.points[n] = Vec3(-5, -5, -5);  // used by no cell
  static const int path[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : path) {
          int c[3] = {i, j, k};
          Tet t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 2; ++s) {
            ++c[p[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          c[3 - p[0] - p[1]]++;
          t[3] = id(c[0], c[1], c[2]);
          if (tet_volume6(m, t) < 0) std::swap(t[2], t[3]);
          m.tets.push_back(t);
          m.tet_layer.push_back(k);
          m.tet_column.push_back(j * nx + i);
        }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.boundary.push_back({id(i, j, 0), id(i, j + 1, 0), id(i + 1, j, 0)});
      m.boundary_tags.push_back(2);
      m.boundary.push_back({id(i, j, nz), id(i + 1, j, nz), id(i, j + 1, nz)});
      m.boundary_tags.push_back(3);
    }
  return m;
}

TEST(CuthillMcKee, NarrowsTheBandOfAShuffledMeshAndKeepsEveryCell) {
  const TetMesh box = shuffled_box(6, 5, 30, 11);
  const int n = box.num_points();
  const std::vector<int> order = cuthill_mckee_order(box);
  ASSERT_EQ(static_cast<int>(order.size()), n);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < n; ++k) ASSERT_EQ(sorted[k], k);  // a permutation
  EXPECT_EQ(order.back(), n - 1);  // the point of no cell, last
  EXPECT_EQ(cuthill_mckee_order(box), order);  // the same, run after run

  const TetMesh r = renumbered(box, order);
  // The shuffled numbering spans the whole mesh; the new one about two cross-sections of the
  // long box (7 x 6 points a section; a Kuhn cube joins points a section and a row apart).
  EXPECT_GT(point_bandwidth(box), n / 2);
  EXPECT_LE(point_bandwidth(r), 2 * 7 * 6 + 2 * 7);
  // The same cells at the same places, positive, their data with them, sorted by new numbers.
  ASSERT_EQ(r.tets.size(), box.tets.size());
  auto key = [](const TetMesh& m, const Tet& t, int layer, int column) {
    std::array<double, 5> k = {0, 0, 0, double(layer), double(column)};
    for (int v : t) k[0] += m.points[v].x(), k[1] += m.points[v].y(), k[2] += m.points[v].z();
    return k;
  };
  std::vector<std::array<double, 5>> before, after;
  for (size_t c = 0; c < box.tets.size(); ++c) {
    before.push_back(key(box, box.tets[c], box.tet_layer[c], box.tet_column[c]));
    after.push_back(key(r, r.tets[c], r.tet_layer[c], r.tet_column[c]));
    EXPECT_NEAR(tet_volume6(r, r.tets[c]), 1.0, 1e-12);
    if (c > 0) {
      EXPECT_LE(*std::min_element(r.tets[c - 1].begin(), r.tets[c - 1].end()),
                *std::min_element(r.tets[c].begin(), r.tets[c].end()));
    }
  }
  std::sort(before.begin(), before.end());
  std::sort(after.begin(), after.end());
  EXPECT_EQ(before, after);
  // Boundary triangles in their order, at the same places, with their tags.
  ASSERT_EQ(r.boundary.size(), box.boundary.size());
  EXPECT_EQ(r.boundary_tags, box.boundary_tags);
  for (size_t f = 0; f < box.boundary.size(); ++f)
    for (int i = 0; i < 3; ++i) EXPECT_EQ(r.points[r.boundary[f][i]], box.points[box.boundary[f][i]]);
}

TEST(CuthillMcKee, EveryConnectedPartIsNumberedInOneRun) {
  // Two boxes side by side, not touching: each part's points take consecutive numbers.
  TetMesh a = shuffled_box(3, 3, 4, 1);
  const TetMesh b = shuffled_box(2, 2, 3, 2);
  a.points.pop_back();  // drop the stray point of the first box
  const int base = a.num_points();
  for (const Vec3& x : b.points) a.points.push_back(x + Vec3(20, 0, 0));
  for (Tet t : b.tets) {
    for (int& v : t) v += base;
    a.tets.push_back(t);
  }
  a.tet_layer.clear();
  a.tet_column.clear();
  const std::vector<int> order = cuthill_mckee_order(a);
  const TetMesh r = renumbered(a, order);
  const int parts = r.num_points() - 1;  // the last point is the second box's stray one
  int switches = 0;
  for (int k = 1; k < parts; ++k) switches += (r.points[k].x() > 10) != (r.points[k - 1].x() > 10);
  EXPECT_EQ(switches, 1);
}

}  // namespace
}  // namespace vesselmesh::mesh
