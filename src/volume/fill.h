// The interior tetrahedra of a closed, outward-oriented triangle surface, through Gmsh's C++
// API: the surface becomes a discrete surface whose triangles and nodes are kept as they are,
// bounding a volume Gmsh fills (sizes from the size function handed in, volume/interior_size.h,
// or, without one, grown from the boundary's edge lengths; Gmsh's own tetrahedron optimization
// runs, the boundary is never changed). Algorithms: Gmsh's Delaunay
// (default), Frontal (needs a Gmsh built with Netgen; an OptionError otherwise) and HXT
// (Marot et al. 2019, Gmsh's fastest, threaded); and TetGen (volume/tetgen_fill.h: the boundary
// kept, quality-bounded, deterministic).
#pragma once

#include "mesh/reporter.h"
#include "mesh/tetmesh.h"

#include <functional>
#include <string>
#include <vector>

namespace vesselmesh::volume {

enum class FillAlgorithm { delaunay, frontal, hxt, tetgen };
FillAlgorithm parse_fill_algorithm(const std::string& name);
const char* fill_algorithm_name(FillAlgorithm algorithm);

struct FillResult {
  std::vector<Vec3> points;  // `points` handed in, then the points Gmsh added
  std::vector<Tet> tets;     // positive volume
};

// The edge length wanted at a point of the interior (mm); called from several threads by HXT.
using SizeFunction = std::function<double(const Vec3&)>;

// `points` may hold points the boundary does not use (they are left alone). `threads`: for
// HXT; 0 = as many as TBB would use. `size`: the interior's sizes (every engine follows it; an
// empty function: each engine's own sizes from the boundary's edges).
FillResult fill_tetrahedra(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary,
                           FillAlgorithm algorithm, int threads = 0, const Reporter& reporter = silent_reporter(),
                           const SizeFunction& size = {});

}  // namespace vesselmesh::volume
