#include "io/msh_stream.h"

#include "io/msh.h"
#include "io/volume_file.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"
#include "volume/volume_mesh.h"

#include "analysis/open_ends.h"

#include <gtest/gtest.h>

namespace vesselmesh::io {
namespace {

// Everything read_msh41_volume gives equals Gmsh's reader's (io::read_msh_volume).
void expect_same(const TetMesh& a, const TetMesh& b) {
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.prisms, b.prisms);
  EXPECT_EQ(a.boundary, b.boundary);
  EXPECT_EQ(a.boundary_tags, b.boundary_tags);
  EXPECT_EQ(a.tag_names, b.tag_names);
  EXPECT_EQ(a.volume_tag, b.volume_tag);
  EXPECT_EQ(a.volume_name, b.volume_name);
}

// What `vesselmesh volume` writes (a pipe with its layer's prisms kept, Gmsh's MSH 4.1 text): the
// same mesh as Gmsh reads, to the bit.
TEST(MshStream, ReadsWhatVolumeWritesAsGmshDoes) {
  test::TemporaryFolder tmp;
  const TriMesh pipe = synth::cylinder({.radius = 2.0, .length = 6.0, .resolution = 0.6});
  auto ends = analysis::open_ends(pipe);
  volume::VolumeOptions options;
  options.keep_prisms = true;
  const TetMesh mesh =
      volume::build_volume(pipe, ends, std::vector<double>(pipe.points.size(), 2.0), options).mesh;
  ASSERT_GT(mesh.num_prisms(), 0);
  write_msh(tmp.path("pipe.msh"), mesh);
  const std::optional<TetMesh> streamed = read_msh41_volume(tmp.path("pipe.msh"));
  ASSERT_TRUE(streamed.has_value());
  expect_same(*streamed, read_msh_volume(tmp.path("pipe.msh")));
  EXPECT_EQ(streamed->num_tets(), mesh.num_tets());
  EXPECT_EQ(streamed->prisms, mesh.prisms);
}

// A file as other tools write them: nodes in several entity blocks out of order, tags with gaps,
// a name with a space, an unnamed surface, two volumes, sections and elements this reader skips.
TEST(MshStream, EntitiesOutOfOrderGapsAndSkippedSections) {
  test::TemporaryFolder tmp;
  test::write_bytes(tmp.path("m.msh"), R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Comments
anything $Nodes here is skipped
$EndComments
$PhysicalNames
3
2 5 "outlet one"
2 9 "wall"
3 4 "blood"
$EndPhysicalNames
$Entities
0 1 3 2
3 0 0 0 1 1 1 0 0
2 0 0 0 1 1 1 1 9 1 3
1 0 0 0 1 1 1 1 5 1 3
7 0 0 0 1 1 1 0 1 3
6 0 0 0 1 1 1 1 4 2 1 2
3 0 0 0 1 1 1 0 1 1
$EndEntities
$Nodes
3 6 10 60
3 6 0 1
60
1.5 1.5 1.5
2 2 0 3
10
20
30
0 0 0
1 0 0
0 1 0
2 1 1 2
40
50
0 0 1 0.5 0.5
1 1 1 0.2 0.3
$EndNodes
$Elements
5 7 1 7
1 3 1 1
1 10 20
2 2 2 1
2 10 20 30
2 7 2 1
3 10 30 40
3 6 4 2
4 10 20 30 40
5 20 30 40 50
3 3 4 1
6 40 50 60 10
$EndElements
$Custom
1 2 3
$EndCustom
)");
  const std::optional<TetMesh> streamed = read_msh41_volume(tmp.path("m.msh"));
  ASSERT_TRUE(streamed.has_value());
  const TetMesh gmsh = read_msh_volume(tmp.path("m.msh"));
  expect_same(*streamed, gmsh);
  // Spelled out: the nodes by entity (dimension, then tag: surface 1's 40 and 50, surface 2's 10, 20
  // and 30, volume 6's 60), the volumes' tetrahedra by entity (3, then 6), the surfaces' triangles
  // (2, then 7).
  ASSERT_EQ(streamed->num_points(), 6);
  EXPECT_EQ(streamed->points[0], Vec3(0, 0, 1));
  EXPECT_EQ(streamed->points[2], Vec3(0, 0, 0));
  EXPECT_EQ(streamed->points[5], Vec3(1.5, 1.5, 1.5));
  EXPECT_EQ(streamed->tets, (std::vector<Tet>{{0, 1, 5, 2}, {2, 3, 4, 0}, {3, 4, 0, 1}}));
  EXPECT_EQ(streamed->boundary, (std::vector<Triangle>{{2, 3, 4}, {2, 4, 0}}));
  EXPECT_EQ(streamed->tag_names, (std::map<int, std::string>{{5, "outlet one"}, {7, "tag_7"}, {9, "wall"}}));
  EXPECT_EQ(streamed->boundary_tags, (std::vector<int>{9, 7}));
  EXPECT_EQ(streamed->volume_tag, 4);
  EXPECT_EQ(streamed->volume_name, "blood");
}

// Node tags far apart (a tag range over four times the nodes) are looked up in a map.
TEST(MshStream, SparseNodeTags) {
  test::TemporaryFolder tmp;
  test::write_bytes(tmp.path("s.msh"), R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 4 7 9000000000
3 1 0 4
7
8
9000000000
12
0 0 0
1 0 0
0 1 0
0 0 1
$EndNodes
$Elements
1 1 1 1
3 1 4 1
1 7 8 12 9000000000
$EndElements
)");
  const std::optional<TetMesh> m = read_msh41_volume(tmp.path("s.msh"));
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->tets, (std::vector<Tet>{{0, 1, 3, 2}}));
  EXPECT_EQ(m->points[2], Vec3(0, 1, 0));
}

// Another version or a binary file is Gmsh's to read (io::read_volume falls back to it).
TEST(MshStream, OtherVersionsAreLeftToGmsh) {
  test::TemporaryFolder tmp;
  test::write_bytes(tmp.path("v2.msh"), R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
$EndNodes
$Elements
1
1 4 2 1 1 1 2 3 4
$EndElements
)");
  EXPECT_FALSE(read_msh41_volume(tmp.path("v2.msh")).has_value());
  const TetMesh m = read_volume(tmp.path("v2.msh"));
  EXPECT_EQ(m.num_tets(), 1);
  test::write_bytes(tmp.path("binary.msh"), "$MeshFormat\n4.1 1 8\n");
  EXPECT_FALSE(read_msh41_volume(tmp.path("binary.msh")).has_value());
}

// A broken file: an InputError naming the file and the line.
TEST(MshStream, BrokenFilesNameTheLine) {
  test::TemporaryFolder tmp;
  const auto message = [&](const std::string& text) {
    return test::input_error(tmp.path("b.msh"), text, [](const std::string& f) { read_msh41_volume(f); });
  };
  const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  EXPECT_NE(message(head + "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 zero\n").find("b.msh:8: MSH: expected a node's coordinate"),
            std::string::npos);
  EXPECT_NE(message(head + "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n")
                .find("uses node 2, which the file does not define"),
            std::string::npos);
  EXPECT_NE(message(head + "$Nodes\n1 2 1 2\n").find("the file ends where"), std::string::npos);
  EXPECT_NE(message(head + "$Comments\nno end\n").find("$Comments is not closed by $EndComments"), std::string::npos);
  EXPECT_NE(message(head + "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n").find("no tetrahedra or prisms"),
            std::string::npos);
  EXPECT_THROW(read_msh41_volume(tmp.path("missing.msh")), InputError);
}

}  // namespace
}  // namespace vesselmesh::io
