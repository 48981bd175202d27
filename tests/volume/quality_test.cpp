#include "volume/quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::volume {
namespace {

TetMesh corner_tet() {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.boundary = mesh::tet_boundary(m.tets);
  m.boundary_tags = {1, 1, 1, 2};
  m.tag_names = {{1, "wall"}, {2, "inlet"}};
  return m;
}

TEST(Quality, CornerTetrahedronFigures) {
  const VolumeQuality q = measure_volume(corner_tet());
  EXPECT_EQ(q.tets, 1);
  EXPECT_EQ(q.inverted, 0);
  EXPECT_TRUE(q.closed);
  EXPECT_EQ(q.triangles_per_tag.at("wall"), 3);
  EXPECT_EQ(q.triangles_per_tag.at("inlet"), 1);
  EXPECT_NEAR(q.min_dihedral, std::acos(1.0 / std::sqrt(3.0)) * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(q.max_dihedral, 90.0, 1e-9);
  EXPECT_NEAR(q.worst_scaled_jacobian, std::sqrt(2.0) / 2.0, 1e-12);
  EXPECT_FALSE(q.has_layers);
}

TEST(Quality, InvertedCellAndOpenBoundaryAreCounted) {
  TetMesh m = corner_tet();
  std::swap(m.tets[0][0], m.tets[0][1]);
  m.boundary.pop_back();
  m.boundary_tags.pop_back();
  const VolumeQuality q = measure_volume(m);
  EXPECT_EQ(q.inverted, 1);
  EXPECT_FALSE(q.closed);
  // The swapped tetrahedron's faces all turn inward: none of the tagged three match.
  EXPECT_EQ(q.open_faces, 4);
  EXPECT_EQ(q.stray_triangles, 3);
}

TEST(Quality, LayersPerColumnAndThickness) {
  // One prism column of two layers on the wall triangle (0, 1, 2), split into tetrahedra.
  TetMesh m;
  m.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0.1}, {0, 1, 0.1}, {1, 0, 0.1}, {0, 0, 0.2}, {0, 1, 0.2}, {1, 0, 0.2}};
  for (int k = 0; k < 2; ++k)
    for (const Tet& t : mesh::split_prism({3 * k, 3 * k + 1, 3 * k + 2, 3 * k + 3, 3 * k + 4, 3 * k + 5})) {
      m.tets.push_back(t);
      m.tet_layer.push_back(k + 1);
      m.tet_column.push_back(0);
    }
  m.boundary = mesh::tet_boundary(m.tets);
  // The wall triangle first (the column's index), then the rest.
  std::stable_partition(m.boundary.begin(), m.boundary.end(),
                        [](const Triangle& f) { return f[0] < 3 && f[1] < 3 && f[2] < 3; });
  // Tag 1 on the wall triangle, 2 on the rest.
  m.boundary_tags.assign(m.boundary.size(), 2);
  m.boundary_tags[0] = 1;
  const std::vector<double> radius(m.points.size(), 2.0);
  const VolumeQuality q = measure_volume(m, radius);
  EXPECT_TRUE(q.closed);
  EXPECT_TRUE(q.has_layers);
  EXPECT_EQ(q.min_layers, 2);
  EXPECT_EQ(q.max_layers, 2);
  EXPECT_NEAR(q.min_thickness_ratio, 0.1, 1e-12);
  EXPECT_GT(q.min_dihedral_layer, 0.0);
  EXPECT_EQ(q.min_dihedral_interior, -1.0);
  EXPECT_EQ(q.wall_triangles, 1);
  // A wall-tagged triangle with no cells standing on it counts as a column of no layer.
  m.boundary_tags[1] = 1;
  EXPECT_EQ(measure_volume(m, radius).min_layers, 0);
}

}  // namespace
}  // namespace vesselmesh::volume
