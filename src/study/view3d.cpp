#include "study/view3d.h"

#include "io/atomic_file.h"
#include "io/base64.h"
#include "mesh/decimate.h"
#include "study/chart.h"
#include "study/picture.h"
#include "study/wall_difference.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace vesselmesh::study {
namespace {

using Json = nlohmann::ordered_json;

// Little-endian float32 and uint32 arrays (the machines that run the report and the browsers that
// read it are little-endian; typed arrays in the browser read the platform's order).
std::string floats(const std::vector<float>& v) { return io::encode_base64(v.data(), v.size() * sizeof(float)); }

std::string positions(const TriMesh& mesh) {
  std::vector<float> v;
  v.reserve(3 * mesh.points.size());
  for (const Vec3& p : mesh.points)
    for (int k = 0; k < 3; ++k) v.push_back(static_cast<float>(p[k]));
  return floats(v);
}

std::string triangles(const TriMesh& mesh) {
  std::vector<uint32_t> v;
  v.reserve(3 * mesh.triangles.size());
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) v.push_back(static_cast<uint32_t>(t[k]));
  return io::encode_base64(v.data(), v.size() * sizeof(uint32_t));
}

std::string values(const std::vector<double>& v) { return floats(std::vector<float>(v.begin(), v.end())); }

std::string polyline(const std::vector<Vec3>& line) {
  std::vector<float> v;
  for (const Vec3& p : line)
    for (int k = 0; k < 3; ++k) v.push_back(static_cast<float>(p[k]));
  return floats(v);
}

constexpr int kStops = 32;

// A colour table of kStops + 1 stops (RGB in [0, 1], flat), for the script to interpolate.
template <class Map>
Json table(Map map, double from, double to) {
  Json t = Json::array();
  for (int k = 0; k <= kStops; ++k) {
    const std::array<double, 3> c = map(from + (to - from) * k / kStops);
    for (double v : c) t.push_back(std::round(v * 1000.0) / 1000.0);
  }
  return t;
}

std::string css_colour(const std::array<double, 3>& c) {
  return fmt::format("rgb({},{},{})", std::lround(255 * c[0]), std::lround(255 * c[1]), std::lround(255 * c[2]));
}

// A horizontal colour bar, `colour` at s in [0, 1] from left to right, with five ticks from `from` to
// `to`, as HTML.
template <class Colour>
std::string legend(const std::string& id, const std::string& label, Colour colour, double from, double to, bool shown) {
  std::string stops;
  for (int k = 0; k <= 8; ++k) stops += fmt::format("{}{} {:.1f}%", k ? "," : "", css_colour(colour(k / 8.0)), 12.5 * k);
  std::string ticks;
  for (int k = 0; k <= 4; ++k)
    ticks += fmt::format("<span style=\"position:absolute;left:{}%;transform:translateX(-50%)\">{:.3g}</span>", 25 * k,
                         from + (to - from) * k / 4.0);
  return fmt::format(
      "<div id=\"{}\" style=\"display:{};margin:.5em 1.5em 1.2em\"><div>{}</div><div style=\"width:360px;height:14px;"
      "background:linear-gradient(to right,{})\"></div><div style=\"position:relative;width:360px;height:1em;"
      "font-size:.85em\">{}</div></div>\n",
      id, shown ? "block" : "none", xml_escape(label), stops, ticks);
}

// The viewer (three.js r111 and its OrbitControls loaded before it).
constexpr const char* kViewerScript = R"JS(
(function () {
  'use strict';
  var status = document.getElementById('view3d-status');
  var errors = window.__view3dErrors;
  function finish(views) {
    var rects = views.map(function (v) {
      var b = v.canvas.getBoundingClientRect();
      return [Math.round(b.left + window.scrollX), Math.round(b.top + window.scrollY), Math.round(b.width),
              Math.round(b.height)];
    });
    status.textContent = JSON.stringify({drawn: views.length, errors: errors, rects: rects,
                                         milliseconds: Math.round(performance.now())});
  }
  var focus = /[?&]view3d(=([a-z]+))?/.exec(window.location.search);
  // The views alone: report.html?view3d (or ?view3d=difference); the rule also hides what follows.
  if (focus) document.documentElement.className += ' view3d-only';
  function show() {
  try {
    // three.js and its controls, kept as text until the views are wanted: parsing them is most of
    // the view's cost, which a reader who never scrolls here does not pay.
    ['view3d-three', 'view3d-controls'].forEach(function (id) {
      var script = document.createElement('script');
      script.text = document.getElementById(id).textContent;
      document.head.appendChild(script);
    });
    var data = JSON.parse(document.getElementById('view3d-data').textContent);
    var bytes = function (s) {
      var b = atob(s), u = new Uint8Array(b.length);
      for (var i = 0; i < b.length; ++i) u[i] = b.charCodeAt(i);
      return u.buffer;
    };
    var floats = function (s) { return new Float32Array(bytes(s)); };
    var colours = function (values, table, low, high) {
      var n = table.length / 3 - 1, c = new Float32Array(values.length * 3);
      for (var i = 0; i < values.length; ++i) {
        var t = Math.min(1, Math.max(0, (values[i] - low) / (high - low))) * n;
        var k = Math.min(n - 1, Math.floor(t)), f = t - k;
        for (var j = 0; j < 3; ++j) c[3 * i + j] = table[3 * k + j] + f * (table[3 * k + 3 + j] - table[3 * k + j]);
      }
      return c;
    };
    var surface = function (points, triangles, values, table, low, high) {
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(points, 3));
      g.setAttribute('color', new THREE.BufferAttribute(colours(values, table, low, high), 3));
      g.setIndex(new THREE.BufferAttribute(triangles, 1));
      g.computeVertexNormals();
      // Pushed back a little, so that the rings drawn on it stay in front.
      return new THREE.Mesh(g, new THREE.MeshLambertMaterial({vertexColors: THREE.VertexColors,
                                                               side: THREE.DoubleSide, polygonOffset: true,
                                                               polygonOffsetFactor: 1, polygonOffsetUnits: 1}));
    };
    var rings = function (list) {
      var group = new THREE.Group();
      list.forEach(function (s) {
        var g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(floats(s), 3));
        group.add(new THREE.Line(g, new THREE.LineBasicMaterial({color: 0x000000})));
      });
      return group;
    };
    var ref = data.walls[data.reference];
    var refPoints = floats(ref.points), refTriangles = new Uint32Array(bytes(ref.triangles));
    var c = new THREE.Vector3().fromArray(data.center), r = data.radius;
    var canvas0 = document.getElementById('view3d-canvas-0');
    var camera = new THREE.PerspectiveCamera(30, canvas0.clientWidth / canvas0.clientHeight, r / 100, r * 100);
    camera.up.fromArray(data.up);
    camera.position.copy(c).addScaledVector(new THREE.Vector3().fromArray(data.view), -3.4 * r);
    camera.lookAt(c);
    var views = [], controls = [];
    var draw = function () {
      views.forEach(function (v) {
        v.light.position.copy(camera.position);
        v.renderer.render(v.scene, camera);
      });
    };
    data.walls.forEach(function (w, k) {
      var canvas = document.getElementById('view3d-canvas-' + k);
      var renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
      renderer.setPixelRatio(window.devicePixelRatio || 1);
      renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
      renderer.setClearColor(0xffffff);
      var scene = new THREE.Scene();
      scene.add(new THREE.AmbientLight(0xffffff, 0.6));
      var light = new THREE.DirectionalLight(0xffffff, 0.5);
      scene.add(light);
      var own = new THREE.Group(), diff = new THREE.Group();
      own.add(surface(floats(w.points), new Uint32Array(bytes(w.triangles)), floats(w.magnitude), data.wss_table, 0,
                      data.high));
      own.add(rings(w.rings));
      if (w.difference) {
        diff.add(surface(refPoints, refTriangles, floats(w.difference), data.difference_table,
                         -data.difference_range, data.difference_range));
        diff.add(rings(ref.rings));
      }
      diff.visible = false;
      scene.add(own);
      scene.add(diff);
      data.points.forEach(function (p) {
        var m = new THREE.Mesh(new THREE.SphereBufferGeometry(0.012 * r, 16, 8),
                               new THREE.MeshBasicMaterial({color: 0xff00ff}));
        m.position.fromArray(p.point);
        scene.add(m);
      });
      var control = new THREE.OrbitControls(camera, canvas);
      control.target.copy(c);
      control.update();
      control.addEventListener('change', function () {
        controls.forEach(function (o) { if (o !== control) o.target.copy(control.target); });
        draw();
      });
      controls.push(control);
      views.push({canvas: canvas, renderer: renderer, scene: scene, light: light, own: own, diff: diff,
                  compared: !!w.difference});
    });
    Array.prototype.forEach.call(document.querySelectorAll('input[name=view3d-mode]'), function (input) {
      input.addEventListener('change', function () {
        var difference = input.value === 'difference' && input.checked;
        views.forEach(function (v) {
          v.own.visible = !(difference && v.compared);
          v.diff.visible = difference && v.compared;
        });
        document.getElementById('view3d-legend-wss').style.display = difference ? 'none' : 'block';
        document.getElementById('view3d-legend-difference').style.display = difference ? 'block' : 'none';
        draw();
      });
    });
    var start = focus && focus[2] && document.querySelector('input[name=view3d-mode][value=' + focus[2] + ']');
    if (start) {
      start.checked = true;
      start.dispatchEvent(new Event('change'));
    }
    draw();
    finish(views);
  } catch (e) {
    errors.push(String(e && e.stack ? e.stack : e));
    finish([]);
  }
  }
  // Drawn when the section comes near the window (at once with ?view3d).
  if (focus || !('IntersectionObserver' in window)) {
    show();
  } else {
    var seen = new IntersectionObserver(function (entries) {
      if (entries.some(function (e) { return e.isIntersecting; })) {
        seen.disconnect();
        show();
      }
    }, {rootMargin: '400px'});
    seen.observe(document.getElementById('view3d'));
  }
})();
)JS";

// Text that may sit inside a <script> element: "</" broken so that it cannot close the element.
std::string script_safe(std::string text) {
  for (size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3)) text.replace(at, 2, "<\\/");
  return text;
}

}  // namespace

std::array<double, 3> diverging(double t) {
  constexpr std::array<double, 3> blue = {0.230, 0.299, 0.754}, white = {0.865, 0.865, 0.865},
                                  red = {0.706, 0.016, 0.150};
  t = std::clamp(t, -1.0, 1.0);
  const std::array<double, 3>& end = t < 0.0 ? blue : red;
  const double f = std::abs(t);
  return {white[0] + f * (end[0] - white[0]), white[1] + f * (end[1] - white[1]), white[2] + f * (end[2] - white[2])};
}

ViewedWall viewed_wall(const std::string& name, const TriMesh& wall, const std::vector<double>& magnitude,
                       int max_triangles) {
  ViewedWall v;
  v.name = name;
  v.mesh = mesh::decimated(wall, max_triangles);
  v.magnitude = v.mesh.num_triangles() == wall.num_triangles() ? magnitude : interpolate(map_onto(wall, v.mesh), magnitude);
  return v;
}

std::vector<double> difference_on(const ViewedWall& reference, const TriMesh& wall,
                                  const std::vector<double>& magnitude) {
  std::vector<double> d = interpolate(map_onto(wall, reference.mesh), magnitude);
  for (size_t i = 0; i < d.size(); ++i) d[i] -= reference.magnitude[i];
  return d;
}

std::optional<ThreeScripts> read_three_scripts() {
  const char* env = std::getenv("VESSELMESH_THREE_DIR");
  const std::filesystem::path dir = env && *env ? env : "/usr/share/javascript/three";
  const std::filesystem::path three = dir / "three.min.js", controls = dir / "examples/js/controls/OrbitControls.js";
  if (!std::filesystem::is_regular_file(three) || !std::filesystem::is_regular_file(controls)) return std::nullopt;
  return ThreeScripts{io::read_file(three.string()), io::read_file(controls.string())};
}

std::string view3d_html(const ViewScene& scene, const ThreeScripts& scripts) {
  const ViewedWall& reference = scene.walls.at(scene.reference);
  Vec3 low = Vec3::Constant(INFINITY), high = Vec3::Constant(-INFINITY);
  for (const Vec3& p : reference.mesh.points) low = low.cwiseMin(p), high = high.cwiseMax(p);
  const Vec3 center = reference.mesh.points.empty() ? Vec3::Zero() : Vec3(0.5 * (low + high));
  const double radius = reference.mesh.points.empty() ? 1.0 : std::max(0.5 * (high - low).norm(), 1e-12);
  const Vec3 view = scene.view.normalized(), up = screen_up(view);
  Json data;
  data["center"] = {center.x(), center.y(), center.z()};
  data["radius"] = radius;
  data["view"] = {view.x(), view.y(), view.z()};
  data["up"] = {up.x(), up.y(), up.z()};
  data["high"] = scene.high;
  data["difference_range"] = scene.difference_range;
  data["wss_table"] = table(viridis, 0.0, 1.0);
  data["difference_table"] = table(diverging, -1.0, 1.0);
  data["reference"] = scene.reference;
  data["points"] = Json::array();
  for (const auto& [name, p] : scene.points) data["points"].push_back({{"name", name}, {"point", {p.x(), p.y(), p.z()}}});
  data["walls"] = Json::array();
  std::string figures;
  for (size_t k = 0; k < scene.walls.size(); ++k) {
    const ViewedWall& w = scene.walls[k];
    Json wall = {{"name", w.name}, {"points", positions(w.mesh)}, {"triangles", triangles(w.mesh)},
                 {"magnitude", values(w.magnitude)}, {"rings", Json::array()}};
    if (!w.difference.empty()) wall["difference"] = values(w.difference);
    for (const std::vector<Vec3>& ring : w.rings) wall["rings"].push_back(polyline(ring));
    data["walls"].push_back(wall);
    figures += fmt::format(
        "<figure style=\"margin:0\"><canvas id=\"view3d-canvas-{}\" style=\"width:460px;height:330px;border:1px solid "
        "#ccc;touch-action:none\"></canvas><figcaption>{}{} ({} triangles shown)</figcaption></figure>\n",
        k, xml_escape(w.name), k == scene.reference ? " (reference)" : "", w.mesh.num_triangles());
  }
  std::string html = "<section id=\"view3d\">\n<style>.view3d-only body>:not(#view3d){display:none!important}"
                     ".view3d-only body{max-width:none!important}</style>\n";
  html += "<p><label><input type=\"radio\" name=\"view3d-mode\" value=\"wss\" checked> |WSS|</label> &nbsp; "
          "<label><input type=\"radio\" name=\"view3d-mode\" value=\"difference\"> each mesh's |WSS| minus the "
          "reference's, on the reference's wall</label></p>\n";
  html += legend("view3d-legend-wss", "|WSS| (Pa), every view", viridis, 0.0, scene.high, true);
  html += legend(
      "view3d-legend-difference", "|WSS| minus the reference's (Pa); the reference's own view shows its |WSS|",
      [](double s) { return diverging(2.0 * s - 1.0); }, -scene.difference_range, scene.difference_range, false);
  html += "<div style=\"display:flex;flex-wrap:wrap;gap:10px\">\n" + figures + "</div>\n";
  html += "<pre id=\"view3d-status\" style=\"display:none\">pending</pre>\n";
  html += "<script>window.__view3dErrors = window.__view3dErrors || []; window.addEventListener('error', "
          "function (e) { window.__view3dErrors.push(String(e.message)); });</script>\n";
  html += "<script type=\"text/x-three\" id=\"view3d-three\">" + script_safe(scripts.three) + "\n</script>\n";
  html += "<script type=\"text/x-three\" id=\"view3d-controls\">" + script_safe(scripts.controls) + "\n</script>\n";
  html += "<script type=\"application/json\" id=\"view3d-data\">" + script_safe(data.dump()) + "</script>\n";
  html += std::string("<script>") + kViewerScript + "</script>\n</section>\n";
  return html;
}

}  // namespace vesselmesh::study
