#include "volume/fill.h"

#include "mesh/error.h"
#include "volume/gmsh_fill.h"
#include "volume/tetgen_fill.h"

#include <fmt/format.h>

namespace vesselmesh::volume {

FillAlgorithm parse_fill_algorithm(const std::string& name) {
  if (name == "delaunay") return FillAlgorithm::delaunay;
  if (name == "frontal") return FillAlgorithm::frontal;
  if (name == "hxt") return FillAlgorithm::hxt;
  if (name == "tetgen") return FillAlgorithm::tetgen;
  throw OptionError(fmt::format("--algorithm {}: give delaunay, frontal, hxt or tetgen", name));
}

const char* fill_algorithm_name(FillAlgorithm algorithm) {
  switch (algorithm) {
    case FillAlgorithm::delaunay: return "delaunay";
    case FillAlgorithm::frontal: return "frontal";
    case FillAlgorithm::hxt: return "hxt";
    case FillAlgorithm::tetgen: return "tetgen";
  }
  return "?";
}

FillResult fill_tetrahedra(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary,
                           FillAlgorithm algorithm, int threads, const Reporter& reporter, const SizeFunction& size) {
  if (algorithm == FillAlgorithm::tetgen) return tetgen_fill(points, boundary, {}, reporter, size);
  return gmsh_fill(points, boundary, algorithm, threads, reporter, size);
}

}  // namespace vesselmesh::volume
