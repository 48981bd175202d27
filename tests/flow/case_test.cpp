#include "flow/case.h"

#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>


namespace vesselmesh::flow {
namespace {

// The issue's contract example, as users write it.
const char* kContract = R"(
mesh = "volume.msh"          # from `vesselmesh volume`
length_unit = "mm"
[fluid]
density = 1060.0
viscosity = 0.0035
[time]
steady = false
dt = 1e-3
end = 1.0
save_every = 10
[[boundary]]
tag = "inlet"
type = "velocity"
profile = "parabolic"
flow = 5.0
[[boundary]]
tag = "outlet_1"
type = "traction"
[[boundary]]
tag = "wall"
type = "wall"
[solver]
petsc_options = "-ksp_rtol 1e-8"
)";

TEST(FlowCase, ReadsTheContractKeys) {
  const FlowCase c = parse_case(kContract, "/cases/pipe/case.toml");
  EXPECT_EQ(c.mesh, "/cases/pipe/volume.msh");
  EXPECT_DOUBLE_EQ(c.length_scale, 1e-3);
  EXPECT_DOUBLE_EQ(c.density, 1060.0);
  EXPECT_DOUBLE_EQ(c.viscosity, 0.0035);
  EXPECT_FALSE(c.steady);
  EXPECT_DOUBLE_EQ(c.dt, 1e-3);
  EXPECT_DOUBLE_EQ(c.end, 1.0);
  EXPECT_EQ(c.save_every, 10);
  ASSERT_EQ(c.boundaries.size(), 3u);
  EXPECT_EQ(c.boundaries[0].type, BoundaryType::velocity);
  EXPECT_EQ(c.boundaries[0].profile, Profile::parabolic);
  EXPECT_DOUBLE_EQ(c.boundaries[0].flow(0.37), 5.0);
  EXPECT_EQ(c.boundaries[1].type, BoundaryType::traction);
  EXPECT_EQ(c.boundaries[2].type, BoundaryType::wall);
  EXPECT_EQ(c.petsc_options, "-ksp_rtol 1e-8");
  EXPECT_EQ(c.wss_method, "quadratic");
  EXPECT_TRUE(c.reuse_preconditioner);
  EXPECT_EQ(c.threads, 0);  // automatic
  EXPECT_NO_THROW(check_tags(c, {"wall", "inlet", "outlet_1"}));
}

// The study's time-step check: half the step, the same saved times.
TEST(FlowCase, TimeStepDividedSavesAtTheSameTimes) {
  FlowCase c = parse_case(kContract, "/cases/pipe/case.toml");
  divide_time_step(c, 2);
  EXPECT_DOUBLE_EQ(c.dt, 5e-4);
  EXPECT_EQ(c.save_every, 20);
  EXPECT_EQ(c.checkpoint_every, 20);
  EXPECT_EQ(c.fluid_every, 20);
  EXPECT_DOUBLE_EQ(c.end, 1.0);
  EXPECT_EQ(c.cfl_target, 0.0);  // none: still none
  c.cfl_target = 40.0;
  divide_time_step(c, 2);
  EXPECT_DOUBLE_EQ(c.cfl_target, 20.0);
  EXPECT_THROW(divide_time_step(c, 0), OptionError);
  c.steady = true;
  EXPECT_THROW(divide_time_step(c, 2), OptionError);
}

TEST(FlowCase, PreconditionerReuseCanBeTurnedOff) {
  std::string text = kContract;
  text += "reuse_preconditioner = false\n";
  EXPECT_FALSE(parse_case(text, "case.toml").reuse_preconditioner);
  text.replace(text.find("false"), 5, "\"no\"");
  EXPECT_THROW(parse_case(text, "case.toml"), InputError);
}

TEST(FlowCase, KeptSolutions) {
  EXPECT_EQ(parse_case(kContract, "case.toml").kept_solutions, 4);
  std::string text = kContract;
  text += "kept_solutions = 0\n";
  EXPECT_EQ(parse_case(text, "case.toml").kept_solutions, 0);
  text.replace(text.find("kept_solutions = 0"), 18, "kept_solutions = -1");
  EXPECT_THROW(parse_case(text, "case.toml"), InputError);
}

TEST(FlowCase, CyclesTimesPeriodAndOtherUnits) {
  std::string text = kContract;
  text.replace(text.find("end = 1.0"), 9, "cycles = 3\nperiod = 0.8");
  text.replace(text.find("\"mm\""), 4, "\"cm\"");
  const FlowCase c = parse_case(text, "case.toml");
  EXPECT_DOUBLE_EQ(c.end, 2.4);
  EXPECT_DOUBLE_EQ(c.length_scale, 1e-2);
}

// Each mistake is an InputError naming the file and the key.
void expect_error(const std::string& text, const std::string& part) {
  try {
    parse_case(text, "bad.toml");
    ADD_FAILURE() << "no error; expected one mentioning " << part;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.toml"), std::string::npos) << e.what();
  }
}

std::string with(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

// Newton's method the default (issue 49); Picard's and pseudo time steps by name.
TEST(FlowCase, SteadyMethodByName) {
  std::string text = kContract;
  EXPECT_FALSE(parse_case(text, "case.toml").pseudo_transient);
  EXPECT_TRUE(parse_case(text, "case.toml").newton);
  EXPECT_EQ(parse_case(text, "case.toml").steady_method, "newton");
  const std::string picard = with(text, "steady = false", "steady = true\nsteady_method = \"picard\"");
  EXPECT_FALSE(parse_case(picard, "case.toml").newton);
  EXPECT_FALSE(parse_case(picard, "case.toml").pseudo_transient);
  EXPECT_EQ(parse_case(picard, "case.toml").steady_method, "picard");
  text.replace(text.find("steady = false"), 14, "steady = true\nsteady_method = \"pseudo-transient\"");
  EXPECT_TRUE(parse_case(text, "case.toml").pseudo_transient);
  EXPECT_FALSE(parse_case(text, "case.toml").newton);
  text.replace(text.find("pseudo-transient"), 16, "newton");
  EXPECT_TRUE(parse_case(text, "case.toml").newton);
  EXPECT_FALSE(parse_case(text, "case.toml").pseudo_transient);
  text.replace(text.find("newton"), 6, "secant");
  expect_error(text, "time.steady_method");
}

TEST(FlowCase, MistakesAreNamed) {
  expect_error(with(kContract, "length_unit = \"mm\"", "length_unit = \"furlong\""), "length_unit");
  expect_error(with(kContract, "density = 1060.0", "density = -1.0"), "fluid.density");
  expect_error(with(kContract, "density = 1060.0", "densty = 1060.0"), "fluid.densty");
  expect_error(with(kContract, "type = \"traction\"", "type = \"outflow\""), "boundary[1].type");
  expect_error(with(kContract, "flow = 5.0", "flow = \"five\""), "boundary[0].flow");
  expect_error(with(kContract, "flow = 5.0", ""), "needs `flow`");
  expect_error(with(kContract, "dt = 1e-3", ""), "time.dt");
  expect_error(with(kContract, "tag = \"wall\"", "tag = \"inlet\""), "two conditions");
  expect_error(with(kContract, "save_every = 10", "save_every = 0"), "time.save_every");
  expect_error(with(kContract, "[fluid]", "[fluid"), "bad.toml:");
  expect_error(with(kContract, "mesh = \"volume.msh\"", ""), "mesh");
  expect_error(with(kContract, "profile = \"parabolic\"", "profile = \"poiseuille\""), "boundary[0].profile");
  expect_error(with(kContract, "flow = 5.0", "flow = 5.0\nharmonics = 4"), "only a womersley profile");
  expect_error(kContract + std::string("[output]\nwss_method = \"spr\"\n"), "output.wss_method");
  expect_error(kContract + std::string("[output]\nwss = \"face\"\n"), "output.wss");
  expect_error(with(kContract, "dt = 1e-3", "dt = 1e-3\ninitial = \"potential\""), "time.initial");
}

// Issue 48: [time] cfl_target, the steps' length chosen for a CFL number (off unless given); a
// value not above 0, too large, or on a steady case is named; the step's choice grows at most 1.25x,
// shrinks at most 4x, and the last steps land on the end, no longer than asked and without a sliver.
TEST(FlowCase, TimeStepsForACflTarget) {
  EXPECT_EQ(parse_case(kContract, "case.toml").cfl_target, 0.0);
  EXPECT_EQ(parse_case(with(kContract, "dt = 1e-3", "dt = 1e-3\ncfl_target = 20"), "case.toml").cfl_target, 20.0);
  expect_error(with(kContract, "dt = 1e-3", "dt = 1e-3\ncfl_target = 0"), "time.cfl_target");
  expect_error(with(kContract, "dt = 1e-3", "dt = 1e-3\ncfl_target = 5000"), "time.cfl_target");
  expect_error(with(kContract, "steady = false", "steady = true\ncfl_target = 5"), "time.cfl_target");
  EXPECT_DOUBLE_EQ(next_time_step(0.01, 10.0, 20.0), 0.0125);  // at most 1.25x
  EXPECT_DOUBLE_EQ(next_time_step(0.01, 0.0, 20.0), 0.0125);   // at rest
  EXPECT_DOUBLE_EQ(next_time_step(0.01, 40.0, 20.0), 0.005);   // twice the target: half
  EXPECT_DOUBLE_EQ(next_time_step(0.01, 400.0, 20.0), 0.0025);  // at most 4x shorter
  EXPECT_DOUBLE_EQ(next_time_step(0.01, 21.0, 21.0), 0.01);
  EXPECT_DOUBLE_EQ(landing_time_step(0.01, 0.5, 1.0), 0.01);
  EXPECT_DOUBLE_EQ(landing_time_step(0.01, 0.985, 1.0), 0.5 * (1.0 - 0.985));  // 1.5 dt left: two halves
  EXPECT_DOUBLE_EQ(landing_time_step(0.01, 0.99, 1.0), 1.0 - 0.99);  // dt left: all of it
  EXPECT_DOUBLE_EQ(landing_time_step(0.01, 0.996, 1.0), 1.0 - 0.996);
}

// An rcr end (issue 32): its keys read, its initial pressure the distal one unless given, and
// each mistake named: a missing or negative value, a key of another type.
TEST(FlowCase, RcrEndsReadTheirCircuit) {
  const std::string rcr = with(kContract, "type = \"traction\"",
                               "type = \"rcr\"\nproximal_resistance = 1e7\ndistal_resistance = 1.2e8\n"
                               "capacitance = 1e-9\ndistal_pressure = 1000.0");
  const FlowCase c = parse_case(rcr, "case.toml");
  const BoundaryCondition& b = c.boundaries[1];
  EXPECT_EQ(b.type, BoundaryType::rcr);
  EXPECT_EQ(to_string(b.type), "rcr");
  EXPECT_TRUE(is_natural(b.type));
  EXPECT_DOUBLE_EQ(b.proximal_resistance, 1e7);
  EXPECT_DOUBLE_EQ(b.distal_resistance, 1.2e8);
  EXPECT_DOUBLE_EQ(b.capacitance, 1e-9);
  EXPECT_DOUBLE_EQ(b.distal_pressure, 1000.0);
  EXPECT_FALSE(b.initial_pressure.has_value());
  EXPECT_DOUBLE_EQ(*parse_case(with(rcr, "distal_pressure = 1000.0", "initial_pressure = 9000.0"), "case.toml")
                        .boundaries[1]
                        .initial_pressure,
                   9000.0);
  expect_error(with(rcr, "capacitance = 1e-9", ""), "boundary[1].capacitance");
  expect_error(with(rcr, "capacitance = 1e-9", "capacitance = -1e-9"), "boundary[1].capacitance");
  expect_error(with(rcr, "proximal_resistance = 1e7", "proximal_resistance = -1e7"),
               "boundary[1].proximal_resistance");
  expect_error(with(rcr, "distal_resistance = 1.2e8", "distal_resistance = 0.0"), "boundary[1].distal_resistance");
  expect_error(with(kContract, "flow = 5.0", "flow = 5.0\ncapacitance = 1e-9"), "boundary[0].capacitance");
  EXPECT_NO_THROW(parse_case(with(rcr, "capacitance = 1e-9", "capacitance = 1e-9\nbackflow = 0.5"), "case.toml"));
}

TEST(FlowCase, InitialStateAtRestOrStokes) {
  EXPECT_FALSE(parse_case(kContract, "case.toml").stokes_start);
  EXPECT_TRUE(parse_case(with(kContract, "dt = 1e-3", "dt = 1e-3\ninitial = \"stokes\""), "case.toml").stokes_start);
  EXPECT_FALSE(parse_case(with(kContract, "dt = 1e-3", "dt = 1e-3\ninitial = \"rest\""), "case.toml").stokes_start);
}

TEST(FlowCase, WallShearMethodByName) {
  EXPECT_EQ(parse_case(kContract + std::string("[output]\nwss_method = \"face\"\n"), "case.toml").wss_method, "face");
}

TEST(FlowCase, CheckpointsEverySaveUnlessToldOtherwise) {
  EXPECT_EQ(parse_case(kContract, "case.toml").checkpoint_every, 10);  // the case's save_every
  EXPECT_EQ(parse_case(with(kContract, "save_every = 10", "save_every = 7"), "case.toml").checkpoint_every, 7);
  EXPECT_EQ(parse_case(kContract + std::string("[output]\ncheckpoint_every = 0\n"), "case.toml").checkpoint_every, 0);
  EXPECT_EQ(parse_case(kContract + std::string("[output]\ncheckpoint_every = 50\n"), "case.toml").checkpoint_every, 50);
  expect_error(kContract + std::string("[output]\ncheckpoint_every = -1\n"), "output.checkpoint_every");
  EXPECT_EQ(parse_case(kContract, "case.toml").fluid_every, 10);  // the case's save_every
  EXPECT_EQ(parse_case(kContract + std::string("[output]\nfluid_every = 0\n"), "case.toml").fluid_every, 0);
  EXPECT_EQ(parse_case(kContract + std::string("[output]\nfluid_every = 40\n"), "case.toml").fluid_every, 40);
  expect_error(kContract + std::string("[output]\nfluid_every = 15\n"), "not a multiple of time.save_every");
  expect_error(kContract + std::string("[output]\nfluid_every = -2\n"), "output.fluid_every");
}

// Issue 47: [boundary] perturbation, the inflow's disturbance (none unless asked), on velocity
// boundaries of unsteady cases only, a fraction in [0, 1).
TEST(FlowCase, PerturbationOfAnInflow) {
  EXPECT_EQ(parse_case(kContract, "case.toml").boundaries[0].perturbation, 0.0);
  EXPECT_DOUBLE_EQ(
      parse_case(with(kContract, "flow = 5.0", "flow = 5.0\nperturbation = 0.04"), "case.toml")
          .boundaries[0]
          .perturbation,
      0.04);
  expect_error(with(kContract, "flow = 5.0", "flow = 5.0\nperturbation = 1.5"),
               "boundary[0].perturbation");
  expect_error(with(kContract, "flow = 5.0", "flow = 5.0\nperturbation = -0.1"), "lies in [0, 1)");
  expect_error(with(kContract, "type = \"wall\"", "type = \"wall\"\nperturbation = 0.04"),
               "not used by a wall boundary");
  expect_error(with(with(kContract, "steady = false", "steady = true"), "flow = 5.0",
                    "flow = 5.0\nperturbation = 0.04"),
               "a steady case has no fluctuation in time");
}

TEST(FlowCase, StabilizationFactors) {
  const FlowCase plain = parse_case(kContract, "case.toml");
  EXPECT_EQ(plain.tau_c_factor, 1.0);  // Bazilevs et al.'s tau_C and tau_M unless asked
  EXPECT_EQ(plain.tau_m_time, 4.0);
  const FlowCase c =
      parse_case(kContract + std::string("[stabilization]\ntau_c_factor = 0.25\ntau_m_time = 0\n"), "case.toml");
  EXPECT_DOUBLE_EQ(c.tau_c_factor, 0.25);
  EXPECT_DOUBLE_EQ(c.tau_m_time, 0.0);
  expect_error(kContract + std::string("[stabilization]\ntau_c_factor = -1\n"), "stabilization.tau_c_factor");
  expect_error(kContract + std::string("[stabilization]\ntau_m_time = -4\n"), "stabilization.tau_m_time");
  expect_error(kContract + std::string("[stabilization]\ntau_c = 1\n"), "tau_c");
  expect_error(std::string("stabilization = 1\n") + kContract, "expected a table [stabilization]");
}

TEST(FlowCase, StatisticsFromATimeBeforeTheEnd) {
  EXPECT_LT(parse_case(kContract, "case.toml").statistics_from, 0.0);  // none unless asked
  const auto from = [](const std::string& value) {
    const std::string text = std::string(kContract) + "[output]\nstatistics_from = " + value + "\n";
    return parse_case(text, "case.toml").statistics_from;
  };
  EXPECT_DOUBLE_EQ(from("0.5"), 0.5);
  EXPECT_DOUBLE_EQ(from("0"), 0.0);
  expect_error(kContract + std::string("[output]\nstatistics_from = -0.1\n"), "output.statistics_from");
  expect_error(kContract + std::string("[output]\nstatistics_from = 1.0\n"), "before time.end, 1 s");
  expect_error(with(kContract, "steady = false", "steady = true") + "[output]\nstatistics_from = 0.1\n",
               "a steady case has no time statistics");
}

TEST(FlowCase, TagsMustMatchTheMesh) {
  const FlowCase c = parse_case(kContract, "case.toml");
  try {
    check_tags(c, {"wall", "inlet"});
    ADD_FAILURE() << "outlet_1 is not in the mesh";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"outlet_1\" is not in the mesh"), std::string::npos) << e.what();
  }
  try {
    check_tags(c, {"wall", "inlet", "outlet_1", "outlet_2"});
    ADD_FAILURE() << "outlet_2 has no condition";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"outlet_2\" has no condition"), std::string::npos) << e.what();
  }
}

// Samples that close their period: the periodic cubic spline through them, its slope continuous
// at every sample and round the period; a sinusoid from 20 samples within 1e-3 of its amplitude
// (straight lines between them: 1.2 %).
TEST(Waveform, ASplineThroughSamplesThatCloseThePeriod) {
  const Waveform w({0.0, 0.2, 1.0}, {1.0, 3.0, 1.0});
  EXPECT_TRUE(w.smooth());
  EXPECT_DOUBLE_EQ(w.period(), 1.0);
  for (double t : {0.0, 1.0, -1.0, 3.0}) EXPECT_NEAR(w(t), 1.0, 1e-12) << t;
  for (double t : {0.2, 1.2, -0.8}) EXPECT_NEAR(w(t), 3.0, 1e-12) << t;
  EXPECT_NEAR(w(0.1), w(1.1), 1e-12);
  EXPECT_NEAR(w(0.6), w(-0.4), 1e-12);
  EXPECT_GT(std::abs(w(0.05) - 1.5), 0.01);  // a curve, not the line (1.5 there)
  const double e = 1e-6;
  for (double t : {0.0, 0.2, 1.0}) {
    const double left = (w(t) - w(t - e)) / e, right = (w(t + e) - w(t)) / e;
    EXPECT_NEAR(left, right, 1e-4 * (1.0 + std::abs(left))) << "slope at t = " << t;
  }
  std::vector<double> t, q;
  for (int k = 0; k <= 20; ++k) {
    t.push_back(0.8 * k / 20.0);
    q.push_back(2.0 + std::sin(2.0 * M_PI * k / 20.0));
  }
  q.back() = q.front();
  const Waveform sine(t, q);
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double s = 0.8 * (k + 0.5) / 1000.0;
    worst = std::max(worst, std::abs(sine(s) - (2.0 + std::sin(2.0 * M_PI * s / 0.8))));
  }
  EXPECT_LT(worst, 1e-3);
}

// Samples whose last value is not their first: straight lines between them, as the period's end
// jumps anyway.
TEST(Waveform, LinesBetweenSamplesThatDoNotCloseThePeriod) {
  const Waveform w({0.0, 0.2, 1.0}, {1.0, 3.0, 2.0});
  EXPECT_FALSE(w.smooth());
  EXPECT_DOUBLE_EQ(w(0.1), 2.0);
  EXPECT_DOUBLE_EQ(w(0.6), 2.5);
  EXPECT_DOUBLE_EQ(w(1.1), 2.0);
  EXPECT_DOUBLE_EQ(w(-0.9), 2.0);
  EXPECT_DOUBLE_EQ(w(3.2), 3.0);
}

TEST(FlowCase, ScaleMultipliesTheFlowOfAVelocityBoundary) {
  std::string text = kContract;
  text.replace(text.find("flow = 5.0"), 10, "flow = 5.0\nscale = -0.5");
  EXPECT_DOUBLE_EQ(parse_case(text, "/c/case.toml").boundaries[0].flow(0.3), -2.5);
  std::string wall = kContract;
  wall.replace(wall.find("type = \"wall\""), 13, "type = \"wall\"\nscale = 2.0");
  EXPECT_THROW(parse_case(wall, "/c/case.toml"), InputError);
  const Waveform given({0.0, 0.2, 1.0}, {1.0, 3.0, 1.0}), w = given.scaled(-2.0);
  EXPECT_DOUBLE_EQ(w(0.1), -2.0 * given(0.1));
  EXPECT_DOUBLE_EQ(w(0.2), -6.0);
  EXPECT_DOUBLE_EQ(w.period(), 1.0);
}

TEST(Waveform, ReadsCsvAndNamesTheBadLine) {
  const test::TemporaryFolder folder;
  const std::string good = folder.path("good.csv"), bad = folder.path("bad.csv");
  test::write_bytes(good, "time_s,flow_ml_s\n# a comment\n0.0, 2.0\n0.5, 4.0\r\n1.0, 2.0\n");
  test::write_bytes(bad, "0.0, 2.0\n0.5, four\n");
  const Waveform w = Waveform::read_csv(good);
  EXPECT_EQ(w.samples(), 3);
  EXPECT_DOUBLE_EQ(w(0.25), 3.0);
  try {
    Waveform::read_csv(bad);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:2"), std::string::npos) << e.what();
  }
  std::string text = kContract;
  text.replace(text.find("flow = 5.0"), 10, "waveform = \"good.csv\"");
  const FlowCase c = parse_case(text, folder.path("case.toml"));
  EXPECT_DOUBLE_EQ(c.boundaries[0].flow(1.25), 3.0);
}

TEST(FlowCase, AssemblyThreads) {
  EXPECT_EQ(parse_case(std::string(kContract) + "threads = 3\n", "case.toml").threads, 3);
  expect_error(std::string(kContract) + "threads = -1\n", "solver.threads");
  expect_error(std::string(kContract) + "threads = \"all\"\n", "solver.threads");
}

}  // namespace
}  // namespace vesselmesh::flow
