#include "volume/volume_mesh.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "volume/cap.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace vesselmesh::volume {
namespace {

// The wall: the surface without its caps, points renumbered; `old_of[i]` is the surface point
// of wall point i.
struct Wall {
  TriMesh mesh;
  std::vector<int> old_of, new_of;
  std::vector<WallEnd> ends;
};

Wall extract_wall(const TriMesh& surface, const std::vector<analysis::OpenEnd>& ends) {
  std::vector<char> cap(surface.triangles.size(), 0);
  for (const auto& end : ends)
    for (int t : end.cap_triangles) cap[t] = 1;
  // Points keep their surface order, so the numbering does not depend on the triangles'.
  Wall wall;
  wall.new_of.assign(surface.points.size(), -1);
  for (size_t t = 0; t < surface.triangles.size(); ++t)
    if (!cap[t])
      for (int v : surface.triangles[t]) wall.new_of[v] = 0;
  for (int v = 0; v < surface.num_points(); ++v) {
    if (wall.new_of[v] < 0) continue;
    wall.new_of[v] = static_cast<int>(wall.old_of.size());
    wall.old_of.push_back(v);
    wall.mesh.points.push_back(surface.points[v]);
  }
  for (size_t t = 0; t < surface.triangles.size(); ++t) {
    if (cap[t]) continue;
    const Triangle& f = surface.triangles[t];
    wall.mesh.triangles.push_back({wall.new_of[f[0]], wall.new_of[f[1]], wall.new_of[f[2]]});
  }
  if (wall.mesh.triangles.empty()) throw InputError("the surface has no wall triangles");

  // Every boundary loop of the wall is one of the ends.
  const mesh::EdgeMap edges = mesh::build_edge_map(wall.mesh);
  const auto loops = mesh::boundary_loops(wall.mesh, edges);
  std::set<std::vector<int>> end_loops;
  for (const auto& end : ends) {
    WallEnd w;
    w.normal = end.normal;
    for (int v : end.loop) {
      if (wall.new_of[v] < 0) throw InternalError("an end's loop point is not on the wall");
      w.loop.push_back(wall.new_of[v]);
    }
    std::vector<int> key = w.loop;
    std::sort(key.begin(), key.end());
    end_loops.insert(key);
    wall.ends.push_back(std::move(w));
  }
  for (auto loop : loops) {
    const Vec3 at = wall.mesh.points[loop.front()];
    std::sort(loop.begin(), loop.end());
    if (!end_loops.count(loop))
      throw InputError(fmt::format("the wall has a hole at {} that is not one of the ends (a boundary of {} edges); "
                                   "close or repair the surface first",
                                   mesh::format_point(at), loop.size()));
  }
  if (loops.size() != ends.size())
    throw InputError(fmt::format("the wall has {} boundary loops for {} ends", loops.size(), ends.size()));
  return wall;
}

// Tags: capped ends keep their label (when positive); the wall and the other ends take the
// smallest free positive integers.
void assign_tags(const std::vector<analysis::OpenEnd>& ends, VolumeOptions options, VolumeReport& report) {
  const int count = static_cast<int>(ends.size());
  if (!options.end_at.empty()) {
    if (!options.end_names.empty() || options.inlet >= 0)
      throw OptionError("name the ends by --end, or by --inlet / --end-names, not both");
    options.end_names = names_of_ends(ends, options.end_at);
  }
  if (options.inlet >= count || options.inlet < -1)
    throw OptionError(fmt::format("--inlet {}: the surface has {} ends, numbered 0 to {} as `vesselmesh info` "
                                  "lists them",
                                  options.inlet, count, count - 1));
  if (!options.end_names.empty() && static_cast<int>(options.end_names.size()) != count)
    throw OptionError(fmt::format("--end-names: {} names given for {} ends", options.end_names.size(), count));
  std::set<std::string> names_seen = {"wall"};
  for (const std::string& name : options.end_names)
    if (name.empty() || !names_seen.insert(name).second)
      throw OptionError(fmt::format("--end-names: '{}' is empty, 'wall', or given twice", name));

  std::set<int> taken;
  for (const auto& end : ends)
    if (end.capped && end.label > 0) taken.insert(end.label);
  int next = 1;
  auto fresh = [&] {
    while (taken.count(next)) ++next;
    taken.insert(next);
    return next;
  };
  report.wall_tag = fresh();
  const int inlet = options.inlet >= 0 ? options.inlet : 0;  // ends come largest first
  const std::vector<std::string> names =
      !options.end_names.empty() ? options.end_names : analysis::default_end_names(count, inlet);
  for (int e = 0; e < count; ++e) {
    VolumeEnd v;
    v.center = ends[e].center;
    v.normal = ends[e].normal;
    v.radius = ends[e].radius;
    v.capped = ends[e].capped;
    v.tag = ends[e].capped && ends[e].label > 0 ? ends[e].label : fresh();
    v.name = names[e];
    report.ends.push_back(v);
  }
}

}  // namespace

std::vector<std::string> names_of_ends(const std::vector<analysis::OpenEnd>& ends, const std::vector<EndAt>& named) {
  auto centres = [&] {
    std::string list;
    for (size_t e = 0; e < ends.size(); ++e)
      list += fmt::format("{}end {} at ({:.4g}, {:.4g}, {:.4g}) radius {:.3g}", e ? "; " : "", e, ends[e].center.x(),
                          ends[e].center.y(), ends[e].center.z(), ends[e].radius);
    return list;
  };
  if (named.size() != ends.size())
    throw OptionError(fmt::format("{} ends named by a point for {} ends: name every end ({})", named.size(), ends.size(),
                                  centres()));
  std::vector<std::string> names(ends.size());
  for (const EndAt& n : named) {
    size_t best = 0;
    for (size_t e = 1; e < ends.size(); ++e)
      if ((ends[e].center - n.point).norm() < (ends[best].center - n.point).norm()) best = e;
    const double distance = (ends[best].center - n.point).norm();
    if (distance > 3.0 * ends[best].radius)
      throw OptionError(fmt::format("end '{}' at ({:.4g}, {:.4g}, {:.4g}): no end within three radii ({})", n.name,
                                    n.point.x(), n.point.y(), n.point.z(), centres()));
    if (!names[best].empty())
      throw OptionError(fmt::format("ends '{}' and '{}' name the same end {}: give a point near each end's centre ({})",
                                    names[best], n.name, best, centres()));
    names[best] = n.name;
  }
  return names;
}

void check_volume(const TetMesh& m) {
  const std::vector<Tet> all = mesh::all_tetrahedra(m);
  for (size_t i = 0; i < all.size(); ++i) {
    const Tet& tet = all[i];
    if (mesh::tet_volume6(m, tet) > 0.0) continue;
    const Vec3 at = (m.points[tet[0]] + m.points[tet[1]] + m.points[tet[2]] + m.points[tet[3]]) / 4.0;
    const std::string cell = i < m.tets.size() ? fmt::format("tetrahedron {}", i)
                                               : fmt::format("prism {}", (i - m.tets.size()) / 3);
    throw InputError(fmt::format("{} at {} is inverted or flat (6 V = {:.3g})", cell, mesh::format_point(at),
                                 mesh::tet_volume6(m, tet)));
  }
  // The prisms' quadrilateral sides appear as the triangles of their split, which is how the
  // boundary lists them.
  const mesh::BoundaryClosure closure = mesh::boundary_closure(m, all);
  if (!closure.closed())
    throw InternalError(fmt::format("the volume's boundary is not closed as tagged: {} faces of one cell untagged, {} "
                                    "tagged triangles that are no such face, {} faces shared by more than two cells",
                                    closure.open_faces, closure.stray_triangles, closure.nonmanifold));
}

VolumeResult build_volume(const TriMesh& surface, const std::vector<analysis::OpenEnd>& ends,
                          const std::vector<double>& radius, const VolumeOptions& options, const Reporter& reporter) {
  VM_CHECK(radius.size() == surface.points.size() || (radius.empty() && options.layer.layers == 0),
           "build_volume: one radius per surface point (none needed without a layer)");
  if (ends.empty())
    throw InputError("the surface has no ends (no boundary loop and no flat cap): a flow domain needs an inlet "
                     "and an outlet; cut the vessel's ends open or cap them flat");
  check_interior_size_options(options.interior);
  VolumeResult result;
  VolumeReport& report = result.report;
  report.interior_factor = options.interior.factor;
  assign_tags(ends, options, report);
  Wall wall = extract_wall(surface, ends);
  std::vector<double> wall_radius(wall.mesh.num_points());
  for (size_t v = 0; v < wall_radius.size() && !radius.empty(); ++v) wall_radius[v] = radius[wall.old_of[v]];

  // Layer (or the wall itself) and the inner loops the caps close.
  std::vector<Vec3> points;
  std::vector<Triangle> inner;
  std::vector<std::vector<int>> inner_loops;
  std::vector<std::vector<Triangle>> strips(ends.size());
  BoundaryLayer layer;
  report.layers = options.layer.layers;
  if (options.layer.layers > 0) {
    reporter.progress("boundary layer", 0.0);
    // Columns still under the split angle once built (thin layers over stretched triangles)
    // have their triangle's long edge halved, and the layer is built again.
    constexpr int kSplitPasses = 3;
    const double split_angle = options.layer.split_angle_deg;
    for (int pass = 0;; ++pass) {
      layer = build_boundary_layer(wall.mesh, wall_radius, wall.ends, options.layer, reporter);
      if (!(split_angle > 0.0) || pass == kSplitPasses) break;
      std::vector<int> under;
      for (size_t t = 0; t < layer.column_angle.size(); ++t)
        if (layer.column_angle[t] < split_angle) under.push_back(static_cast<int>(t));
      if (under.empty()) break;
      const int split = split_long_edges(wall.mesh, wall_radius, under);
      if (split == 0) break;
      report.split_edges += split;
      reporter.info(fmt::format("boundary layer: {} wall triangles under {} degrees (least {:.2f}): {} long edges "
                                "halved, the layer built again",
                                under.size(), split_angle, layer.least_angle, split));
    }
    reporter.progress("boundary layer", 1.0);
    points = layer.points;
    inner = layer.inner;
    inner_loops = layer.inner_loops;
    strips = layer.end_strips;
    report.shrunk_vertices = layer.shrunk_vertices;
    report.first_height_capped = layer.capped_vertices;
    if (layer.capped_vertices > 0)
      reporter.info(fmt::format("boundary layer: its first layer lowered to the height asked at {} of {} wall "
                                "points (its layers growing faster, or the layer thinner where growth 2 would not do)",
                                layer.capped_vertices, wall.mesh.num_points()));
    report.least_fraction = layer.least_fraction;
    report.least_at = layer.least_at;
    report.thickened_vertices = layer.thickened_vertices;
    report.most_fraction = layer.most_fraction;
    report.most_at = layer.most_at;
    report.under_angle_prisms = layer.under_angle_prisms;
    report.least_layer_angle = layer.least_angle;
    report.min_thickness_ratio = 1e300;
    for (int v = 0; v < wall.mesh.num_points(); ++v) {
      const double ratio = layer.thickness[v] / wall_radius[v];
      report.min_thickness_ratio = std::min(report.min_thickness_ratio, ratio);
      report.max_thickness_ratio = std::max(report.max_thickness_ratio, ratio);
    }
    if (layer.shrunk_vertices > 0)
      reporter.warning(fmt::format("boundary layer thinner than asked at {} of {} wall points (down to {:.0f} % near {})",
                                   layer.shrunk_vertices, wall.mesh.num_points(), 100.0 * layer.least_fraction,
                                   mesh::format_point(layer.least_at)));
    if (layer.thickened_vertices > 0)
      reporter.info(fmt::format("boundary layer thicker than asked at {} of {} wall points (up to {:.2f} times near {}): "
                                "the wall's triangles are large there against the thinnest layer, whose "
                                "tetrahedra would fall under {} degrees (--layer-angle 0 keeps the thickness asked)",
                                layer.thickened_vertices, wall.mesh.num_points(), layer.most_fraction, mesh::format_point(layer.most_at),
                                options.layer.min_angle_deg));
    if (layer.under_angle_prisms > 0)
      reporter.warning(fmt::format("{} of {} layer prisms have tetrahedra under {} degrees (least {:.2f} near {}): "
                                   "their columns were shrunk or held at half the radius; remesh the wall finer there "
                                   "or ask fewer --layers",
                                   layer.under_angle_prisms, layer.prisms.size(), options.layer.min_angle_deg,
                                   layer.least_angle, mesh::format_point(layer.least_angle_at)));
  } else {
    points = wall.mesh.points;
    inner = wall.mesh.triangles;
    for (const WallEnd& end : wall.ends) inner_loops.push_back(end.loop);
  }

  const int n = wall.mesh.num_points();  // the wall's points, with those the splits added

  // Caps on the inner loops.
  std::vector<std::vector<Triangle>> caps(ends.size());
  for (size_t e = 0; e < ends.size(); ++e) {
    std::vector<Vec3> loop;
    for (int v : inner_loops[e]) loop.push_back(points[v]);
    const Cap cap = triangulate_cap(loop, ends[e].normal);
    const int m = static_cast<int>(loop.size()), base = static_cast<int>(points.size());
    points.insert(points.end(), cap.points.begin(), cap.points.end());
    for (Triangle f : cap.triangles) {
      for (int& v : f) v = v < m ? inner_loops[e][v] : base + (v - m);
      caps[e].push_back(f);
    }
    report.ends[e].cap_triangles = static_cast<int>(cap.triangles.size());
  }

  // Interior.
  std::vector<Triangle> closed = inner;
  for (const auto& cap : caps) closed.insert(closed.end(), cap.begin(), cap.end());
  reporter.info(fmt::format("interior: {} boundary triangles, {}", closed.size(),
                            options.algorithm == FillAlgorithm::tetgen
                                ? std::string("TetGen")
                                : fmt::format("Gmsh {}", fill_algorithm_name(options.algorithm))));
  const InteriorSize interior_size(wall.mesh, radius.empty() ? std::vector<double>{} : wall_radius, options.interior,
                                   layer.thickness);
  {
    std::vector<double> at_wall(n);
    for (int v = 0; v < n; ++v) at_wall[v] = interior_size.at_wall_point(v);
    std::sort(at_wall.begin(), at_wall.end());
    report.interior_size_min = at_wall.front();
    report.interior_size_median = at_wall[n / 2];
    report.interior_size_max = at_wall.back();
    reporter.info(fmt::format("interior sizes: {:.3g} mm at the wall (least {:.3g}, largest {:.3g}; x{:g}), growing "
                              "inward by {:g} to at most {}",
                              report.interior_size_median, report.interior_size_min, report.interior_size_max,
                              options.interior.factor, options.interior.gradation,
                              options.interior.flow ? std::string("the flow's sizes")
                                                    : fmt::format("{:g} of the local radius",
                                                                  options.interior.core_fraction)));
  }
  FillResult fill = fill_tetrahedra(points, closed, options.algorithm, options.threads, reporter,
                                    [&interior_size](const Vec3& x) { return interior_size.at(x); });
  if (options.sliver_angle_deg > 0.0) {
    reporter.progress("removing slivers", 0.0);
    report.slivers = remove_slivers(fill.points, fill.tets, static_cast<int>(points.size()),
                                    {.min_dihedral_deg = options.sliver_angle_deg});
    reporter.progress("removing slivers", 1.0);
    const SliverReport& s = report.slivers;
    reporter.info(fmt::format("interior: {} tetrahedra under {:g} degrees before the clean-up, {} after ({} flips, {} "
                              "moves, {} insertions, {} collapses); least dihedral angle {:.2f} -> {:.2f} degrees",
                              s.below_before, options.sliver_angle_deg, s.below_after, s.flips, s.moves, s.insertions,
                              s.collapses,
                              s.least_before, s.least_after));
    if (s.below_after > 0)
      reporter.warning(fmt::format("{} interior tetrahedra keep a dihedral angle under {:g} degrees (the least, {:.2f}, "
                                   "near {})",
                                   s.below_after, options.sliver_angle_deg, s.least_after,
                                   mesh::format_point(s.worst_at)));
  }

  report.interior_points = static_cast<int>(fill.points.size() - points.size());
  TetMesh& mesh = result.mesh;
  mesh.points = std::move(fill.points);
  if (options.layer.layers > 0) {
    for (size_t p = 0; p < layer.prisms.size(); ++p) {
      if (options.keep_prisms) {
        mesh.prisms.push_back(layer.prisms[p]);
        mesh.prism_layer.push_back(layer.prism_layer[p]);
        mesh.prism_column.push_back(layer.prism_column[p]);
        continue;
      }
      for (const Tet& t : mesh::split_prism(layer.prisms[p])) {
        mesh.tets.push_back(t);
        mesh.tet_layer.push_back(layer.prism_layer[p]);
        mesh.tet_column.push_back(layer.prism_column[p]);
      }
    }
  }
  report.layer_tets = mesh.num_tets();
  report.layer_prisms = mesh.num_prisms();
  for (const Tet& t : fill.tets) {
    mesh.tets.push_back(t);
    mesh.tet_layer.push_back(0);
    mesh.tet_column.push_back(-1);
  }
  report.interior_tets = static_cast<int>(fill.tets.size());

  // Boundary: the wall (its triangles first, so a layer cell's column is its boundary index),
  // then each end's strip and cap.
  mesh.tag_names[report.wall_tag] = "wall";
  for (const Triangle& f : wall.mesh.triangles) {
    mesh.boundary.push_back(f);
    mesh.boundary_tags.push_back(report.wall_tag);
  }
  for (size_t e = 0; e < ends.size(); ++e) {
    mesh.tag_names[report.ends[e].tag] = report.ends[e].name;
    for (const auto* part : {&strips[e], &caps[e]})
      for (const Triangle& f : *part) {
        mesh.boundary.push_back(f);
        mesh.boundary_tags.push_back(report.ends[e].tag);
      }
  }
  if (options.layer.layers == 0) {
    mesh.tet_layer.clear();
    mesh.tet_column.clear();
  }
  check_volume(mesh);

  result.radius.assign(mesh.points.size(), 0.0);
  const int levels = options.layer.layers > 0 ? options.layer.layers + 1 : 1;
  for (int k = 0; k < levels; ++k)
    for (int v = 0; v < n; ++v) result.radius[k * n + v] = wall_radius[v];
  return result;
}

VolumeResult build_volume_with_points(const TriMesh& surface, const std::vector<analysis::OpenEnd>& ends,
                                      const std::vector<double>& radius, const VolumeOptions& options,
                                      int target_points, double tolerance, const Reporter& reporter) {
  VM_CHECK(target_points > 0 && tolerance > 0.0, "build_volume_with_points: a target count > 0 and a tolerance > 0");
  constexpr int kBuilds = 4;
  VolumeOptions o = options;
  VolumeResult result = build_volume(surface, ends, radius, o, reporter);
  double last_factor = 0.0;
  int last_interior = 0;
  for (int build = 1;; ++build) {
    const int points = result.mesh.num_points(), interior = result.report.interior_points;
    if (std::abs(points - target_points) <= tolerance * target_points || build == kBuilds) break;
    const int wanted = target_points - (points - interior);
    if (wanted <= 0)
      throw InputError(fmt::format("a volume of {} points cannot be made: the boundary layer and the caps alone have "
                                   "{} (ask for more points, or fewer layers)",
                                   target_points, points - interior));
    // Points inside go as the size to the power -3, or as the last two builds say (the exponent
    // through them, where it lies between -6 and -1: the fill's count is not smooth in the size,
    // and the flow kind's interior, graded from its own sizes, follows the factor less than a cube:
    // on the small study's, -3 went 4327 -> 6239 -> 5318 -> 5729 for 5590); the step is bounded,
    // so that a count the fill cannot follow (a tiny interior) does not send the factor far.
    double exponent = -3.0;
    if (last_interior > 0 && interior > 0 && last_factor != o.interior.factor) {
      const double through = std::log(static_cast<double>(interior) / last_interior) /
                             std::log(o.interior.factor / last_factor);
      if (through >= -6.0 && through <= -1.0) exponent = through;
    }
    const double scale =
        std::clamp(std::pow(static_cast<double>(wanted) / std::max(interior, 1), 1.0 / exponent), 0.5, 2.0);
    last_factor = o.interior.factor, last_interior = interior;
    o.interior.factor *= scale;
    reporter.info(fmt::format("volume: {} points for {} asked: the interior's size factor {:.4g} -> {:.4g}", points,
                              target_points, o.interior.factor / scale, o.interior.factor));
    result = build_volume(surface, ends, radius, o, reporter);
  }
  return result;
}

}  // namespace vesselmesh::volume
