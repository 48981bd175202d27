#include "flow/case.h"

#include "io/atomic_file.h"
#include "io/toml_reader.h"
#include "io/units.h"
#include "mesh/error.h"
#include "post/wss.h"

#include <Eigen/SparseCholesky>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

namespace vesselmesh::flow {

Waveform::Waveform(std::vector<double> times, std::vector<double> values)
    : times_(std::move(times)), values_(std::move(values)) {
  VM_CHECK(times_.size() == values_.size() && !times_.empty(), "waveform samples");
  const int n = static_cast<int>(times_.size()) - 1;  // intervals
  double largest = 0.0;
  for (double v : values_) largest = std::max(largest, std::abs(v));
  if (n < 2 || std::abs(values_.back() - values_.front()) > 1e-9 * largest) return;
  // The periodic spline's second derivatives M_0 .. M_(n-1) (M_n = M_0): at each sample i,
  // h_(i-1)/6 M_(i-1) + (h_(i-1) + h_i)/3 M_i + h_i/6 M_(i+1) = slope_i - slope_(i-1), the indices
  // round the period (symmetric, positive definite).
  const auto h = [&](int i) { return times_[(i + n) % n + 1] - times_[(i + n) % n]; };
  const auto slope = [&](int i) { return (values_[(i + n) % n + 1] - values_[(i + n) % n]) / h(i); };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, (i + n - 1) % n, h(i - 1) / 6.0);
    entries.emplace_back(i, i, (h(i - 1) + h(i)) / 3.0);
    entries.emplace_back(i, (i + 1) % n, h(i) / 6.0);
    rhs[i] = slope(i) - slope(i - 1);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());  // (n = 2: a neighbour both sides, summed)
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factors(a);
  const Eigen::VectorXd m = factors.solve(rhs);
  curvature_.assign(m.data(), m.data() + n);
  curvature_.push_back(curvature_.front());
}

Waveform Waveform::constant(double value) { return Waveform({0.0}, {value}); }

Waveform Waveform::read_csv(const std::string& path) {
  const std::string text = io::read_file(path);
  std::istringstream in(text);
  std::string line;
  std::vector<double> times, values;
  int number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::replace(line.begin(), line.end(), ';', ' ');
    std::istringstream fields(line);
    double t = 0.0, q = 0.0;
    std::string rest;
    if (!(fields >> t >> q) || (fields >> rest)) {
      if (times.empty() && !header) {  // a header line before the first row
        header = true;
        continue;
      }
      throw InputError(fmt::format("{}:{}: expected two numbers (time in s, flow in mL/s), found \"{}\"",
                                   path, number, line));
    }
    if (!std::isfinite(t) || !std::isfinite(q))
      throw InputError(fmt::format("{}:{}: time and flow must be finite numbers", path, number));
    if (!times.empty() && t <= times.back())
      throw InputError(fmt::format("{}:{}: times must increase (time {} s follows {} s)", path, number, t,
                                   times.back()));
    times.push_back(t);
    values.push_back(q);
  }
  if (times.size() < 2)
    throw InputError(fmt::format("{}: a waveform needs at least two rows of time (s), flow (mL/s)", path));
  return Waveform(std::move(times), std::move(values));
}

double Waveform::operator()(double t) const {
  if (times_.size() == 1) return values_[0];
  const double t0 = times_.front(), span = period();
  double s = std::fmod(t - t0, span);
  if (s < 0.0) s += span;
  s += t0;
  const auto it = std::upper_bound(times_.begin(), times_.end(), s);
  const size_t j = std::clamp<size_t>(static_cast<size_t>(it - times_.begin()), 1, times_.size() - 1);
  const double h = times_[j] - times_[j - 1], w = (s - times_[j - 1]) / h;
  const double line = (1.0 - w) * values_[j - 1] + w * values_[j];
  if (curvature_.empty()) return line;
  // The cubic with second derivatives M_(j-1) and M_j at the interval's ends, through its samples.
  return line - h * h / 6.0 * w * (1.0 - w) * ((2.0 - w) * curvature_[j - 1] + (1.0 + w) * curvature_[j]);
}

Waveform Waveform::scaled(double factor) const {
  Waveform out = *this;
  for (double& v : out.values_) v *= factor;
  for (double& m : out.curvature_) m *= factor;
  return out;
}

std::string to_string(BoundaryType type) {
  switch (type) {
    case BoundaryType::velocity: return "velocity";
    case BoundaryType::traction: return "traction";
    case BoundaryType::resistance: return "resistance";
    case BoundaryType::rcr: return "rcr";
    case BoundaryType::wall: return "wall";
  }
  return "?";
}

namespace {

// One [[boundary]] table (`where` names it in messages; `seen`: the tags before it, this one added;
// `backflow`: the case's coefficient, set when the table gives it).
BoundaryCondition parse_boundary(const io::TomlReader& r, const toml::table* table, const std::string& where,
                                 const std::string& path, std::set<std::string>& seen, double& backflow) {
  r.known_keys(*table, where, {"tag", "type", "profile", "flow", "waveform", "scale", "resistance", "backflow",
                               "harmonics", "proximal_resistance", "distal_resistance", "capacitance",
                               "distal_pressure", "initial_pressure", "perturbation"});
  const io::TomlView b(table);
  BoundaryCondition bc;
  bc.tag = r.text(b["tag"], where + ".tag", "");
  if (bc.tag.empty()) r.fail(where + ".tag", "missing: the mesh tag this condition applies to");
  if (!seen.insert(bc.tag).second) r.fail(where + ".tag", fmt::format("tag \"{}\" has two conditions", bc.tag));
  const std::string type = r.text(b["type"], where + ".type", "");
  if (type == "velocity") bc.type = BoundaryType::velocity;
  else if (type == "traction") bc.type = BoundaryType::traction;
  else if (type == "resistance") bc.type = BoundaryType::resistance;
  else if (type == "rcr") bc.type = BoundaryType::rcr;
  else if (type == "wall") bc.type = BoundaryType::wall;
  else r.fail(where + ".type", fmt::format("\"{}\": expected velocity, traction, resistance, rcr or wall", type));

  const auto only_for = [&](const char* key, BoundaryType allowed) {
    if (b[key] && bc.type != allowed)
      r.fail(where + "." + key, fmt::format("not used by a {} boundary", to_string(bc.type)));
  };
  only_for("profile", BoundaryType::velocity);
  only_for("flow", BoundaryType::velocity);
  only_for("waveform", BoundaryType::velocity);
  only_for("scale", BoundaryType::velocity);
  only_for("resistance", BoundaryType::resistance);
  only_for("harmonics", BoundaryType::velocity);
  only_for("perturbation", BoundaryType::velocity);
  for (const char* key : {"proximal_resistance", "distal_resistance", "capacitance", "distal_pressure",
                          "initial_pressure"})
    only_for(key, BoundaryType::rcr);
  if (b["backflow"] && !is_natural(bc.type))
    r.fail(where + ".backflow", "only traction, resistance and rcr boundaries have backflow stabilization");

  if (bc.type == BoundaryType::velocity) {
    const std::string profile = r.text(b["profile"], where + ".profile", "parabolic");
    if (profile == "parabolic") bc.profile = Profile::parabolic;
    else if (profile == "plug") bc.profile = Profile::plug;
    else if (profile == "womersley") bc.profile = Profile::womersley;
    else r.fail(where + ".profile", fmt::format("\"{}\": expected parabolic, plug or womersley", profile));
    if (b["harmonics"] && bc.profile != Profile::womersley)
      r.fail(where + ".harmonics", "only a womersley profile has harmonics");
    bc.harmonics = r.integer(b["harmonics"], where + ".harmonics", bc.harmonics, 1);
    if (b["flow"] && b["waveform"]) r.fail(where, "give `flow` or `waveform`, not both");
    if (b["waveform"]) {
      bc.waveform_file = io::resolve_path(path, r.text(b["waveform"], where + ".waveform", ""));
      bc.flow = Waveform::read_csv(bc.waveform_file);
    } else if (b["flow"]) {
      bc.flow = Waveform::constant(r.number(b["flow"], where + ".flow", 0.0, false));
    } else {
      r.fail(where, "a velocity boundary needs `flow` (mL/s) or `waveform` (CSV: time s, flow mL/s)");
    }
    if (b["scale"]) bc.flow = bc.flow.scaled(r.number(b["scale"], where + ".scale", 1.0, false));
    bc.perturbation = r.number(b["perturbation"], where + ".perturbation", 0.0, false);
    if (bc.perturbation < 0.0 || bc.perturbation >= 1.0)
      r.fail(where + ".perturbation", fmt::format("{:g}: the inflow's fluctuation, each component's RMS over the local "
                                                  "speed, lies in [0, 1) (0.04: 4 %)",
                                                  bc.perturbation));
  }
  if (bc.type == BoundaryType::resistance) {
    if (!b["resistance"]) r.fail(where + ".resistance", "missing: the resistance in Pa s/m3");
    bc.resistance = r.number(b["resistance"], where + ".resistance", 0.0);
  }
  if (bc.type == BoundaryType::rcr) {
    for (const char* key : {"proximal_resistance", "distal_resistance", "capacitance"})
      if (!b[key])
        r.fail(where + "." + key, std::string("missing: an rcr boundary needs proximal_resistance and "
                                              "distal_resistance (Pa s/m3) and capacitance (m3/Pa)"));
    bc.proximal_resistance = r.number(b["proximal_resistance"], where + ".proximal_resistance", 0.0, false);
    if (bc.proximal_resistance < 0.0) r.fail(where + ".proximal_resistance", "must not be negative");
    bc.distal_resistance = r.number(b["distal_resistance"], where + ".distal_resistance", 0.0);
    bc.capacitance = r.number(b["capacitance"], where + ".capacitance", 0.0);
    bc.distal_pressure = r.number(b["distal_pressure"], where + ".distal_pressure", 0.0, false);
    if (b["initial_pressure"])
      bc.initial_pressure = r.number(b["initial_pressure"], where + ".initial_pressure", 0.0, false);
  }
  if (b["backflow"]) backflow = r.number(b["backflow"], where + ".backflow", 1.0, false);
  return bc;
}

}  // namespace

FlowCase parse_case(const std::string& text, const std::string& path) {
  const toml::table parsed = io::parse_toml(text, path);
  const toml::table& root = parsed;
  const io::TomlReader r{path};
  FlowCase c;
  c.path = path;
  r.known_keys(root, "", {"mesh", "length_unit", "fluid", "time", "boundary", "solver", "stabilization", "output"});

  const std::string mesh = r.text(root["mesh"], "mesh", "");
  if (mesh.empty()) r.fail("mesh", "missing: name the volume mesh (MSH 4.1 from `vesselmesh volume`)");
  c.mesh = io::resolve_path(path, mesh);
  c.length_unit = r.text(root["length_unit"], "length_unit", "mm");
  try {
    c.length_scale = io::millimetres_per(io::parse_unit(c.length_unit)) * 1e-3;
  } catch (const OptionError& e) {
    r.fail("length_unit", e.what());
  }

  const io::TomlView fluid = root["fluid"];
  if (fluid && !fluid.is_table()) r.fail("fluid", "expected a table [fluid]");
  if (fluid) r.known_keys(*fluid.as_table(), "fluid", {"density", "viscosity"});
  c.density = r.number(fluid["density"], "fluid.density", c.density);
  c.viscosity = r.number(fluid["viscosity"], "fluid.viscosity", c.viscosity);

  const io::TomlView time = root["time"];
  if (time && !time.is_table()) r.fail("time", "expected a table [time]");
  if (time)
    r.known_keys(*time.as_table(), "time",
                 {"steady", "dt", "end", "cycles", "period", "save_every", "picard", "steady_tolerance",
                  "steady_iterations", "steady_method", "initial", "cfl_target"});
  c.steady = r.flag(time["steady"], "time.steady", false);
  c.steady_tolerance = r.number(time["steady_tolerance"], "time.steady_tolerance", c.steady_tolerance);
  c.steady_iterations = r.integer(time["steady_iterations"], "time.steady_iterations", c.steady_iterations, 1);
  c.picard = r.integer(time["picard"], "time.picard", 0, 0);
  const std::string method = r.text(time["steady_method"], "time.steady_method", "newton");
  if (method != "picard" && method != "pseudo-transient" && method != "newton")
    r.fail("time.steady_method",
           fmt::format("\"{}\" is not a steady method: give \"picard\", \"pseudo-transient\" or \"newton\"", method));
  c.pseudo_transient = method == "pseudo-transient";
  c.newton = method == "newton";
  c.steady_method = method;
  const std::string initial = r.text(time["initial"], "time.initial", "rest");
  if (initial != "rest" && initial != "stokes")
    r.fail("time.initial", fmt::format("\"{}\" is not an initial state: give \"rest\" or \"stokes\"", initial));
  c.stokes_start = initial == "stokes";
  if (!c.steady) {
    if (!time["dt"]) r.fail("time.dt", "missing: an unsteady case needs the time step in s");
    c.dt = r.number(time["dt"], "time.dt", c.dt);
    if (time["end"] && time["cycles"]) r.fail("time", "give `end` or `cycles` (with `period`), not both");
    if (time["period"]) c.period = r.number(time["period"], "time.period", 1.0);
    if (time["cycles"]) {
      const double cycles = r.number(time["cycles"], "time.cycles", 1.0);
      if (!time["period"]) r.fail("time.period", "missing: `cycles` needs the period in s");
      c.end = cycles * c.period;
    } else {
      if (!time["end"]) r.fail("time.end", "missing: give the end time in s (or cycles and period)");
      c.end = r.number(time["end"], "time.end", c.end);
    }
    c.save_every = r.integer(time["save_every"], "time.save_every", c.save_every, 1);
    c.cfl_target = r.number(time["cfl_target"], "time.cfl_target", 0.0);
    if (time["cfl_target"] && !(c.cfl_target > 0.0 && c.cfl_target <= 1000.0))
      r.fail("time.cfl_target", fmt::format("{:g} is not a CFL number to aim at: give one above 0 (up to 1000)",
                                            c.cfl_target));
  } else if (time && time["cfl_target"]) {
    r.fail("time.cfl_target", "a steady case has no time steps: leave it out, or set steady = false");
  }

  if (!root["boundary"] || !root["boundary"].is_array_of_tables())
    r.fail("boundary", "missing: one [[boundary]] table per tag of the mesh");
  std::set<std::string> seen;
  for (const auto& [where, table] : r.tables(root, "boundary")) {
    c.boundaries.push_back(parse_boundary(r, table, where, path, seen, c.backflow));
    if (c.steady && c.boundaries.back().perturbation > 0.0)
      r.fail(where + ".perturbation", "a steady case has no fluctuation in time: remove it, or run in time");
  }

  const io::TomlView solver = root["solver"];
  if (solver && !solver.is_table()) r.fail("solver", "expected a table [solver]");
  if (solver)
    r.known_keys(*solver.as_table(), "solver", {"petsc_options", "reuse_preconditioner", "kept_solutions", "threads"});
  c.petsc_options = r.text(solver["petsc_options"], "solver.petsc_options", "");
  c.reuse_preconditioner = r.flag(solver["reuse_preconditioner"], "solver.reuse_preconditioner", true);
  c.kept_solutions = r.integer(solver["kept_solutions"], "solver.kept_solutions", c.kept_solutions, 0);
  c.threads = r.integer(solver["threads"], "solver.threads", 0, 0);

  const io::TomlView stabilization = root["stabilization"];
  if (stabilization && !stabilization.is_table()) r.fail("stabilization", "expected a table [stabilization]");
  if (stabilization) r.known_keys(*stabilization.as_table(), "stabilization", {"tau_c_factor", "tau_m_time"});
  c.tau_c_factor = r.number(stabilization["tau_c_factor"], "stabilization.tau_c_factor", c.tau_c_factor, false);
  if (!(c.tau_c_factor >= 0.0 && c.tau_c_factor <= 100.0))
    r.fail("stabilization.tau_c_factor", "give a factor from 0 to 100 (1: tau_C as Bazilevs et al. 2007; 0: no LSIC)");
  c.tau_m_time = r.number(stabilization["tau_m_time"], "stabilization.tau_m_time", c.tau_m_time, false);
  if (!(c.tau_m_time >= 0.0 && c.tau_m_time <= 1e4))
    r.fail("stabilization.tau_m_time", "give C_t from 0 to 1e4 (tau_M's time term C_t / dt^2; 4 by default)");

  const io::TomlView output = root["output"];
  if (output && !output.is_table()) r.fail("output", "expected a table [output]");
  if (output)
    r.known_keys(*output.as_table(), "output", {"wss_method", "checkpoint_every", "fluid_every", "statistics_from"});
  c.checkpoint_every = r.integer(output["checkpoint_every"], "output.checkpoint_every", c.save_every, 0);
  c.fluid_every = r.integer(output["fluid_every"], "output.fluid_every", c.save_every, 0);
  if (c.fluid_every % c.save_every != 0)
    r.fail("output.fluid_every", fmt::format("{} is not a multiple of time.save_every ({}): the fluid is saved with "
                                             "the wall; give a multiple, or 0 for the last step only",
                                             c.fluid_every, c.save_every));
  if (output["statistics_from"]) {
    c.statistics_from = r.number(output["statistics_from"], "output.statistics_from", -1.0, false);
    if (c.steady) r.fail("output.statistics_from", "a steady case has no time statistics: remove it, or run in time");
    if (!(c.statistics_from >= 0.0 && c.statistics_from < c.end))
      r.fail("output.statistics_from", fmt::format("{:g} s: give the time (s, from 0 to before time.end, {:g} s) from "
                                                   "which to average the flow",
                                                   c.statistics_from, c.end));
  }
  c.wss_method = r.text(output["wss_method"], "output.wss_method", c.wss_method);
  try {
    post::parse_wss_method(c.wss_method);
  } catch (const InputError& e) {
    r.fail("output.wss_method", e.what());
  }
  return c;
}

FlowCase read_case(const std::string& path) { return parse_case(io::read_file(path), path); }

double next_time_step(double dt, double max_cfl, double target) {
  const double ratio = max_cfl > 0.0 ? target / max_cfl : kTimeStepGrowth;
  return dt * std::clamp(ratio, 1.0 / kTimeStepShrink, kTimeStepGrowth);
}

double landing_time_step(double dt, double time, double end) {
  const double left = end - time;
  if (left <= dt * (1.0 + 1e-9)) return left;
  return left < 2.0 * dt ? 0.5 * left : dt;
}

void divide_time_step(FlowCase& c, int divisor) {
  if (divisor < 1) throw OptionError(fmt::format("the time step's divisor must be at least 1 (found {})", divisor));
  if (c.steady) throw OptionError(fmt::format("{}: a steady case has no time step to divide", c.path));
  c.dt /= divisor;
  c.cfl_target /= divisor;
  c.save_every *= divisor;
  c.checkpoint_every *= divisor;
  c.fluid_every *= divisor;
}

void set_end(FlowCase& c, double end) {
  if (!(end > 0.0)) throw OptionError(fmt::format("the run's end must be a positive time in s (found {:g})", end));
  if (c.steady) throw OptionError(fmt::format("{}: a steady case has no end time to set", c.path));
  c.end = end;
}

void check_tags(const FlowCase& flow_case, const std::vector<std::string>& mesh_tags) {
  const std::set<std::string> in_mesh(mesh_tags.begin(), mesh_tags.end());
  std::set<std::string> in_case;
  for (const BoundaryCondition& b : flow_case.boundaries) in_case.insert(b.tag);
  const auto list = [](const std::set<std::string>& s) {
    std::string out;
    for (const std::string& t : s) out += (out.empty() ? "" : ", ") + t;
    return out;
  };
  for (const std::string& t : in_case)
    if (!in_mesh.count(t))
      throw InputError(fmt::format("{}: boundary tag \"{}\" is not in the mesh {} (its tags: {})", flow_case.path, t,
                                   flow_case.mesh, list(in_mesh)));
  for (const std::string& t : in_mesh)
    if (!in_case.count(t))
      throw InputError(fmt::format("{}: the mesh's boundary tag \"{}\" has no condition: add a [[boundary]] with "
                                   "tag = \"{}\" (the case names: {})",
                                   flow_case.path, t, t, list(in_case)));
  bool has_velocity = false;
  for (const BoundaryCondition& b : flow_case.boundaries) has_velocity |= b.type == BoundaryType::velocity;
  if (!has_velocity)
    throw InputError(fmt::format("{}: no velocity boundary: the flow needs at least one inlet with a flow", flow_case.path));
}

}  // namespace vesselmesh::flow
