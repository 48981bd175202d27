// The seed paper's remeshing route, through Gmsh's C++ API: the input triangulation is cut into
// patches that a single map can flatten (classifySurfaces with forReparametrization: zero genus,
// moderate aspect ratio, split where normals turn more than the classification angle), each
// patch is parametrized (createGeometry), meshed in its plane by a 2D algorithm to our size
// field (a size callback: the metric at the closest input point), and mapped back.
//
// The field is the one the native engine meets (remesh::effective_metric: the size field
// intersected with the chord bound of the distance bounds), so that both engines can be compared
// on the same input and field. Delaunay, Frontal and MeshAdapt are isotropic: an anisotropic
// metric is met through its smallest size. BAMG takes the whole metric, as a tensor view on the
// input triangles set as Gmsh's background mesh (no size callback); it fits the metric better
// than Delaunay, far less than the native engine, and its stretched triangles can stray from
// curved patches (README: measured figures). No Gmsh algorithm here enforces the distance bound.
//
// Gmsh's tolerances follow the model's size, which adding nodes through the API does not set:
// it is set before classifying (without it the aortic arch's patches came out with edges 0.46 of
// the size asked, whatever the size). Should Gmsh's median edge still be off the field by more
// than 15 %, the first run scales the sizes handed to it by the inverse and meshes again (twice at
// most); later runs of a count loop keep that scale. Each run meshes the same patches again:
// the classification and the parametrization are made once per call.
//
// Output: the same as adapt() gives — the surface (labels carried from the closest input
// triangle), the metric per output point, the figures against that metric (measure()). A patch
// Gmsh fails on (an error, or a patch left without triangles), or a result whose topology differs
// from the input's (a hole, a lost or extra boundary loop), is an InputError naming the patch
// and where it is: never a mesh with holes.
#pragma once

#include "mesh/error.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"
#include "remesh/adapt.h"

#include <string>
#include <vector>

namespace vesselmesh::remesh {

enum class GmshAlgorithm { delaunay, frontal, meshadapt, bamg };

// Inline: the program parses these without opening Gmsh's module (modules/gmsh_module.h).
inline GmshAlgorithm parse_gmsh_algorithm(const std::string& name) {  // OptionError for an unknown name
  if (name == "delaunay") return GmshAlgorithm::delaunay;
  if (name == "frontal") return GmshAlgorithm::frontal;
  if (name == "meshadapt") return GmshAlgorithm::meshadapt;
  if (name == "bamg") return GmshAlgorithm::bamg;
  throw OptionError("unknown Gmsh algorithm '" + name + "': delaunay, frontal, meshadapt or bamg");
}
inline std::string gmsh_algorithm_name(GmshAlgorithm algorithm) {
  switch (algorithm) {
    case GmshAlgorithm::delaunay: return "delaunay";
    case GmshAlgorithm::frontal: return "frontal";
    case GmshAlgorithm::meshadapt: return "meshadapt";
    case GmshAlgorithm::bamg: return "bamg";
  }
  return "delaunay";
}

struct GmshRemeshOptions {
  GmshAlgorithm algorithm = GmshAlgorithm::delaunay;
  double classify_angle_deg = 40.0;  // patches split where normals turn more than this
  double curve_angle_deg = 180.0;    // curves split where they turn more than this (180: never)
  RemeshOptions remesh;              // distance bounds, local radius, features: as the native engine
  double size_factor = 1.0;          // the sizes handed to Gmsh times this at first (a calibration)
  // > 0: the metric scaled until Gmsh makes this many triangles, as remesh::fit_count does for
  // the native engine (within 2 %, 6 corrections at most, the closest run kept); the input is
  // classified and parametrized once for all the runs.
  double target_triangles = 0.0;
};

struct GmshRemeshResult {
  RemeshResult result;
  int patches = 0;  // surfaces Gmsh classified and parametrized
  double size_factor = 1.0;  // what the calibration settled on: hand it to the next run on this input
};

GmshRemeshResult reparametrize(const TriMesh& input, const std::vector<Sym3>& metrics, const GmshRemeshOptions& options,
                               const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::remesh
