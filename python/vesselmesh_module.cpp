// The Python module `vesselmesh` (issue 33): the library's stages over numpy arrays, for pipelines
// scripted in Python as VMTK's pypes and VaMPy are. Surfaces are (points, triangles): points an
// (n, 3) float64 array in mm, triangles an (m, 3) int32 array of point indices from 0; volumes are
// dicts (points, tetrahedra, boundary, boundary_tags, tag_names). Errors are Python exceptions with
// the library's messages: ValueError for bad input (vesselmesh's exit code 2), RuntimeError
// otherwise. Long stages release the GIL. Built against Debian's own /usr/bin/python3 (its numpy
// and pybind11): import it from the build folder (build/python) or where it is installed.
#include "analysis/curvature.h"
#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "flow/case.h"
#include "flow/simulate.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/surface.h"
#include "io/units.h"
#include "io/volume_file.h"
#include "io/vtk_formats.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/statistics.h"
#include "post/ring.h"
#include "post/wall_series.h"
#include "remesh/adapt.h"
#include "remesh/extend.h"
#include "sizing/size_field.h"
#include "study/study.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <toml++/toml.h>

#include <filesystem>
#include <optional>
#include <sstream>
#include <string>

namespace py = pybind11;
using namespace vesselmesh;

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Indices = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

py::array_t<double> points_array(const std::vector<Vec3>& points) {
  py::array_t<double> a({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto v = a.mutable_unchecked<2>();
  for (size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) v(static_cast<py::ssize_t>(i), k) = points[i][k];
  return a;
}

template <size_t N>
py::array_t<int32_t> index_array(const std::vector<std::array<int, N>>& rows) {
  py::array_t<int32_t> a({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(N)});
  auto v = a.mutable_unchecked<2>();
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t k = 0; k < N; ++k) v(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) = rows[i][k];
  return a;
}

py::array_t<double> values_array(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

std::vector<Vec3> to_points(const Points& points, const char* what) {
  if (points.ndim() != 2 || points.shape(1) != 3)
    throw InputError(fmt::format("{}: expected an (n, 3) array of points", what));
  std::vector<Vec3> out(static_cast<size_t>(points.shape(0)));
  auto v = points.unchecked<2>();
  for (py::ssize_t i = 0; i < points.shape(0); ++i) out[static_cast<size_t>(i)] = Vec3(v(i, 0), v(i, 1), v(i, 2));
  return out;
}

template <size_t N>
std::vector<std::array<int, N>> to_rows(const Indices& rows, size_t points, const char* what) {
  if (rows.ndim() != 2 || rows.shape(1) != static_cast<py::ssize_t>(N))
    throw InputError(fmt::format("{}: expected an (m, {}) array of point indices", what, N));
  std::vector<std::array<int, N>> out(static_cast<size_t>(rows.shape(0)));
  auto v = rows.unchecked<2>();
  for (py::ssize_t i = 0; i < rows.shape(0); ++i)
    for (size_t k = 0; k < N; ++k) {
      const int p = v(i, static_cast<py::ssize_t>(k));
      if (p < 0 || static_cast<size_t>(p) >= points)
        throw InputError(fmt::format("{}: row {} names point {}, not among the {} points", what, i, p, points));
      out[static_cast<size_t>(i)][k] = p;
    }
  return out;
}

TriMesh to_surface(const Points& points, const Indices& triangles) {
  TriMesh mesh;
  mesh.points = to_points(points, "points");
  mesh.triangles = to_rows<3>(triangles, mesh.points.size(), "triangles");
  return mesh;
}

py::tuple surface_tuple(const TriMesh& mesh) { return py::make_tuple(points_array(mesh.points), index_array(mesh.triangles)); }

py::dict volume_dict(const TetMesh& mesh) {
  py::dict d;
  d["points"] = points_array(mesh.points);
  d["tetrahedra"] = index_array(mesh.tets);
  d["prisms"] = index_array(mesh.prisms);
  d["boundary"] = index_array(mesh.boundary);
  d["boundary_tags"] = py::array_t<int32_t>(static_cast<py::ssize_t>(mesh.boundary_tags.size()), mesh.boundary_tags.data());
  py::dict names;
  for (const auto& [tag, name] : mesh.tag_names) names[py::int_(tag)] = name;
  d["tag_names"] = names;
  return d;
}

TetMesh to_volume(const py::dict& d) {
  TetMesh mesh;
  mesh.points = to_points(d["points"].cast<Points>(), "volume['points']");
  mesh.tets = to_rows<4>(d["tetrahedra"].cast<Indices>(), mesh.points.size(), "volume['tetrahedra']");
  if (d.contains("prisms")) mesh.prisms = to_rows<6>(d["prisms"].cast<Indices>(), mesh.points.size(), "volume['prisms']");
  mesh.boundary = to_rows<3>(d["boundary"].cast<Indices>(), mesh.points.size(), "volume['boundary']");
  const auto tags = d["boundary_tags"].cast<Indices>();
  mesh.boundary_tags.assign(tags.data(), tags.data() + tags.size());
  if (mesh.boundary_tags.size() != mesh.boundary.size())
    throw InputError("volume: a boundary tag per boundary triangle is needed");
  for (const auto& [tag, name] : d["tag_names"].cast<py::dict>()) mesh.tag_names[tag.cast<int>()] = name.cast<std::string>();
  return mesh;
}

sizing::SizeKind kind_of(const std::string& name) { return sizing::parse_size_kind(name); }

// A case given as a dict: the same keys as the TOML file ({"mesh": ..., "time": {...}, "boundary":
// [{...}, ...]}), turned into TOML and read by the same reader (the same checks and messages).
void add_value(toml::table& table, const std::string& key, const py::handle& value);
toml::array to_array(const py::handle& list, const std::string& key) {
  toml::array a;
  for (const py::handle& item : list) {
    toml::table holder;
    add_value(holder, key, item);
    a.push_back(std::move(*holder.get(key)));
  }
  return a;
}
void add_value(toml::table& table, const std::string& key, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) {
    table.insert_or_assign(key, value.cast<bool>());
  } else if (py::isinstance<py::int_>(value)) {
    table.insert_or_assign(key, value.cast<int64_t>());
  } else if (py::isinstance<py::float_>(value)) {
    table.insert_or_assign(key, value.cast<double>());
  } else if (py::isinstance<py::str>(value)) {
    table.insert_or_assign(key, value.cast<std::string>());
  } else if (py::isinstance<py::dict>(value)) {
    toml::table inner;
    for (const auto& [k, v] : value.cast<py::dict>()) add_value(inner, py::str(k).cast<std::string>(), v);
    table.insert_or_assign(key, std::move(inner));
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    table.insert_or_assign(key, to_array(value, key));
  } else {
    throw InputError(fmt::format("key \"{}\": a {} is not a TOML value (give numbers, strings, booleans, lists "
                                 "or dicts)",
                                 key, py::str(value.get_type().attr("__name__")).cast<std::string>()));
  }
}
// A dict of a file's keys as TOML text, for the file's own reader (its checks and messages).
std::string toml_text(const py::dict& given) {
  toml::table root;
  for (const auto& [k, v] : given) add_value(root, py::str(k).cast<std::string>(), v);
  std::ostringstream text;
  text << root;
  return text.str();
}

flow::FlowCase case_of(const py::object& given) {
  if (py::isinstance<py::str>(given)) return flow::read_case(given.cast<std::string>());
  if (!py::isinstance<py::dict>(given)) throw InputError("case: give a case file's path or a dict of its keys");
  // Paths in it (the mesh, waveforms) are taken from the working folder.
  return flow::parse_case(toml_text(given.cast<py::dict>()), (std::filesystem::current_path() / "case (a dict)").string());
}

// A study file's path, or a dict of its keys: a dict is written as TOML into the output folder
// (study_input.toml, which the report quotes) and its paths are taken from the working folder.
study::StudyConfig study_of(const py::object& given, const std::string& output) {
  if (py::isinstance<py::str>(given)) return study::read_study(given.cast<std::string>());
  if (!py::isinstance<py::dict>(given)) throw InputError("study: give a study file's path or a dict of its keys");
  const std::string text = toml_text(given.cast<py::dict>());
  const std::filesystem::path cwd = std::filesystem::current_path();
  study::StudyConfig config = study::parse_study(text, (cwd / "study (a dict)").string());
  std::filesystem::create_directories(output);
  config.path = (std::filesystem::path(output) / "study_input.toml").string();
  io::write_text(config.path, fmt::format("# The study given to vesselmesh.study() as a dict; its paths are from {}\n{}\n",
                                          cwd.string(), text));
  return config;
}

// The centerlines and distance map of a surface (ValueError when it has no ends to trace between).
centerline::DistanceMap distance_of(const TriMesh& mesh) { return centerline::distance_map(mesh, centerline::extract(mesh)); }

// Surfaces: reading and writing, their ends, curvature, centerlines and distance map.
void define_surface_functions(py::module_& m) {
  m.def(
      "read_surface",
      [](const std::string& path, const std::string& units, bool repair) {
        io::SurfaceFile file = [&] {
          py::gil_scoped_release release;
          io::SurfaceFile f = io::read_surface(path, {.units = io::parse_unit(units)});
          if (repair) mesh::clean(f.mesh, {.find_self_intersections = false});
          return f;
        }();
        return surface_tuple(file.mesh);
      },
      py::arg("path"), py::arg("units") = "mm", py::arg("repair") = true,
      "Reads a surface (.stl, .vtp, .vtu, .ply, .obj, .msh, .mesh) in `units` (um, mm, cm, m) and returns (points in "
      "mm, triangles). `repair`: the mesh doctor as `vesselmesh info` runs it (merged points, consistent outward "
      "orientation, degenerate and duplicate triangles gone).");
  m.def(
      "write_surface",
      [](const std::string& path, const Points& points, const Indices& triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        py::gil_scoped_release release;
        io::write_surface(path, mesh);
      },
      py::arg("path"), py::arg("points"), py::arg("triangles"),
      "Writes a surface by its extension (.stl, .vtp, .msh, .mesh), lengths as given (mm).");
  m.def(
      "info",
      [](const Points& points, const Indices& triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        const mesh::Statistics s = mesh::statistics(mesh);
        py::dict d;
        d["points"] = s.points;
        d["triangles"] = s.triangles;
        d["components"] = s.components;
        d["closed"] = s.closed;
        d["genus"] = s.genus;
        d["area"] = s.area;
        d["volume"] = s.volume;
        py::list ends;
        for (const analysis::OpenEnd& e : analysis::open_ends(mesh))
          ends.append(py::dict(py::arg("center") = std::vector<double>{e.center.x(), e.center.y(), e.center.z()},
                               py::arg("normal") = std::vector<double>{e.normal.x(), e.normal.y(), e.normal.z()},
                               py::arg("radius") = e.radius, py::arg("area") = e.area, py::arg("capped") = e.capped));
        d["ends"] = ends;
        return d;
      },
      py::arg("points"), py::arg("triangles"),
      "What `vesselmesh info` says of a surface: counts, components, closed, genus, area (mm2), enclosed volume "
      "(mm3), and its ends (centre, outward normal, equivalent radius, area; largest first).");
  m.def(
      "curvature",
      [](const Points& points, const Indices& triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        analysis::CurvatureField c;
        {
          py::gil_scoped_release release;
          c = analysis::curvature(mesh);
        }
        std::vector<double> mean(c.k1.size()), gauss(c.k1.size());
        for (int v = 0; v < c.size(); ++v) mean[v] = c.mean(v), gauss[v] = c.gauss(v);
        return py::dict(py::arg("k1") = values_array(c.k1), py::arg("k2") = values_array(c.k2),
                        py::arg("mean_curvature") = values_array(mean), py::arg("gauss_curvature") = values_array(gauss),
                        py::arg("dir1") = points_array(c.dir1), py::arg("dir2") = points_array(c.dir2),
                        py::arg("normal") = points_array(c.normal));
      },
      py::arg("points"), py::arg("triangles"),
      "Principal curvatures per point (1/mm; k1 <= k2, positive where the outward surface is convex), their "
      "directions and the normal (Rusinkiewicz 2004), as `vesselmesh curvature` writes them.");
  m.def(
      "centerlines",
      [](const Points& points, const Indices& triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        centerline::Centerlines lines;
        {
          py::gil_scoped_release release;
          lines = centerline::extract(mesh);
        }
        py::list branches;
        for (const centerline::Branch& b : lines.branches)
          branches.append(py::dict(py::arg("id") = b.id, py::arg("parent") = b.parent,
                                   py::arg("points") = points_array(b.points), py::arg("radius") = values_array(b.radius)));
        return branches;
      },
      py::arg("points"), py::arg("triangles"),
      "Centerlines from the inlet (the largest end) to every outlet through the lumen's internal Voronoi diagram, "
      "split into branches: a list of dicts (id, parent, points (k, 3), radius: the maximal inscribed sphere's, mm).");
  m.def(
      "distance_map",
      [](const Points& points, const Indices& triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        centerline::DistanceMap d;
        {
          py::gil_scoped_release release;
          d = distance_of(mesh);
        }
        return py::dict(py::arg("distance") = values_array(d.distance), py::arg("radius") = values_array(d.radius));
      },
      py::arg("points"), py::arg("triangles"),
      "Each surface point's distance to the centerlines and the inscribed radius there (mm).");
}

// Meshing: size fields, remeshing, flow extensions, volumes read, made and written.
void define_meshing_functions(py::module_& m) {
  m.def(
      "size_field",
      [](const Points& points, const Indices& triangles, const std::string& kind, double target_triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        sizing::SizeField field;
        {
          py::gil_scoped_release release;
          const analysis::CurvatureField c = analysis::curvature(mesh);
          std::optional<centerline::DistanceMap> d;
          if (kind_of(kind) == sizing::SizeKind::distance) d = distance_of(mesh);
          field = sizing::make_size_field(mesh, {.kind = kind_of(kind), .target_triangles = target_triangles},
                                          {.curvature = &c, .distance = d ? &*d : nullptr});
        }
        py::array_t<double> metric({static_cast<py::ssize_t>(field.metric.size()), py::ssize_t{6}});
        auto v = metric.mutable_unchecked<2>();
        for (size_t i = 0; i < field.metric.size(); ++i)
          for (int k = 0; k < 6; ++k) v(static_cast<py::ssize_t>(i), k) = field.metric[i].v[static_cast<size_t>(k)];
        return py::dict(py::arg("size") = values_array(field.size), py::arg("metric") = metric,
                        py::arg("predicted_triangles") = field.predicted_triangles);
      },
      py::arg("points"), py::arg("triangles"), py::arg("kind") = "curvature", py::arg("target_triangles") = 0.0,
      "The size field the remesher adapts to: kind uniform, distance, curvature or anisotropic, scaled to "
      "`target_triangles` when positive: per point its size (mm) and metric (xx, xy, xz, yy, yz, zz).");
  m.def(
      "remesh",
      [](const Points& points, const Indices& triangles, const std::string& kind, double target_triangles) {
        const TriMesh mesh = to_surface(points, triangles);
        remesh::RemeshResult r;
        {
          py::gil_scoped_release release;
          const analysis::CurvatureField c = analysis::curvature(mesh);
          const centerline::DistanceMap d = distance_of(mesh);
          const sizing::SizeField field = sizing::make_size_field(
              mesh, {.kind = kind_of(kind), .target_triangles = target_triangles}, {.curvature = &c, .distance = &d});
          remesh::RemeshOptions options;
          options.input_radius = &d.radius;
          r = remesh::adapt_to_count(mesh, field.metric, target_triangles, options);
        }
        const py::dict stats(py::arg("triangles") = r.stats.triangles, py::arg("points") = r.stats.points,
                             py::arg("min_angle_deg") = r.stats.min_angle_deg,
                             py::arg("mean_quality") = r.stats.mean_quality, py::arg("hausdorff") = r.stats.hausdorff,
                             py::arg("hausdorff_relative") = r.stats.hausdorff_relative,
                             py::arg("hausdorff_facets") = r.stats.hausdorff_facets,
                             py::arg("count_note") = r.count_note, py::arg("least_count") = r.least_count);
        return py::make_tuple(points_array(r.mesh.points), index_array(r.mesh.triangles), stats);
      },
      py::arg("points"), py::arg("triangles"), py::arg("kind") = "curvature", py::arg("target_triangles") = 8000.0,
      "Remeshes a surface with ends to about `target_triangles` triangles adapted to the size field of `kind` "
      "(uniform, distance, curvature, anisotropic), as `vesselmesh remesh --size KIND --target-triangles N`; returns "
      "(points, triangles, stats): stats' hausdorff is the distance to the smooth surface the input's triangles "
      "stand for, hausdorff_facets to the triangles; count_note says why the count stays more than 3 % off the "
      "target (empty when within), least_count the least count the distance bound allows this kind where it holds "
      "the count over the target (0: not measured).");
  m.def(
      "extend",
      [](const Points& points, const Indices& triangles, double length) {
        const TriMesh mesh = to_surface(points, triangles);
        remesh::ExtensionResult r;
        {
          py::gil_scoped_release release;
          r = remesh::extend_ends(mesh, analysis::open_ends(mesh), {.length = length});
        }
        return surface_tuple(r.mesh);
      },
      py::arg("points"), py::arg("triangles"), py::arg("length") = 5.0,
      "Flow extensions: a tube of `length` radii on every open end, as `vesselmesh extend`.");
  m.def(
      "volume",
      [](const Points& points, const Indices& triangles, int layers, double thickness_ratio) {
        const TriMesh mesh = to_surface(points, triangles);
        volume::VolumeResult r;
        {
          py::gil_scoped_release release;
          const centerline::DistanceMap d = distance_of(mesh);
          volume::VolumeOptions options;
          options.layer.layers = layers;
          options.layer.thickness_ratio = thickness_ratio;
          r = volume::build_volume(mesh, analysis::open_ends(mesh), d.radius, options);
        }
        return volume_dict(r.mesh);
      },
      py::arg("points"), py::arg("triangles"), py::arg("layers") = 4, py::arg("thickness_ratio") = 0.1,
      "The boundary-layer volume mesh of a (remeshed) surface, as `vesselmesh volume`: a dict of points (mm), "
      "tetrahedra, boundary triangles, their tags and the tags' names (wall, inlet, outlet_1, ...).");
  m.def(
      "read_volume",
      [](const std::string& path) {
        TetMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = io::read_volume(path);
        }
        return volume_dict(mesh);
      },
      py::arg("path"), "Reads a volume mesh (.msh as `vesselmesh volume` writes it, or .vtu with cell data tag).");
  m.def(
      "write_volume",
      [](const std::string& path, const py::dict& volume) {
        const TetMesh mesh = to_volume(volume);
        py::gil_scoped_release release;
        io::write_volume(path, mesh);
      },
      py::arg("path"), py::arg("volume"), "Writes a volume dict as .msh (Gmsh 4.1, for `simulate`) or .vtu.");
}

// The flow, the mesh-impact study and the WSS along a ring.
void define_flow_functions(py::module_& m) {
  m.def(
      "simulate",
      [](const py::object& case_given, const std::string& output, const std::string& mesh) {
        flow::FlowCase fc = case_of(case_given);
        if (!mesh.empty()) fc.mesh = mesh;
        flow::SimulationSummary s;
        {
          py::gil_scoped_release release;
          s = flow::simulate(fc, output);
        }
        return py::dict(py::arg("status") = s.status, py::arg("points") = s.points, py::arg("dofs") = s.dofs,
                        py::arg("steps") = s.steps, py::arg("saved") = s.saved,
                        py::arg("linear_iterations") = s.linear_iterations, py::arg("seconds") = s.seconds,
                        py::arg("steady_residual") = s.steady_residual, py::arg("output") = output);
      },
      py::arg("case"), py::arg("output"), py::arg("mesh") = "",
      "Runs a flow case — a case file (TOML, as `vesselmesh simulate`) or a dict of the same keys, e.g. "
      "{'mesh': 'volume.msh', 'time': {'steady': True}, 'boundary': [{'tag': 'inlet', 'type': 'velocity', 'flow': 1.0}, "
      "...]} (its paths from the working folder) — into the folder `output` (fluid.pvd, wall.pvd, log.csv, "
      "summary.json); `mesh` replaces its mesh. Returns the summary.");
  m.def(
      "study",
      [](const py::object& study_given, const std::string& output) {
        const study::StudyConfig config = study_of(study_given, output);
        {
          py::gil_scoped_release release;
          study::run_study(config, output);
        }
        const std::string text = io::read_file((std::filesystem::path(output) / "study.json").string());
        return py::module_::import("json").attr("loads")(text);
      },
      py::arg("study"), py::arg("output"),
      "Runs the mesh-impact study — a study file (TOML, as `vesselmesh study`) or a dict of the same keys, e.g. "
      "{'surface': 'vessel.stl', 'case': 'flow.toml', 'triangles': 4000, 'reference': {'levels': 1}, 'ring': "
      "[{'name': 'inlet', 'point': [0, 0, -10]}]} (its paths from the working folder) — into the folder `output` "
      "(report.html, report.md, study.json, a folder per mesh). Returns what study.json holds: 'meshes', "
      "'differences', 'summary' (its 'rankings' and 'mean_place'), 'whole_wall', 'grid_convergence', ...");
  m.def(
      "wss_ring",
      [](const std::string& results, const std::vector<double>& point, const std::vector<double>& normal,
         std::optional<double> time) {
        if (point.size() != 3 || normal.size() != 3) throw InputError("point and normal: three numbers each");
        post::Ring ring;
        {
          py::gil_scoped_release release;
          const post::WallSeries series = post::read_wall_series(results);
          const post::WallField wall = post::wall_at_time(series, time.value_or(series.frames.back().time));
          ring = post::cut_ring(wall.mesh, wall.wss,
                                {.name = "ring", .point = Vec3(point[0], point[1], point[2]),
                                 .normal = Vec3(normal[0], normal[1], normal[2]), .reference = std::nullopt});
        }
        std::vector<double> s, angle, magnitude;
        for (const post::RingSample& sample : ring.samples) {
          s.push_back(sample.arc_length);
          angle.push_back(sample.angle);
          magnitude.push_back(sample.magnitude);
        }
        return py::dict(py::arg("arc_length") = values_array(s), py::arg("angle") = values_array(angle),
                        py::arg("wss") = values_array(magnitude), py::arg("length") = ring.length,
                        py::arg("minimum") = ring.minimum, py::arg("closed") = ring.closed);
      },
      py::arg("results"), py::arg("point"), py::arg("normal"), py::arg("time") = py::none(),
      "WSS magnitude (Pa) along the ring where the plane (point, normal; mm) cuts the wall of `simulate`'s results, "
      "at `time` (s; linear between saved frames; default the last): arc length (mm), angle (degrees), wss.");
}

}  // namespace

PYBIND11_MODULE(vesselmesh, m) {
  m.doc() = "vesselmesh: vessel lumen surfaces to curvature- and radius-adapted surface meshes, boundary-layer volume "
            "meshes, flow and wall shear stress. Lengths in mm, points (n, 3) float64, triangles (m, 3) int32. "
            "GPL-3.0-or-later.";
  m.attr("__version__") = VESSELMESH_VERSION;
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const OptionError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  define_surface_functions(m);
  define_meshing_functions(m);
  define_flow_functions(m);
}
