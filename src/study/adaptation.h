// Flow-adapted meshes by cycles (issue 52's `vesselmesh adapt`): a first mesh of a geometric kind and
// its flow, then, each cycle, the surface remeshed to the error of the last flow's WSS (sizing's flow
// kind), its volume's interior sized by the error of the last flow's velocity (post/fluid_metric.h),
// and the flow run again. Each cycle is reported: its counts, its stages' seconds, and how far its
// wall's WSS moved from the cycle before's (the whole-wall measures of study/wall_difference.h, the
// last saved frames; the cycle before's interpolated onto this one's wall).
// Folder: DIR/cycle_K/{surface.vtp, volume.msh, flow/} for K = 0 .. cycles, DIR/summary.json.
// Lengths in mm, WSS in Pa.
#pragma once

#include "flow/case.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"
#include "sizing/hessian.h"
#include "sizing/size_field.h"
#include "volume/volume_mesh.h"

#include <string>
#include <vector>

namespace vesselmesh::study {

struct AdaptOptions {
  double target_triangles = 0.0;  // every cycle's surface (> 0)
  // Every cycle's volume points; 0: the first mesh's as the volume makes it, the later cycles at its count.
  int target_points = 0;
  int cycles = 2;  // flow-adapted cycles after the first mesh (>= 1)
  sizing::SizeKind start = sizing::SizeKind::curvature;  // the first mesh's kind (not flow)
  // Layer, fill, ends and the interior's gradation. Without end_at, the later cycles name their ends as the
  // first mesh's volume named them (by their centres), so that no end swaps names as the wall changes.
  volume::VolumeOptions volume;
  sizing::ErrorMetricOptions error;  // the WSS's and the velocity's L^p norm
  // The later cycles' first layer no higher than this y+ in the last flow's largest wall shear
  // (post::first_layer_heights); 0: the layer as `volume` gives it.
  double y_plus = 1.0;
};

struct AdaptCycle {
  int cycle = 0;
  std::string folder;
  int triangles = 0, surface_points = 0, volume_points = 0, dofs = 0;
  double remesh_seconds = 0.0, volume_seconds = 0.0, flow_seconds = 0.0;
  double min_dihedral_interior = 0.0;  // degrees
  // The WSS's move from the cycle before (none for the first: NaN), over this cycle's wall's mean |WSS|.
  double change_l2 = 0.0, change_p95 = 0.0;
  double wall_mean_wss = 0.0;  // Pa, area-weighted
};

// The flow kind's volume options from a flow on a first mesh (`flow_dir`; the study's "flow" kind and each
// cycle here): the interior sized by the velocity's interpolation error (post/fluid_metric.h, graded by
// vo.interior.gradation) and, with y_plus > 0 and layers, the first layer's height by the wall shear
// (post::first_layer_heights, the fluid `flow_case`'s).
void size_volume_to_flow(volume::VolumeOptions& vo, const std::string& flow_dir,
                         const sizing::ErrorMetricOptions& error,
                         double y_plus, const flow::FlowCase& flow_case, const Reporter& reporter);

// OptionError for a target of triangles <= 0, cycles < 1, a flow start kind, a negative point target or y+.
void check_adapt_options(const AdaptOptions& options);

// `input`: the vessel's surface (read and cleaned, mm); `flow_case`: the case each mesh's flow runs
// (its mesh replaced). Writes `folder` (created) as above; returns the cycles, the first mesh's first.
std::vector<AdaptCycle> adapt_to_flow(const TriMesh& input, const flow::FlowCase& flow_case,
                                      const std::string& folder, const AdaptOptions& options,
                                      const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::study
