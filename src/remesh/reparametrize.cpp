#include "remesh/reparametrize.h"

#include "io/gmsh_session.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/statistics.h"
#include "remesh/surface_model.h"
#include "sizing/metric.h"

#include <fmt/format.h>
#include <gmsh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vesselmesh::remesh {
namespace {

constexpr int kTriangle3 = 2;  // Gmsh's element type of a 3-node triangle

int gmsh_code(GmshAlgorithm a) {
  switch (a) {
    case GmshAlgorithm::meshadapt: return 1;
    case GmshAlgorithm::delaunay: return 5;
    case GmshAlgorithm::frontal: return 6;
    case GmshAlgorithm::bamg: return 7;
  }
  return 5;
}

// The smallest size a metric asks for.
double smallest_size(const Sym3& m) {
  Vec3 sizes;
  Eigen::Matrix3d directions;
  sizing::metric_sizes(m, sizes, directions);
  return sizes.minCoeff();
}

// The median edge length of a mesh in a metric given at its points.
double median_edge_length(const TriMesh& mesh, const std::vector<Sym3>& metric) {
  std::vector<double> lengths;
  for (const Triangle& f : mesh.triangles)
    for (int c = 0; c < 3; ++c) {
      const int a = f[c], b = f[(c + 1) % 3];
      if (a < b) lengths.push_back(sizing::edge_length(mesh.points[a], mesh.points[b], metric[a], metric[b]));
    }
  if (lengths.empty()) return 1.0;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return lengths[lengths.size() / 2];
}

std::string where(const Vec3& p) { return fmt::format("({:.4g}, {:.4g}, {:.4g})", p.x(), p.y(), p.z()); }

// The input, classified into patches and parametrized by Gmsh once, then meshed as often as
// asked (the calibration and the count loop re-run the 2D meshing only; the classification
// is the same each time). Lives inside one GmshSession.
class Patches {
 public:
  Patches(const TriMesh& input, const GmshRemeshOptions& o, io::ScopedGmshOptions& options, const Reporter& reporter)
      : input_(input), o_(o), options_(options), reporter_(reporter) {
    io::call_gmsh("remeshing by Gmsh (reparametrization)", [&] {
      gmsh::model::add("surface");
      io::add_discrete_surface(input);
      reporter.progress("Gmsh: classifying and parametrizing patches", 0.0);
      gmsh::model::mesh::classifySurfaces(o.classify_angle_deg * std::numbers::pi / 180.0, true, true,
                                          o.curve_angle_deg * std::numbers::pi / 180.0);
      gmsh::model::mesh::createGeometry();
      gmsh::model::getEntities(surfaces_, 2);
      if (input.has_labels()) label_patches();
      reporter.progress("Gmsh: classifying and parametrizing patches", 1.0);

      options.set("General.NumThreads", 1);  // the size callback is ours and serial
      options.set("Mesh.Algorithm", gmsh_code(o.algorithm));
      options.set("Mesh.MeshSizeFromPoints", 0);
      options.set("Mesh.MeshSizeFromCurvature", 0);
      options.set("Mesh.MeshSizeExtendFromBoundary", 0);
      // The curves' nodes are placed by integrating 1 / size along them to this relative precision
      // (Gmsh's default 1e-9 took 58 % of a curvature-field run on the VMTK aorta; with BAMG's
      // background mesh, minutes).
      options.set("Mesh.LcIntegrationPrecision", 1e-3);
      if (o.algorithm == GmshAlgorithm::bamg) {
        options.set("Mesh.AnisoMax", 1000.0);
        options.set("Mesh.SmoothRatio", 3.0);
      }
    });
  }

  int count() const { return static_cast<int>(surfaces_.size()); }

  // The input label all of a patch's triangles carry, or kMixed (the patch spans a label border
  // that is no crease, or no label was read).
  static constexpr int kMixed = std::numeric_limits<int>::min();
  int label_of(int patch) const {
    const auto it = patch_label_.find(patch);
    return it == patch_label_.end() ? kMixed : it->second;
  }

  // Gmsh's mesh of every patch for `field` (on `model`'s input), its sizes times `factor`: the
  // patches' meshes side by side, their shared curve nodes not yet merged. InputError naming a
  // patch left without triangles.
  TriMesh mesh(const std::vector<Sym3>& field, const SurfaceModel& model, double factor) {
    double least = std::numeric_limits<double>::infinity(), most = 0.0;
    for (const Sym3& m : field) {
      const double h = smallest_size(m);
      least = std::min(least, h), most = std::max(most, h);
    }
    TriMesh mesh;
    std::vector<std::pair<int, Vec3>> empty_patches;
    io::call_gmsh("remeshing by Gmsh (reparametrization)", [&] {
      // generate(2) meshes the curves and the patches anew; clearing the mesh first would lose
      // the classified geometry (measured: Gmsh then fails to recover the curves' edges).
      options_.set("Mesh.MeshSizeMin", 0.5 * factor * least);
      options_.set("Mesh.MeshSizeMax", 2.0 * factor * most);
      if (o_.algorithm == GmshAlgorithm::bamg) {
        // The whole metric, as a tensor view on the input triangles (list data: it does not
        // depend on the mesh Gmsh replaces), Gmsh's background mesh; sizes times `factor`.
        if (view_ >= 0) gmsh::model::mesh::field::remove(background_), gmsh::view::remove(view_);
        const double scale = 1.0 / (factor * factor);
        std::vector<double> data;
        data.reserve(36 * input_.triangles.size());
        for (const Triangle& f : input_.triangles) {
          for (int axis = 0; axis < 3; ++axis)
            for (int v : f) data.push_back(input_.points[v][axis]);
          for (int v : f) {
            const auto& m = field[v].v;  // xx, xy, xz, yy, yz, zz
            for (double x : {m[0], m[1], m[2], m[1], m[3], m[4], m[2], m[4], m[5]}) data.push_back(scale * x);
          }
        }
        view_ = gmsh::view::add("metric");
        gmsh::view::addListData(view_, "TT", input_.num_triangles(), data);
        background_ = gmsh::model::mesh::field::add("PostView");
        gmsh::model::mesh::field::setNumber(background_, "ViewTag", view_);
        gmsh::model::mesh::field::setAsBackgroundMesh(background_);
      } else {
        options_.size_callback([&model, factor](int, int, double x, double y, double z) {
          return factor * smallest_size(model.project(Vec3(x, y, z)).metric);
        });
      }
      reporter_.progress("Gmsh: meshing the patches", 0.0);
      // Gmsh meshes the patches inside an OpenMP region, where an error it throws cannot be
      // caught and ends the program. So its errors are only logged while it meshes (the session
      // throws on them everywhere else), and the first one logged is ours to raise.
      std::vector<std::string> log;
      gmsh::logger::get(log);
      const size_t logged = log.size();
      gmsh::option::setNumber("General.AbortOnError", 0);
      gmsh::model::mesh::generate(2);
      gmsh::option::setNumber("General.AbortOnError", 2);
      gmsh::logger::get(log);
      for (size_t i = logged; i < log.size(); ++i)
        if (log[i].rfind("Error", 0) == 0)
          throw InputError(fmt::format("Gmsh failed to mesh the patches ({}): lower the classification angle to cut "
                                       "them smaller, or use the native engine",
                                       log[i]));
      reporter_.progress("Gmsh: meshing the patches", 1.0);

      std::vector<std::size_t> tags;
      std::vector<double> xyz, parametric;
      gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, true, false);
      std::unordered_map<std::size_t, int> index_of;
      index_of.reserve(tags.size());
      for (size_t i = 0; i < tags.size(); ++i)
        if (index_of.emplace(tags[i], static_cast<int>(mesh.points.size())).second)
          mesh.points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      for (const auto& [dim, tag] : surfaces_) {
        std::vector<std::size_t> triangle_tags, triangle_nodes;
        gmsh::model::mesh::getElementsByType(kTriangle3, triangle_tags, triangle_nodes, tag);
        if (triangle_tags.empty()) {
          double x0, y0, z0, x1, y1, z1;
          gmsh::model::getBoundingBox(dim, tag, x0, y0, z0, x1, y1, z1);
          empty_patches.emplace_back(tag, Vec3(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)));
          continue;
        }
        for (const Triangle& f : io::in_our_numbering<3>(triangle_nodes, index_of, "triangle")) {
          mesh.triangles.push_back(f);
          mesh.labels.push_back(tag);  // the patch, for now (remesh_once turns it into a label)
        }
      }
    });
    if (!empty_patches.empty())
      throw InputError(fmt::format("Gmsh made no triangles on patch {} of {} (near {}){}: lower the classification angle "
                                   "to cut it smaller, or use the native engine",
                                   empty_patches[0].first, count(), where(empty_patches[0].second),
                                   empty_patches.size() > 1 ? fmt::format(" and on {} more", empty_patches.size() - 1) : ""));
    return mesh;
  }

 private:
  // Each patch's input label, from the input triangles classification put in it (their element
  // tags are our indices + 1; one whose corners differ from ours leaves its patch mixed).
  void label_patches() {
    for (const auto& [dim, tag] : surfaces_) {
      std::vector<std::size_t> element_tags, element_nodes;
      gmsh::model::mesh::getElementsByType(kTriangle3, element_tags, element_nodes, tag);
      int label = kMixed;
      for (size_t e = 0; e < element_tags.size(); ++e) {
        const std::size_t t = element_tags[e] - 1;
        const bool ours = t < input_.triangles.size() &&
                          std::is_permutation(input_.triangles[t].begin(), input_.triangles[t].end(),
                                              element_nodes.begin() + 3 * e, [](int v, std::size_t node) {
                                                return static_cast<std::size_t>(v) + 1 == node;
                                              });
        if (!ours || (e > 0 && input_.labels[t] != label)) {
          label = kMixed;
          break;
        }
        label = input_.labels[t];
      }
      patch_label_[tag] = label;
    }
  }

  const TriMesh& input_;
  const GmshRemeshOptions& o_;
  io::ScopedGmshOptions& options_;
  const Reporter& reporter_;
  gmsh::vectorpair surfaces_;
  int view_ = -1, background_ = -1;  // BAMG's metric view and background field of the last run
  std::unordered_map<int, int> patch_label_;
};

// One remeshing of the classified input to `metrics` (as the native engine: intersected with the
// chord bound of the distance bounds). With `calibrate`, when Gmsh's median edge is off the
// length asked by more than 15 %, the sizes handed to it are scaled by the inverse and the
// patches meshed again (twice at most); `factor` is the scale used, updated.
RemeshResult remesh_once(const TriMesh& input, const std::vector<Sym3>& metrics, const GmshRemeshOptions& o,
                         Patches& patches, double& factor, bool calibrate, const Reporter& reporter) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Sym3> field = effective_metric(input, metrics, o.remesh);
  // Gmsh's points lie on the input's triangles (its patches are theirs): measured against them.
  const SurfaceModel model(input, field, o.remesh.features, Reconstruction::facets);
  TriMesh mesh;
  std::vector<Sym3> metric;  // the field at the mesh's points (their closest input points)
  std::vector<int> hints;    // and the input triangles they lie on
  for (int pass = 0;; ++pass) {
    mesh = patches.mesh(field, model, factor);
    metric.assign(mesh.points.size(), Sym3());
    hints.assign(mesh.points.size(), -1);
    for (size_t v = 0; v < mesh.points.size(); ++v) {
      const Projection p = model.project(mesh.points[v]);
      metric[v] = p.metric;
      hints[v] = p.triangle;
    }
    if (!calibrate) break;
    const double median = median_edge_length(mesh, metric);
    if (std::abs(median - 1.0) <= 0.15 || pass == 2) break;
    reporter.info(fmt::format("Gmsh's edges are {:.2f} of the length asked: asking {:.2f} times the size", median,
                              1.0 / median));
    factor /= median;
  }

  // One surface: shared curve nodes merged, oriented like the input (outward), then checked
  // against the input's topology.
  const mesh::CleanReport cleaned =
      mesh::clean(mesh, {.keep_largest_component = false, .orient_outward = true, .find_self_intersections = false});
  const mesh::Statistics before = mesh::statistics(input), after = mesh::statistics(mesh);
  if (after.components != before.components || after.boundary_loops != before.boundary_loops ||
      after.genus != before.genus) {
    throw InputError(fmt::format("Gmsh's mesh does not have the input's topology ({} components, {} boundary loops, "
                                 "genus {} against {}, {}, {}): a patch was left with a hole or a seam; lower the "
                                 "classification angle or use the native engine",
                                 after.components, after.boundary_loops, after.genus, before.components,
                                 before.boundary_loops, before.genus));
  }
  // The field at the points follows them through the clean.
  std::vector<Sym3> kept_metric(mesh.points.size());
  std::vector<int> kept_hints(mesh.points.size());
  for (size_t v = 0; v < mesh.points.size(); ++v) {
    kept_metric[v] = metric[cleaned.point_origin[v]];
    kept_hints[v] = hints[cleaned.point_origin[v]];
  }
  // Labels: a triangle takes its patch's (the classification never puts a crease inside a patch,
  // so a flat cap and its wall are apart: a sliver along the rim stays on its side); in a patch
  // that spans a label border, the label of the input triangle nearest to its centroid.
  if (input.has_labels()) {
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const int label = patches.label_of(mesh.labels[t]);
      if (label != Patches::kMixed) {
        mesh.labels[t] = label;
        continue;
      }
      const Triangle& f = mesh.triangles[t];
      const Vec3 centroid = (mesh.points[f[0]] + mesh.points[f[1]] + mesh.points[f[2]]) / 3.0;
      mesh.labels[t] = input.labels[model.project(centroid).triangle];
    }
  } else {
    mesh.labels.clear();
  }
  RemeshResult out;
  out.mesh = std::move(mesh);
  out.metric = std::move(kept_metric);
  out.stats = measure(out.mesh, out.metric, model, o.remesh.input_radius, &kept_hints);
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

GmshRemeshResult reparametrize(const TriMesh& input, const std::vector<Sym3>& metrics, const GmshRemeshOptions& o,
                               const Reporter& reporter) {
  if (metrics.size() != input.points.size())
    throw InputError(fmt::format("the metric field has {} values for {} points: it does not belong to this surface",
                                 metrics.size(), input.points.size()));
  if (!(o.classify_angle_deg > 0.0 && o.classify_angle_deg < 180.0))
    throw OptionError("the classification angle must be in (0, 180) degrees");
  if (!(o.size_factor > 0.0) || !std::isfinite(o.size_factor)) throw OptionError("the size factor must be positive");
  if (!(o.target_triangles >= 0.0) || !std::isfinite(o.target_triangles))
    throw OptionError("the target triangle count must be positive (or 0: none)");
  const auto start = std::chrono::steady_clock::now();
  GmshRemeshResult out;
  io::GmshSession session;
  io::ScopedGmshOptions options;
  Patches patches(input, o, options, reporter);
  out.patches = patches.count();
  // Should Gmsh's edges come out off the size asked, the first run calibrates the sizes handed to
  // Gmsh (remesh_once); later runs of the count loop keep that scale and vary the metric's.
  double factor = o.size_factor;
  bool first = true;
  const Engine engine = [&](const std::vector<Sym3>& m) {
    const bool calibrate = first;
    first = false;
    return remesh_once(input, m, o, patches, factor, calibrate, reporter);
  };
  out.result = o.target_triangles > 0.0 ? fit_count(engine, metrics, o.target_triangles, reporter) : engine(metrics);
  out.size_factor = factor;
  out.result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace vesselmesh::remesh
