#include "io/medit.h"

#include "io/atomic_file.h"
#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace vesselmesh::io {
namespace {

TEST(Medit, RoundTripKeepsPointsTrianglesAndLabels) {
  test::TemporaryFolder tmp;
  TriMesh m = test::tetrahedron(Vec3(0.1, 0.2, 0.3), 1.7);
  m.labels = {1, 1, 2, 3};
  write_medit(tmp.path("t.mesh"), m);
  const TriMesh back = read_medit(tmp.path("t.mesh"));
  EXPECT_TRUE(back.points == m.points);  // shortest round-trip decimal form: exact
  EXPECT_TRUE(back.triangles == m.triangles);
  EXPECT_TRUE(back.labels == m.labels);
  m.labels.clear();
  write_medit(tmp.path("u.mesh"), m);
  EXPECT_FALSE(read_medit(tmp.path("u.mesh")).has_labels());
}

TEST(Medit, SkipsTheSectionsMmgsAddsAndNamesTheLineOfAnError) {
  const std::string text =
      "MeshVersionFormatted 2\nDimension 3\n# a comment\nVertices\n3\n0 0 0 1\n1 0 0 1\n0 1 0 1\n"
      "Edges\n1\n1 2 0\nTriangles\n1\n1 2 3 7\nRidges\n1\n1\nNormalAtVertices\n1\n1 1\nNormals\n1\n0 0 1\nEnd\n";
  const TriMesh m = parse_medit(text, "ok.mesh");
  EXPECT_EQ(m.num_points(), 3);
  EXPECT_EQ(m.num_triangles(), 1);
  const std::string bad = "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 0\nTriangles\n1\n1 2 3 0\nEnd\n";
  try {
    parse_medit(bad, "bad.mesh");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.mesh:8"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_medit("Vertices\n0\n", "x.mesh"), InputError);
  EXPECT_THROW(parse_medit("", "x.mesh"), InputError);
}

TEST(Medit, MetricIsWrittenInMeditOrder) {
  test::TemporaryFolder tmp;
  write_medit_metric(tmp.path("m.sol"), {Sym3{{1, 2, 3, 4, 5, 6}}});  // xx xy xz yy yz zz
  const std::string text = read_file(tmp.path("m.sol"));
  EXPECT_NE(text.find("SolAtVertices\n1\n1 3\n1 2 4 3 5 6\n"), std::string::npos) << text;  // xx xy yy xz yz zz
}

}  // namespace
}  // namespace vesselmesh::io
