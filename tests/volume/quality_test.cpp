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

// A prism column on the wall triangle of points 0, 1, 2: a layer between each three points and the
// next three (`points` 3 per level, from the wall), split into tetrahedra; the wall triangle the
// first boundary triangle (the column's index), tagged 1, the rest 2.
TetMesh prism_column(const std::vector<Vec3>& points) {
  TetMesh m;
  m.points = points;
  for (int k = 0; 3 * k + 5 < static_cast<int>(points.size()); ++k)
    for (const Tet& t : mesh::split_prism({3 * k, 3 * k + 1, 3 * k + 2, 3 * k + 3, 3 * k + 4, 3 * k + 5})) {
      m.tets.push_back(t);
      m.tet_layer.push_back(k + 1);
      m.tet_column.push_back(0);
    }
  m.boundary = mesh::tet_boundary(m.tets);
  std::stable_partition(m.boundary.begin(), m.boundary.end(),
                        [](const Triangle& f) { return f[0] < 3 && f[1] < 3 && f[2] < 3; });
  m.boundary_tags.assign(m.boundary.size(), 2);
  m.boundary_tags[0] = 1;
  return m;
}

TEST(Quality, LayersPerColumnAndThickness) {
  // One prism column of two layers on the wall triangle (0, 1, 2).
  TetMesh m = prism_column(
      {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0.1}, {0, 1, 0.1}, {1, 0, 0.1}, {0, 0, 0.2}, {0, 1, 0.2}, {1, 0, 0.2}});
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

// One layer prism of height h over the wall triangle (0, 0, 0), (0.5, apex, 0), (1, 0, 0) (the
// equilateral one of side 1 by default) in z = 0, split into its three tetrahedra (the column of
// boundary triangle 0, the wall).
TetMesh flat_column(double h, double apex = std::sqrt(3.0) / 2.0) {
  return prism_column({{0, 0, 0}, {0.5, apex, 0}, {1, 0, 0}, {0, 0, h}, {0.5, apex, h}, {1, 0, h}});
}

TEST(Quality, FlatLayerCellsAreRoundInTheLayersFrame) {
  // A prism 1/50 as high as its wall edge: its tetrahedra's least angle is about atan(1/50); in
  // the layer's frame it is the unit prism (as high as its equilateral base is wide).
  const VolumeQuality flat = measure_volume(flat_column(0.02));
  ASSERT_EQ(flat.tets, 3);
  EXPECT_LT(flat.min_dihedral_layer, 2.0);
  EXPECT_GT(flat.min_dihedral_layer, 0.5);
  const VolumeQuality unit = measure_volume(flat_column(1.0));
  EXPECT_NEAR(unit.min_dihedral_layer, std::atan(std::sqrt(3.0) / 2.0) * 180.0 / M_PI, 1e-9);  // 40.89 deg
  EXPECT_NEAR(flat.min_dihedral_layer_frame, unit.min_dihedral_layer, 1e-9);
  EXPECT_NEAR(unit.min_dihedral_layer_frame, unit.min_dihedral_layer, 1e-9);
  // Over a needle wall triangle (an anisotropic wall's, 1/20 as wide as long) the same: the wall's
  // own shape is the surface's, not the layer's.
  const VolumeQuality needle = measure_volume(flat_column(0.002, 0.05));
  EXPECT_LT(needle.min_dihedral_layer, 2.0);
  EXPECT_NEAR(needle.min_dihedral_layer_frame, unit.min_dihedral_layer, 1e-9);
  // No columns: no frame.
  TetMesh plain = flat_column(0.02);
  plain.tet_column.clear();
  EXPECT_EQ(measure_volume(plain).min_dihedral_layer_frame, -1.0);
}

TEST(Quality, ASliverAcrossALayerColumnStaysThinInItsFrame) {
  // Two wall points and two top points whose tetrahedron is flat in the wall's normal direction
  // (as every layer cell) and, in the column's frame, flat across it too: a sliver the layer's
  // frame must show.
  TetMesh m = flat_column(0.02);
  const Tet sliver = {0, 2, static_cast<int>(m.points.size()), static_cast<int>(m.points.size()) + 1};
  m.points.push_back({0.5, 0.01, 0.02});
  m.points.push_back({0.5, -0.01, 0.02});
  const double frame = layer_frame_angle(m, 0, sliver);
  EXPECT_LT(frame, 2.0);
  EXPECT_GT(frame, 0.0);
  // The split prism's own tetrahedra, in the same frame: the unit prism's.
  for (const Tet& t : m.tets) EXPECT_GT(layer_frame_angle(m, 0, t), 40.0);
  // A column pinched to a point above one corner (its top triangle shrunk toward the wall's
  // corner 0): the frame shows the pinch.
  TetMesh pinched = flat_column(0.02);
  pinched.points[4] = {0.02, 0.02, 0.02};
  pinched.points[5] = {0.02, 0.0, 0.02};
  double least = 180.0;
  for (const Tet& t : pinched.tets) least = std::min(least, layer_frame_angle(pinched, 0, t));
  EXPECT_LT(least, 5.0);
  // A cell with no height along the normal (all four in the wall's plane) has no frame: 0.
  EXPECT_EQ(layer_frame_angle(m, 0, {0, 1, 2, 0}), 0.0);
}

}  // namespace
}  // namespace vesselmesh::volume
