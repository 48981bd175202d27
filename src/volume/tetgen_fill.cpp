#include "volume/tetgen_fill.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"

#include <fmt/format.h>

#define TETLIBRARY
#include <tetgen.h>

#include <dlfcn.h>

#include <string>

namespace vesselmesh::volume {
namespace {

using Tetrahedralize = void (*)(char*, tetgenio*, tetgenio*, tetgenio*, tetgenio*);

// TetGen's entry point, its library opened with its own symbols first (RTLD_DEEPBIND): libgmsh,
// already loaded, exports another TetGen's classes under the same names, and TetGen's internal
// calls would otherwise land there.
Tetrahedralize tetgen_entry() {
  static const Tetrahedralize entry = []() -> Tetrahedralize {
    void* library = dlopen(VESSELMESH_TETGEN_SONAME, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
    if (!library) return nullptr;
    return reinterpret_cast<Tetrahedralize>(dlsym(library, "_Z14tetrahedralizePcP8tetgenioS1_S1_S1_"));
  }();
  if (!entry)
    throw InputError(fmt::format("--algorithm tetgen: TetGen's library {} could not be opened ({}); install it "
                                 "(apt-get install libtet1.5) or use delaunay or hxt",
                                 VESSELMESH_TETGEN_SONAME, dlerror() ? dlerror() : "no tetrahedralize in it"));
  return entry;
}

// TetGen's exit codes (terminatetetgen) in words, with what to do.
std::string tetgen_reason(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "the surface intersects itself: repair it (vesselmesh info lists the defects)";
    case 4: return "a feature of the surface is too small for its bounding box (a tiny edge or a very thin part)";
    case 5: return "two facets of the surface are nearly touching: remesh it more coarsely there";
    case 10: return "the boundary it was given is not a valid closed surface";
    default: return fmt::format("error code {}", code);
  }
}

// TetGen's refinement callback has no argument of ours: the size function and the factor of the
// one call under way (TetGen runs on the calling thread).
thread_local const SizeFunction* g_size = nullptr;
thread_local double g_circumradius_factor = 1.0;

// True when tetrahedron (a, b, c, d) is larger than the size function asks: its circumradius
// above the factor times the size at its centroid.
bool too_large(REAL* a, REAL* b, REAL* c, REAL* d, REAL*, REAL) {
  const Vec3 pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pc(c[0], c[1], c[2]), pd(d[0], d[1], d[2]);
  const Vec3 u = pb - pa, v = pc - pa, w = pd - pa;
  const double det = 2.0 * u.dot(v.cross(w));
  if (det == 0.0) return false;
  const Vec3 centre = (u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v)) / det;
  const double size = (*g_size)(0.25 * (pa + pb + pc + pd));
  return centre.norm() > g_circumradius_factor * size;
}

// Sets the callback's size function for one TetGen run.
class SizeForTetgen {
 public:
  SizeForTetgen(const SizeFunction* size, double factor) {
    g_size = size;
    g_circumradius_factor = factor;
  }
  ~SizeForTetgen() { g_size = nullptr; }
  SizeForTetgen(const SizeForTetgen&) = delete;
  SizeForTetgen& operator=(const SizeForTetgen&) = delete;
};

}  // namespace

FillResult tetgen_fill(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary,
                       const TetgenQuality& quality, const Reporter& reporter, const SizeFunction& size) {
  // TetGen's points: those the boundary uses, in index order (others would become vertices of
  // the mesh); `ours` leads back.
  std::vector<int> index_of(points.size(), -1), ours;
  for (const Triangle& f : boundary)
    for (int v : f) index_of[v] = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (index_of[i] == 0) {
      index_of[i] = static_cast<int>(ours.size());
      ours.push_back(static_cast<int>(i));
    }
  const int n = static_cast<int>(ours.size());
  // TetGen reads past its arrays on a surface with a hole (measured: a heap corruption): every
  // edge must bound exactly two triangles.
  TriMesh closed;
  for (int i : ours) closed.points.push_back(points[i]);
  for (const Triangle& f : boundary) closed.triangles.push_back({index_of[f[0]], index_of[f[1]], index_of[f[2]]});
  const mesh::EdgeMap edges = mesh::build_edge_map(closed);
  for (size_t t = 0; t < closed.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (edges.triangle_edges[t][k] < 0)
        throw InputError(fmt::format("the lumen's boundary has a degenerate triangle at ({:.4g}, {:.4g}, {:.4g})",
                                     closed.points[closed.triangles[t][k]].x(),
                                     closed.points[closed.triangles[t][k]].y(),
                                     closed.points[closed.triangles[t][k]].z()));
  for (int e = 0; e < edges.num_edges(); ++e)
    if (edges.valence(e) != 2) {
      const Vec3 mid = 0.5 * (closed.points[edges.edges[e][0]] + closed.points[edges.edges[e][1]]);
      throw InputError(fmt::format("the lumen's boundary is not closed: the edge at ({:.4g}, {:.4g}, {:.4g}) bounds "
                                   "{} triangle(s), not 2",
                                   mid.x(), mid.y(), mid.z(), edges.valence(e)));
    }
  // Each boundary point's size: the mean length of its edges (each edge counted from both of its triangles).
  std::vector<double> edge_sum(n, 0.0);
  std::vector<int> edge_count(n, 0);
  for (const Triangle& f : boundary)
    for (int k = 0; k < 3; ++k) {
      const int a = index_of[f[k]], b = index_of[f[(k + 1) % 3]];
      const double length = (closed.points[a] - closed.points[b]).norm();
      edge_sum[a] += length;
      edge_sum[b] += length;
      edge_count[a] += 1;
      edge_count[b] += 1;
    }

  tetgenio in, result;
  in.firstnumber = 0;
  in.numberofpoints = n;
  in.pointlist = new REAL[3 * n];
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) in.pointlist[3 * i + c] = closed.points[i][c];
  if (!size) {
    in.numberofpointmtrs = 1;
    in.pointmtrlist = new REAL[n];
    for (int i = 0; i < n; ++i) in.pointmtrlist[i] = quality.size_factor * edge_sum[i] / edge_count[i];
  } else {
    in.tetunsuitable = too_large;
  }
  in.numberoffacets = static_cast<int>(boundary.size());
  in.facetlist = new tetgenio::facet[boundary.size()];
  in.facetmarkerlist = new int[boundary.size()];
  for (size_t t = 0; t < boundary.size(); ++t) {
    tetgenio::facet& f = in.facetlist[t];
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = 3;
    f.polygonlist[0].vertexlist = new int[3];
    for (int c = 0; c < 3; ++c) f.polygonlist[0].vertexlist[c] = index_of[boundary[t][c]];
    in.facetmarkerlist[t] = 1;
  }

  // p: a piecewise linear complex; Y: its surface kept; z: numbered from 0; Q: quiet; q: quality
  // bounds; m: the sizes at the points (without a size function).
  std::string switches =
      fmt::format("pYzQ{}q{:g}/{:g}", size ? "" : "m", quality.radius_edge_ratio, quality.min_dihedral_deg);
  reporter.progress("interior tetrahedra", 0.0);
  const SizeForTetgen sizing(size ? &size : nullptr, quality.circumradius_factor);
  try {
    tetgen_entry()(switches.data(), &in, &result, nullptr, nullptr);
  } catch (int code) {
    throw InputError(fmt::format("TetGen could not fill the lumen: {}", tetgen_reason(code)));
  }
  reporter.progress("interior tetrahedra", 1.0);

  if (result.numberofpoints < n)
    throw InternalError(fmt::format("TetGen returned {} points for {} boundary points", result.numberofpoints, n));
  for (int i = 0; i < n; ++i)
    if (Vec3(result.pointlist[3 * i], result.pointlist[3 * i + 1], result.pointlist[3 * i + 2]) != closed.points[i])
      throw InternalError(fmt::format("TetGen moved boundary point {}", i));
  FillResult out;
  out.points = points;
  for (int i = n; i < result.numberofpoints; ++i) {
    ours.push_back(static_cast<int>(out.points.size()));
    out.points.emplace_back(result.pointlist[3 * i], result.pointlist[3 * i + 1], result.pointlist[3 * i + 2]);
  }
  out.tets.reserve(result.numberoftetrahedra);
  for (int t = 0; t < result.numberoftetrahedra; ++t) {
    Tet tet;
    for (int c = 0; c < 4; ++c) tet[c] = ours[result.tetrahedronlist[result.numberofcorners * t + c]];
    const Vec3& a = out.points[tet[0]];
    if ((out.points[tet[1]] - a).cross(out.points[tet[2]] - a).dot(out.points[tet[3]] - a) < 0.0)
      std::swap(tet[2], tet[3]);
    out.tets.push_back(tet);
  }
  return out;
}

}  // namespace vesselmesh::volume
