// vesselmesh windkessel: RCR outlet parameters from a target flow and pressure, shared among the
// outlets by Murray's law (flow/windkessel.h), printed and, with --case, written into a case.
#include "commands.h"

#include "flow/windkessel.h"
#include "io/atomic_file.h"
#include "io/toml_reader.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <filesystem>
#include <sstream>

namespace vesselmesh::cli {
namespace {

// The case at `path` with one rcr [[boundary]] per outlet (its other keys for that tag replaced), the
// rest as it was (comments are not kept: toml++ writes the tables anew), its files (mesh,
// waveforms) relative to `output`'s folder.
std::string case_with_outlets(const std::string& path, const std::string& output,
                              const std::vector<flow::OutletWindkessel>& outlets) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
  }
  namespace fs = std::filesystem;
  const fs::path folder = fs::absolute(fs::path(output)).parent_path().lexically_normal();
  const auto moved = [&](toml::node* node) {
    if (!node || !node->is_string()) return;
    const fs::path file = fs::absolute(io::resolve_path(path, node->as_string()->get())).lexically_normal();
    const fs::path relative = file.lexically_relative(folder);
    *node->as_string() = relative.empty() ? file.string() : relative.string();
  };
  moved(root.get("mesh"));
  toml::array* boundaries = root["boundary"].as_array();
  if (boundaries)
    for (auto& node : *boundaries)
      if (toml::table* b = node.as_table()) moved(b->get("waveform"));
  if (!boundaries) {
    root.insert("boundary", toml::array{});
    boundaries = root["boundary"].as_array();
  }
  for (const flow::OutletWindkessel& w : outlets) {
    toml::table rcr{{"tag", w.tag},
                    {"type", "rcr"},
                    {"proximal_resistance", w.proximal_resistance},
                    {"distal_resistance", w.distal_resistance},
                    {"capacitance", w.capacitance}};
    bool replaced = false;
    for (auto& node : *boundaries) {
      toml::table* b = node.as_table();
      if (b && b->get_as<std::string>("tag") && b->get_as<std::string>("tag")->get() == w.tag) {
        if (const auto* backflow = b->get("backflow")) rcr.insert("backflow", *backflow);
        *b = rcr;
        replaced = true;
      }
    }
    if (!replaced) boundaries->push_back(rcr);
  }
  std::ostringstream text;
  text << "# RCR outlets from 'vesselmesh windkessel' (Murray's law); resistances Pa s/m3, capacitances m3/Pa\n"
       << root << "\n";
  return text.str();
}

}  // namespace

Command add_windkessel_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "windkessel",
      "RCR (three-element Windkessel) outlet parameters from a target: the outlets' total resistance is the mean "
      "pressure (diastolic + a third of the pulse) over the mean inflow, shared so that each outlet's flow follows "
      "its radius to --murray-exponent (3: Murray's law; 2: by area), split into proximal (--proximal-fraction) and "
      "distal parts; the total compliance (--capacitance-total, or the one of --time-constant) shared as the flow. "
      "The outlets are the surface's open ends but the inlet (the largest unless --inlet), named outlet_1, ... as "
      "'vesselmesh volume' names them. Prints them; --case CASE -o OUT writes CASE with an rcr boundary per outlet");
  struct Options {
    SurfaceInput surface;
    double inflow = 0.0;
    std::string pressure;
    flow::WindkesselTarget target;
    double capacitance = 0.0;
    int inlet = -1;
    std::string case_file, output;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("--inflow", o->target.inflow, "Mean inflow, mL/s")->required();
  app->add_option("--pressure", o->pressure, "Target pressure SYSTOLIC/DIASTOLIC in mmHg, e.g. 120/80")->required();
  app->add_option("--murray-exponent", o->target.murray_exponent, "Flow share as radius^n (3: Murray; 2: area)")
      ->capture_default_str();
  app->add_option("--proximal-fraction", o->target.proximal_fraction,
                  "Proximal share of each outlet's resistance")
      ->capture_default_str();
  app->add_option("--capacitance-total", o->capacitance, "Total compliance, m3/Pa (default: from --time-constant)");
  app->add_option("--time-constant", o->target.time_constant,
                  "R_total x C_total in s, for the compliance when --capacitance-total is not given")
      ->capture_default_str();
  app->add_option("--inlet", o->inlet, "Index of the inlet among the ends, as 'vesselmesh info' lists them");
  app->add_option("--case", o->case_file, "A simulate case to write the outlets into (with -o)")
      ->check(CLI::ExistingFile);
  app->add_option("-o,--output", o->output, "The case written (with --case)");
  add_common_options(*app, o->common);
  return {app, [o] {
            if (o->case_file.empty() != o->output.empty())
              throw OptionError("--case and -o go together: the case to complete and where to write it");
            flow::WindkesselTarget target = o->target;
            const size_t slash = o->pressure.find('/');
            try {
              if (slash == std::string::npos) throw std::invalid_argument("no slash");
              target.systolic = std::stod(o->pressure.substr(0, slash));
              target.diastolic = std::stod(o->pressure.substr(slash + 1));
            } catch (const std::exception&) {
              throw OptionError(fmt::format("--pressure \"{}\": give SYSTOLIC/DIASTOLIC in mmHg, e.g. 120/80",
                                            o->pressure));
            }
            if (o->capacitance != 0.0) target.total_capacitance = o->capacitance;
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            const int ends = static_cast<int>(surface.ends.size());
            if (o->inlet >= ends)
              throw OptionError(fmt::format("--inlet {}: the surface has {} ends (0 to {})", o->inlet, ends, ends - 1));
            const int inlet = o->inlet >= 0 ? o->inlet : 0;  // ends come largest first
            std::vector<std::pair<std::string, double>> outlets;
            int k = 0;
            for (int e = 0; e < ends; ++e)
              if (e != inlet) outlets.emplace_back(fmt::format("outlet_{}", ++k), surface.ends[e].radius * 1e-3);
            const std::vector<flow::OutletWindkessel> result = flow::murray_windkessel(outlets, target);
            reporter.info(fmt::format("mean pressure {:.1f} Pa ({:.1f} mmHg) over {:g} mL/s: total resistance {:.4g} Pa "
                                      "s/m3",
                                      flow::mean_pressure(target), flow::mean_pressure(target) / 133.322,
                                      target.inflow, flow::mean_pressure(target) / (target.inflow * 1e-6)));
            for (const flow::OutletWindkessel& w : result)
              reporter.info(fmt::format("{}: radius {:.3f} mm, {:.1f} % of the flow, proximal_resistance {:.4g}, "
                                        "distal_resistance {:.4g} Pa s/m3, capacitance {:.4g} m3/Pa",
                                        w.tag, w.radius * 1e3, 100.0 * w.flow_fraction, w.proximal_resistance,
                                        w.distal_resistance, w.capacitance));
            if (!o->case_file.empty()) {
              io::write_text(o->output, case_with_outlets(o->case_file, o->output, result));
              reporter.info(fmt::format("{}: the case with rcr outlets", o->output));
            }
            if (o->common.json) {
              Json list = Json::array();
              for (const flow::OutletWindkessel& w : result)
                list.push_back({{"tag", w.tag},
                                {"radius_mm", w.radius * 1e3},
                                {"flow_fraction", w.flow_fraction},
                                {"proximal_resistance", w.proximal_resistance},
                                {"distal_resistance", w.distal_resistance},
                                {"capacitance", w.capacitance}});
              print_json(Json{{"mean_pressure_Pa", flow::mean_pressure(target)},
                              {"units", {{"resistance", "Pa s/m3"}, {"capacitance", "m3/Pa"}}},
                              {"outlets", list}});
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
