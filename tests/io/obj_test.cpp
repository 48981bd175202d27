#include "io/obj.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

namespace vesselmesh::io {
namespace {

TEST(Obj, FacesWithSlashesAndNegativeIndices) {
  const TriMesh m = parse_obj(
      "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvn 0 0 1\nvt 0 0\n"
      "f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1\n",
      "q.obj");
  EXPECT_EQ(m.num_points(), 4);
  ASSERT_EQ(m.num_triangles(), 3);
  EXPECT_EQ(m.triangles[2], (Triangle{0, 2, 3}));
  EXPECT_FALSE(m.has_labels());
}

TEST(Obj, GroupsBecomeLabels) {
  const TriMesh m = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng wall\nf 1 2 3\ng cap\nf 1 3 4\ng wall\nf 1 4 2\n", "g.obj");
  EXPECT_EQ(m.labels, (std::vector<int>{1, 2, 1}));
}

std::string error_of(const std::string& text) {
  try {
    parse_obj(text, "bad.obj");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Obj, DamagedFilesNameTheLine) {
  EXPECT_NE(error_of("").find("empty"), std::string::npos);
  EXPECT_NE(error_of("v 0 0 0\nv 1 0\n").find("bad.obj:2"), std::string::npos) << error_of("v 0 0 0\nv 1 0\n");
  EXPECT_NE(error_of("v 0 0 0\nf 1 2 3\n").find("uses point 2"), std::string::npos) << error_of("v 0 0 0\nf 1 2 3\n");
  EXPECT_NE(error_of("v 0 0 0\nv 1 0 0\nf 1 2\n").find("three corners"), std::string::npos);
  EXPECT_NE(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n").find("point number"), std::string::npos);
  EXPECT_NE(error_of("v 0 0 0\n# only a point\n").find("no faces"), std::string::npos);
}

}  // namespace
}  // namespace vesselmesh::io
