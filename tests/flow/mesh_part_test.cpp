#include "flow/mesh_part.h"

#include "analysis/open_ends.h"
#include "mesh/error.h"
#include "post/wss.h"
#include "synth/shapes.h"
#include "test_support.h"
#include "volume/volume_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace vesselmesh::flow {
namespace {

// A pipe along +z (mm) with a 4-layer boundary layer, tagged wall / inlet / outlet_1.
TetMesh pipe_volume(double radius, double length, double resolution) {
  const TriMesh pipe = synth::cylinder({.radius = radius, .length = length, .resolution = resolution});
  auto ends = analysis::open_ends(pipe);
  volume::VolumeOptions options;
  options.inlet = ends[0].center.z() < ends[1].center.z() ? 0 : 1;
  return volume::build_volume(pipe, ends, std::vector<double>(pipe.points.size(), radius), options).mesh;
}

// The points in consecutive blocks of the graph's numbering (PT-Scotch's stand-in on one process).
std::vector<int> blocks(const std::vector<int>& start, const std::vector<int>&, int parts) {
  const int total = static_cast<int>(start.size()) - 1;
  std::vector<int> part(total);
  for (int k = 0; k < total; ++k) part[k] = static_cast<int>(static_cast<long long>(k) * parts / total);
  return part;
}

int tag_of(const TetMesh& mesh, const std::string& name) {
  for (const auto& [tag, n] : mesh.tag_names)
    if (n == name) return tag;
  return -1;
}

// Split in three, the parts hold the mesh once: every point owned by one part (the owned ranges
// tile the global numbering), every local point where the mesh has it, every cell in the part of
// each of its points' owners and written by one (its least point's), every boundary triangle
// counted by one (its first point's owner), each part's points the ones its cells use.
TEST(MeshPart, PartsHoldTheMeshOnce) {
  const TetMesh mesh = pipe_volume(2.0, 8.0, 0.7);
  const MeshSplitter splitter(mesh, "pipe.msh", 3, blocks, {"wall"});
  ASSERT_EQ(splitter.parts(), 3);
  const std::vector<Tet> cells = mesh::all_tetrahedra(mesh);
  std::vector<int> owner(mesh.num_points(), -1);
  int written = 0, counted = 0, owned = 0;
  std::set<std::array<int, 4>> seen;
  for (int r = 0; r < 3; ++r) {
    const MeshPart p = splitter.part(r);
    EXPECT_EQ(p.total_points, mesh.num_points());
    EXPECT_EQ(p.mesh_tetrahedra, static_cast<int>(cells.size()));
    EXPECT_EQ(p.process_begin[r + 1] - p.process_begin[r], p.owned);
    EXPECT_EQ(p.global_mesh_point.empty(), r != 0);
    owned += p.owned;
    for (int a = 0; a < static_cast<int>(p.points.size()); ++a) {
      EXPECT_EQ(p.points[a], mesh.points[p.mesh_point[a]]);
      if (a < p.owned) {
        EXPECT_EQ(owner[p.mesh_point[a]], -1);
        owner[p.mesh_point[a]] = r;
        EXPECT_EQ(p.local_global[a], p.process_begin[r] + a);
      } else {
        EXPECT_TRUE(p.local_global[a] < p.process_begin[r] || p.local_global[a] >= p.process_begin[r + 1]);
      }
    }
    std::vector<char> used(p.points.size(), 0);
    for (const Tet& t4 : p.tets) {
      bool mine = false;
      int least = t4[0];
      for (int a : t4) {
        used[a] = 1;
        mine = mine || a < p.owned;
        if (p.local_global[a] < p.local_global[least]) least = a;
      }
      EXPECT_TRUE(mine);
      if (least < p.owned) {
        ++written;
        std::array<int, 4> key{p.mesh_point[t4[0]], p.mesh_point[t4[1]], p.mesh_point[t4[2]], p.mesh_point[t4[3]]};
        std::sort(key.begin(), key.end());
        EXPECT_TRUE(seen.insert(key).second);
      }
    }
    for (const Tet& t4 : p.wall.cells)
      for (int a : t4) used[a] = 1;
    EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "part " << r << " holds points no cell uses";
    for (size_t f = 0; f < p.boundary.size(); ++f)
      if (p.boundary[f][0] < p.owned) ++counted;
  }
  EXPECT_EQ(owned, mesh.num_points());
  EXPECT_EQ(std::count(owner.begin(), owner.end(), -1), 0);
  EXPECT_EQ(written, static_cast<int>(cells.size()));
  EXPECT_EQ(counted, static_cast<int>(mesh.boundary.size()));
}

// Each part's wall (MeshPart::wall) gives the wall shear stress the whole mesh gives at every
// point of the triangles it writes, for both methods (the quadratic's 2-ring stencils within its
// cells), on a velocity field that is no polynomial; every wall triangle written by one part.
TEST(MeshPart, EachPartsWallGivesTheWholeWallsStress) {
  const TetMesh mesh = pipe_volume(2.0, 8.0, 0.7);
  const int wall_tag = tag_of(mesh, "wall");
  ASSERT_GE(wall_tag, 0);
  const std::vector<Tet> cells = mesh::all_tetrahedra(mesh);
  const auto velocity_at = [](const Vec3& x) {
    return Vec3(0.1 * std::sin(x.z()), 0.05 * x.x() * x.y(), std::exp(-0.3 * (x.x() * x.x() + x.y() * x.y())));
  };
  std::vector<Vec3> si(mesh.points.size()), velocity(mesh.points.size());
  for (size_t i = 0; i < si.size(); ++i) {
    si[i] = mesh.points[i] * 1e-3;
    velocity[i] = velocity_at(mesh.points[i]);
  }
  const post::WallSurface whole = post::extract_wall(mesh, cells, {wall_tag});
  std::vector<int> wall_point_of(mesh.num_points(), -1);
  for (int v = 0; v < whole.mesh.num_points(); ++v) wall_point_of[whole.volume_point[v]] = v;
  const MeshSplitter splitter(mesh, "pipe.msh", 3, blocks, {"wall"});
  for (post::WssMethod method : {post::WssMethod::quadratic, post::WssMethod::face}) {
    SCOPED_TRACE(post::to_string(method));
    const std::vector<Vec3> expected = post::wall_shear_stress(whole, cells, si, velocity, 0.0035, method);
    double largest = 0.0;
    for (const Vec3& t : expected) largest = std::max(largest, t.norm());
    int written = 0;
    for (int r = 0; r < 3; ++r) {
      const MeshPart p = splitter.part(r);
      TetMesh band;
      band.points = p.points;
      band.boundary = p.wall.triangles;
      band.boundary_tags = p.wall.tags;
      const post::WallSurface wall = post::extract_wall(band, p.wall.cells, {wall_tag});
      std::vector<Vec3> local_si(p.points.size()), local_velocity(p.points.size());
      for (size_t a = 0; a < p.points.size(); ++a) {
        local_si[a] = p.points[a] * 1e-3;
        local_velocity[a] = velocity_at(p.points[a]);
      }
      const std::vector<Vec3> tau = post::wall_shear_stress(wall, p.wall.cells, local_si, local_velocity, 0.0035, method);
      for (size_t f = 0; f < p.wall.triangles.size(); ++f) {
        if (!p.wall.written[f]) continue;
        ++written;
        for (int v : wall.mesh.triangles[f]) {
          const int m = p.mesh_point[wall.volume_point[v]];
          EXPECT_LT((tau[v] - expected[wall_point_of[m]]).norm(), 1e-12 * largest) << "mesh point " << m;
        }
      }
    }
    EXPECT_EQ(written, static_cast<int>(whole.mesh.triangles.size()));
  }
}

// A part as bytes and back is the same part; bytes that are not one are an InternalError.
TEST(MeshPart, PackedPartReadsBack) {
  const TetMesh mesh = pipe_volume(2.0, 6.0, 0.8);
  const MeshSplitter splitter(mesh, "pipe.msh", 2, blocks, {"wall"});
  for (int r = 0; r < 2; ++r) {
    const MeshPart p = splitter.part(r);
    const MeshPart q = unpack(pack(p));
    EXPECT_EQ(q.total_points, p.total_points);
    EXPECT_EQ(q.process_begin, p.process_begin);
    EXPECT_EQ(q.owned, p.owned);
    EXPECT_EQ(q.local_global, p.local_global);
    EXPECT_EQ(q.mesh_point, p.mesh_point);
    EXPECT_EQ(q.points, p.points);
    EXPECT_EQ(q.tets, p.tets);
    EXPECT_EQ(q.boundary, p.boundary);
    EXPECT_EQ(q.boundary_tags, p.boundary_tags);
    EXPECT_EQ(q.point_tags, p.point_tags);
    EXPECT_EQ(q.tag_names, p.tag_names);
    EXPECT_EQ(q.mesh_tetrahedra, p.mesh_tetrahedra);
    EXPECT_EQ(q.global_mesh_point, p.global_mesh_point);
    EXPECT_EQ(q.wall.cells, p.wall.cells);
    EXPECT_EQ(q.wall.triangles, p.wall.triangles);
    EXPECT_EQ(q.wall.written, p.wall.written);
    EXPECT_EQ(q.wall.points, p.wall.points);
    EXPECT_FALSE(q.wall.cells.empty());
  }
  std::string cut = pack(splitter.part(1));
  cut.resize(cut.size() / 2);
  EXPECT_THROW(unpack(cut), InternalError);
}

// An inverted cell, an empty mesh and more parts than points are input errors naming the file.
TEST(MeshPart, BadMeshesAreNamed) {
  TetMesh mesh = pipe_volume(2.0, 6.0, 0.8);
  const auto message = [&](const TetMesh& m, int parts) {
    try {
      MeshSplitter(m, "bad.msh", parts, blocks);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  TetMesh tiny;
  tiny.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  tiny.tets = {{0, 1, 2, 3}};
  EXPECT_NE(message(tiny, 5).find("5 processes for a mesh of 4 points"), std::string::npos) << message(tiny, 5);
  EXPECT_EQ(message(tiny, 4), "");
  EXPECT_NE(message(TetMesh{}, 1).find("bad.msh: the mesh has no tetrahedra"), std::string::npos);
  std::swap(mesh.tets[7][0], mesh.tets[7][1]);
  EXPECT_NE(message(mesh, 2).find("inverted or flat"), std::string::npos) << message(mesh, 2);
}

}  // namespace
}  // namespace vesselmesh::flow
