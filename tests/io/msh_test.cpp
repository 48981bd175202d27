#include "io/msh.h"

#include "io/atomic_file.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

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
