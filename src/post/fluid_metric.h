// Where a flow's velocity is least well represented inside the lumen: the isotropic sizes that
// spread the velocity's P1 interpolation error (sizing::volume_error_sizes) over a `vesselmesh
// simulate` result's fluid frames, for the flow kind's interior (issue 52; the wall's counterpart
// is wall_metric.h).
#pragma once

#include "mesh/reporter.h"
#include "mesh/tetmesh.h"
#include "post/fluid_sample.h"
#include "sizing/hessian.h"

#include <functional>
#include <string>
#include <vector>

namespace vesselmesh::post {

struct FluidSizes {
  TetMesh mesh;               // the flow's mesh, in mm
  std::vector<double> sizes;  // per point of `mesh`, mm
  std::vector<double> times;  // s: the saved times it bounds together
  double scale = 1.0;         // the constant that set the count (below), mm per unit of the raw sizes
};

// The velocity's three components at `times` (linear between the saved frames around each; InputError
// where one lies outside them; none: every saved fluid frame of the last period where the flow has one,
// else the last frame), their sizes bounded together (the finest of each), graded by `growth` along the
// flow mesh's edges (sizing::grade_sizes; 1: none), and scaled so that the field asks for about as
// many points as the flow's own mesh has: the integral of h^-3 over its cells equal to that of its
// own sizes (each point's mean edge length), scaled before the grading and again after it (which only
// made sizes smaller), then graded again, so that the grading holds exactly and the count is a little
// over (volume's --target-points or the study's count loop sets it). InputError where the folder has no fluid frame (the case's output.fluid_every), or the
// frames are not of one mesh.
FluidSizes fluid_error_sizes(const std::string& flow_directory, const std::vector<double>& times, double growth,
                             const sizing::ErrorMetricOptions& options = {},
                             const Reporter& reporter = silent_reporter());

// The sizes anywhere inside the flow's mesh, linear in its cells (prisms split as the solver splits
// them); 0 outside it. Queries are const and may run concurrently.
class FluidSizeField {
 public:
  explicit FluidSizeField(FluidSizes sizes);
  double at(const Vec3& x) const;
  const FluidSizes& sizes() const { return sizes_; }

 private:
  FluidSizes sizes_;
  TetLocator locator_;
};

// A FluidSizeField as the interior's flow bound (volume::InteriorSizeOptions::flow), which it holds.
std::function<double(const Vec3&)> size_function(FluidSizes sizes);

}  // namespace vesselmesh::post
