// Where a flow's wall shear stress is least well represented by a mesh: the error metric of the
// WSS's linear interpolation over the wall of a `vesselmesh simulate` result (sizing/hessian.h),
// for the flow-adapted size field (issue 52).
#pragma once

#include "mesh/reporter.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"
#include "sizing/hessian.h"

#include <functional>
#include <string>
#include <vector>

namespace vesselmesh::post {

struct WallMetric {
  TriMesh wall;               // the flow's wall, in mm
  std::vector<Sym3> metric;   // per wall point: 1 / mm^2, up to a constant
  std::vector<double> times;  // s: the saved times it bounds together
};

// The intersection over `times` (linear between the saved frames around each; InputError where one
// lies outside them) of the metrics of the WSS's three components. With no times: every saved
// frame of the last period where the flow has one (its summary's `period`), else the last frame.
WallMetric wall_error_metric(const std::string& flow_directory, const std::vector<double>& times,
                             const sizing::ErrorMetricOptions& options = {},
                             const Reporter& reporter = silent_reporter());

// The boundary layer's first height that the flow's wall shear asks for (issue 52): per wall point,
// y+ = 1 (or `y_plus`) in the largest wall shear over `times` (as wall_error_metric bounds them):
// y = y+ mu / sqrt(rho |tau|) (u_tau = sqrt(|tau| / rho), the near-wall flow's viscous length), mm.
// The fluid as given (`fluid`, the case's), else from the flow's summary.json (InputError where
// neither says); OptionError for a y+ that is not positive.
struct Fluid {
  double density = 0.0;    // kg/m3; 0: the flow's summary's
  double viscosity = 0.0;  // Pa s
};
struct WallHeights {
  TriMesh wall;                 // the flow's wall, in mm
  std::vector<double> heights;  // per wall point, mm
  std::vector<double> times;    // s
  double y_plus = 1.0;
};
WallHeights first_layer_heights(const std::string& flow_directory, const std::vector<double>& times,
                                double y_plus = 1.0, Fluid fluid = {}, const Reporter& reporter = silent_reporter());

// The heights anywhere (mm): linear over the flow wall's triangle closest to the point, which it holds
// (volume::BoundaryLayerOptions::first_height). Queries are const and may run concurrently.
std::function<double(const Vec3&)> height_function(WallHeights heights);

}  // namespace vesselmesh::post
