// The mesh-impact study (the seed paper's experiment) on any vessel, end to end:
//  1. curvature, centerlines and distance map of the input;
//  2. the four surface meshes (uniform, distance, curvature, anisotropic) with the same number
//     of triangles (the sizing's target count, within its tolerance);
//  3. their volume meshes with the boundary layer;
//  4. a refinement series of `levels` meshes, the finest being the reference: by default (`kind =
//     "envelope"`, study/envelope.h) level k is finer than every compared mesh everywhere, its
//     wall's size the least of their achieved sizes / (1.1 x factor^(k-1)), its first layer height
//     and interior likewise; `kind = "uniform"` (the seed paper's design) is uniform meshes of triangles x
//     factor^k triangles;
//  5. the flow case on every mesh;
//  6. WSS at the chosen time on each ring and point; the relative difference of each ring's
//     minimum and of each point's WSS against the reference; what every mesh resolves at each ring
//     and point (study/resolution.h), so that a difference is called real only where the reference
//     out-resolves the mesh there; and over the whole wall, each mesh's WSS (and TAWSS and OSI, pulsatile) against the reference's
//     on the reference's wall (study/wall_difference.h);
//  7. a report (study_report.h).
// Each mesh's surface, volume and flow are kept in DIR/<mesh>/ with a stamp of what made them
// (a hash of the input's bytes, the options, the case and its waveforms, the version): a step
// whose stamp matches is reused, so a study can be resumed and extended.
//
// The study file (TOML; paths relative to it):
//   surface = "vessel.stl"     units = "mm" (the surface's unit, optional)
//   case = "flow.toml"         # a flow case; its `mesh` is replaced by each volume mesh
//   triangles = 8000           # the four meshes' surface triangles
//   meshes = ["uniform", "distance", "curvature", "anisotropic"] (and "flow": adapted to the WSS of
//               the flow on the curvature mesh, or on the first mesh listed, which must come before it:
//               sizing/size_field.h's flow kind over its last period's saved frames, issue 52, and
//               its interior to the velocity's error there, post/fluid_metric.h; its cost in the
//               summary counts that flow too); flow_cycles = 1 (more: flow_1 .. flow_N, each
//               adapted to the flow on the one before, all compared)
//   [reference] kind = "envelope" (or "uniform"), levels = 3, factor = 1.33 (envelope: each level
//               that many times finer in h than the one before, level 1 the finest compared mesh
//               at every point / 1.1: 1.33^3 = 2.35 times the volume nodes a level, the reference
//               1.95 times finer than any compared mesh) or 2.0 (uniform: that many times the
//               triangles a level), time_step_check =
//               true (an unsteady case: level 1's flow again at half the time step, the time step's
//               share of the reference's error beside its grid convergence), period_check = true (a
//               case with a [time] period: level 1's flow one period more, the start-up's share)
//   [volume]    layers = 4, thickness_ratio = 0.1, layer_angle = 0 (the paper's layer on every
//               mesh: a layer thickened for its angles on some meshes only would confound the
//               comparison; see volume/boundary_layer.h), layer_split_angle = 0 (5: the long
//               edges of stretched wall triangles halved until the layer keeps 5 degrees; on an
//               anisotropic wall that adds wall points, +42 % on the demo's 8000 triangles, so
//               the compared meshes no longer have equal counts), algorithm = "delaunay", inlet = K,
//               end_names = ["inlet", "outlet_1", ...], interior_size = 1.0 and
//               interior_gradation = 1.3 (volume/interior_size.h: the same interior field for
//               every mesh, so that equal surface counts give comparable volumes),
//               flow_y_plus = 1 (the flow kinds' layer no higher at its first height than this y+ in
//               their source flow's largest wall shear, post::first_layer_heights; 0: the layer as
//               the others'), equal_volume_nodes = true (each compared mesh after the first has its interior's
//               size factor scaled until its volume has the first's node count within 2 %:
//               volume::build_volume_with_points; the factor used is in Table 1)
//   [post]      time = 0.21 (s; default the last saved)
//   [[ring]]    name = "ring1", point = [x, y, z], normal = [nx, ny, nz] (omit it: the plane
//               normal to the centerline nearest the point), reference = [rx, ry, rz] (optional)
//   [[point]]   name = "A", point = [x, y, z]
//   [[end]]     name = "inlet", point = [x, y, z]: the end whose centre is nearest the point takes
//               that name (all ends or none; instead of [volume] inlet / end_names)
#pragma once

#include "mesh/reporter.h"
#include "post/ring.h"
#include "sizing/size_field.h"
#include "study/resolution.h"
#include "study/wall_difference.h"
#include "volume/volume_mesh.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::study {

enum class ReferenceKind { envelope, uniform };
// "envelope", "uniform"; OptionError otherwise.
ReferenceKind parse_reference_kind(const std::string& name);
std::string reference_kind_name(ReferenceKind kind);

struct StudyConfig {
  std::string path;        // the study file
  std::string surface;     // resolved against the study file's folder
  std::string units;       // the surface's unit; empty: mm
  std::string flow_case;   // resolved
  double triangles = 8000.0;
  std::vector<sizing::SizeKind> kinds = {sizing::SizeKind::uniform, sizing::SizeKind::distance,
                                         sizing::SizeKind::curvature, sizing::SizeKind::anisotropic};
  ReferenceKind reference = ReferenceKind::envelope;
  int levels = 3;
  double factor = 1.33;  // envelope: in h; uniform: in triangles
  // An unsteady case: the series' coarsest level's flow run again at half the time step, so that the
  // report sets the time step's share of the reference's error beside the mesh's (`[reference]
  // time_step_check`).
  bool time_step_check = true;
  // A periodic case (its [time] period): the same level's flow one period more, so that the report sets
  // what is left of the start (the flow from rest not yet periodic) beside them (`[reference] period_check`).
  bool period_check = true;
  int layers = 4;
  double thickness_ratio = 0.1;
  double layer_angle = 0.0;        // degrees: volume::BoundaryLayerOptions::min_angle_deg
  double layer_split_angle = 0.0;  // degrees: volume::BoundaryLayerOptions::split_angle_deg
  double flow_y_plus = 1.0;        // the flow kinds' first layer height (post::first_layer_heights); 0: none
  std::string algorithm = "delaunay";
  volume::InteriorSizeOptions interior;
  bool equal_volume_nodes = true;  // the compared meshes' volumes of the first one's node count
  int inlet = -1;
  std::vector<std::string> end_names;
  std::vector<volume::EndAt> end_at;
  // [extensions] length = L (radii; 0: none), mode = "smooth" | "straight": flow extensions added to
  // every open end of the input before anything else (remesh/extend.h); an [[end]] point names the
  // end it was nearest before, now moved.
  double extension_length = 0.0;
  std::string extension_mode = "smooth";
  std::optional<double> time;
  std::vector<post::RingRequest> rings;
  std::vector<post::PointSpec> points;
  // The processes each flow runs on (`ranks`; `vesselmesh study --ranks`): more than 1 runs
  // `mpirun -np ranks PROGRAM simulate CASE --mesh MESH -o DIR` (mpirun from PATH), PROGRAM this
  // vesselmesh program (set by the caller).
  int ranks = 1;
  // The flow kind adapted this many times, each cycle to the flow on the cycle before's mesh (the first to
  // the curvature mesh's): the compared meshes flow_1 .. flow_N (one cycle: "flow").
  int flow_cycles = 1;
  std::string program;
};

// Every mistake is an InputError naming the file and the key.
StudyConfig read_study(const std::string& path);
StudyConfig parse_study(const std::string& text, const std::string& path);

struct MeshRun {
  std::string name;       // uniform, distance, curvature, anisotropic, or level_1 ... level_N
  bool series = false;    // a level of the refinement series
  double target_triangles = 0.0;
  int surface_triangles = 0, surface_points = 0;
  // Where the remesher's distance bound held the count over its target: the least count it allows
  // this kind (remesh::RemeshResult::least_count); 0 where not measured.
  int least_count = 0;
  int volume_points = 0, tetrahedra = 0, dofs = 0;
  double min_dihedral = 0.0;  // degrees, over all cells
  // Degrees: the boundary layer's cells' and the interior's apart (-1: none, or a stamp from before
  // they were kept).
  double min_dihedral_layer = -1.0, min_dihedral_interior = -1.0;
  // Degrees: the layer's cells in the layer's own frame (volume::VolumeQuality's; -1: not measured).
  double min_dihedral_layer_frame = -1.0;
  double interior_size = 1.0;  // the interior's size factor its volume was made with
  std::map<std::string, double> seconds = {};  // remesh, volume, flow (those of the run that made them)
  bool reused = false;                         // loaded from an earlier run
  std::string adapted_from = {};               // the flow kind: the compared mesh whose flow it adapts to
  std::string folder = {};                     // DIR/<name>
  std::vector<post::Ring> rings = {};
  std::vector<post::PointProbe> points = {};
  std::vector<PlaceResolution> resolution = {};  // per StudyResult::places
  int layers = 0;              // the boundary layer's count and growth it was made with
  double layer_growth = 1.0;
  // Whole-wall differences from the reference (study/wall_difference.h): "wss" at the study's time,
  // "tawss" and "osi" over the flows' last period where they wrote them; and the fields on the
  // reference's wall they were measured from.
  std::map<std::string, WallDifference> wall = {};
  std::vector<Vec3> wss_on_reference = {};
  double read_after = 0.0;  // s: read this long after the study's time (a run one period longer: the period)
  std::vector<double> tawss_on_reference = {}, osi_on_reference = {};
};

struct StudyResult {
  std::vector<MeshRun> meshes;  // the compared meshes, then the series coarse to fine
  int reference = -1;           // index of the finest level
  double time = 0.0;            // s: when WSS was read
  std::vector<post::RingSpec> rings;
  std::vector<Place> places;    // each ring, then each point: where the resolution is measured
  // Per point of the reference's wall (at the study's time; of its indices' file): a third of the
  // area of its triangles.
  std::vector<double> reference_area, reference_index_area;
  std::string length_unit = "mm";
  // The series' coarsest level run again at half the time step (unsteady cases, time_step_check):
  // its rings, points and fields on the reference's wall.
  std::optional<MeshRun> half_step;
  // The same level one period more (periodic cases, period_check): the start-up's share.
  std::optional<MeshRun> next_period;
  double period = 0.0;  // s: the case's (0: none, or steady)
  double time_step = 0.0;  // s: the case's (0: steady)
  std::map<std::string, double> seconds;  // input analysis, post-processing, report, total
  std::vector<std::string> warnings;      // e.g. compared meshes off their triangle count
  std::string report_markdown, report_html;
};

// Relative difference in percent: 100 (value - reference) / |reference| (NaN when the
// reference is 0).
double relative_difference(double value, double reference);

StudyResult run_study(const StudyConfig& config, const std::string& folder,
                      const Reporter& reporter = silent_reporter());

// The warning when the compared meshes' volume node counts differ by more than 5 % (the least
// and the most, named), or "" when they do not.
std::string volume_count_warning(const std::vector<MeshRun>& meshes);

}  // namespace vesselmesh::study
