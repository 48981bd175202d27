#include "io/msh.h"

#include "io/atomic_file.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace vesselmesh::io {
namespace {

TEST(Msh, WritesVersion41WithPhysicalGroupsAndReadsBack) {
  test::TemporaryFolder tmp;
  const TriMesh m = synth::cylinder({.radius = 1.0, .length = 2.0, .resolution = 0.4, .capped = true});
  write_msh(tmp.path("c.msh"), m, {{1, "wall"}, {2, "inlet"}, {3, "outlet_1"}});
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"c.msh"});
  const std::string text = read_file(tmp.path("c.msh"));
  EXPECT_EQ(text.rfind("$MeshFormat\n4.1 0 8\n", 0), 0u) << text.substr(0, 40);
  EXPECT_NE(text.find("\"inlet\""), std::string::npos);

  std::map<int, std::string> names;
  const TriMesh back = read_msh_surface(tmp.path("c.msh"), &names);
  EXPECT_EQ(back.num_triangles(), m.num_triangles());
  EXPECT_EQ(back.num_points(), m.num_points());
  EXPECT_EQ(names, (std::map<int, std::string>{{1, "wall"}, {2, "inlet"}, {3, "outlet_1"}}));
  std::map<int, int> before, after;
  for (int l : m.labels) ++before[l];
  for (int l : back.labels) ++after[l];
  EXPECT_EQ(before, after);
}

TEST(Msh, UnlabelledSurfaceIsOneGroup) {
  test::TemporaryFolder tmp;
  write_msh(tmp.path("t.msh"), test::tetrahedron());
  std::map<int, std::string> names;
  const TriMesh back = read_msh_surface(tmp.path("t.msh"), &names);
  EXPECT_EQ(back.num_triangles(), 4);
  EXPECT_EQ(names, (std::map<int, std::string>{{1, "surface"}}));
}

TEST(Msh, BadFileIsAnInputError) {
  test::TemporaryFolder tmp;
  test::write_bytes(tmp.path("bad.msh"), "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n");
  EXPECT_THROW(read_msh_surface(tmp.path("bad.msh")), InputError);
  EXPECT_THROW(read_msh_surface(tmp.path("missing.msh")), InputError);
}

}  // namespace
}  // namespace vesselmesh::io

namespace vesselmesh::io {
namespace {

// One prism on the wall triangle (0, 1, 2) (z = 0, facing -z) topped at z = 1, and a
// tetrahedron on its top: the boundary is every face of the two cells but the shared one.
TetMesh prism_and_tet() {
  TetMesh m;
  m.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {0.3, 0.3, 2}};
  m.prisms = {{0, 1, 2, 3, 4, 5}};
  m.tets = {{3, 5, 4, 6}};
  EXPECT_GT(mesh::tet_volume6(m, m.tets[0]), 0.0);
  std::vector<Tet> all(m.tets);
  for (const Tet& t : mesh::split_prism(m.prisms[0])) all.push_back(t);
  m.boundary = mesh::tet_boundary(all);
  for (const Triangle& f : m.boundary) {
    const bool wall = f[0] < 3 && f[1] < 3 && f[2] < 3;
    m.boundary_tags.push_back(wall ? 1 : 2);
  }
  m.tag_names = {{1, "wall"}, {2, "rest"}};
  m.volume_tag = 7;
  return m;
}

TEST(MshVolume, RoundTripKeepsCellsTagsAndNames) {
  test::TemporaryFolder tmp;
  const TetMesh m = prism_and_tet();
  write_msh(tmp.path("v.msh"), m);
  const TetMesh back = read_msh_volume(tmp.path("v.msh"));
  EXPECT_EQ(back.points, m.points);
  EXPECT_EQ(back.tets, m.tets);
  EXPECT_EQ(back.prisms, m.prisms);
  EXPECT_EQ(back.volume_tag, 7);
  EXPECT_EQ(back.volume_name, "fluid");
  EXPECT_EQ(back.tag_names, m.tag_names);
  ASSERT_EQ(back.boundary.size(), m.boundary.size());
  for (size_t i = 0; i < m.boundary.size(); ++i) {
    const auto it = std::find(back.boundary.begin(), back.boundary.end(), m.boundary[i]);
    ASSERT_NE(it, back.boundary.end());
    EXPECT_EQ(back.boundary_tags[it - back.boundary.begin()], m.boundary_tags[i]);
  }
  // A surface MSH is not a volume: a clear error.
  write_msh(tmp.path("s.msh"), test::tetrahedron());
  EXPECT_THROW(read_msh_volume(tmp.path("s.msh")), InputError);
  EXPECT_THROW(read_msh_volume(tmp.path("none.msh")), InputError);
}

}  // namespace
}  // namespace vesselmesh::io
