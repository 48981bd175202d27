#include "io/conformance.h"

#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::io {
namespace {

// The header's fluid: the FDA's blood analogue (1056 kg/m3, 0.0035 Pa s) at the flow rate given.
void expect_fda_fluid(const ConformanceFile& file, double flow) {
  EXPECT_DOUBLE_EQ(file.flow, flow);
  EXPECT_DOUBLE_EQ(file.density, 1056.0);
  EXPECT_DOUBLE_EQ(file.viscosity, 0.0035);
}

// A section read as it should be: its keyword, parameters and rows (position, value) in order.
void expect_section(const ConformanceSection& s, const std::string& keyword, const std::vector<double>& parameters,
                    const std::vector<std::pair<double, double>>& rows) {
  EXPECT_EQ(s.keyword, keyword);
  ASSERT_EQ(s.parameters.size(), parameters.size()) << keyword;
  for (size_t i = 0; i < parameters.size(); ++i) EXPECT_DOUBLE_EQ(s.parameters[i], parameters[i]) << keyword;
  ASSERT_EQ(s.rows.size(), rows.size()) << keyword;
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_DOUBLE_EQ(s.rows[i].first, rows[i].first) << keyword << " row " << i;
    EXPECT_DOUBLE_EQ(s.rows[i].second, rows[i].second) << keyword << " row " << i;
  }
}

// The one-line error reading `text` as a file gives (test::input_error).
std::string read_error(const test::TemporaryFolder& folder, const std::string& text) {
  return test::input_error(folder.path("bad.txt"), text, [](const std::string& f) { read_conformance(f); });
}

// A file as the FDA writes them: the header's fluid, a withdrawn section left out, a section
// with parameters, rows kept in the file's order (tabs and trailing blanks as theirs).
TEST(Conformance, ReadsTheHeadersFluidAndEveryPlotSection) {
  test::TemporaryFolder folder;
  const std::string path = folder.path("lab.txt");
  test::write_bytes(path,
                    "dataset-comment \"a lab\"\n"
                    "fluid-density 1056  \n"
                    "fluid-viscosity 0.0035  \n"
                    "fluid-volumetric-flow-rate 5.20624E-006  \n"
                    "deleted-plot-wall-distribution-pressure\n"
                    "2\n"
                    "-0.09 353.0\n"
                    "0.0 1.0\n"
                    "plot-z-distribution-axial-velocity   \n"
                    " 2\n"
                    "0.016\t 7.0E-001 \n"
                    "-0.088\t 8.7E-002 \n"
                    "plot-profile-axial-velocity-at-z -0.02000 0\n"
                    "1\n"
                    "-1.0E-003  6.5E-001\n");
  const ConformanceFile file = read_conformance(path);
  expect_fda_fluid(file, 5.20624e-6);
  ASSERT_EQ(file.sections.size(), 2u);  // the deleted- section's rows are not taken for sections either
  expect_section(file.sections[0], "plot-z-distribution-axial-velocity", {}, {{0.016, 0.7}, {-0.088, 0.087}});
  expect_section(file.sections[1], "plot-profile-axial-velocity-at-z", {-0.02, 0.0}, {{-1e-3, 0.65}});
}

// What is wrong, where: a row that is not two numbers (its line), a missing count, a section cut
// short, a file that is not there; another format gives no sections.
TEST(Conformance, BadFilesSayWhereAndWhat) {
  test::TemporaryFolder folder;
  const auto error = [&](const std::string& text) { return read_error(folder, text); };
  EXPECT_NE(error("plot-z-distribution-pressure\n2\n0.0 1.0\n0.1 x\n")
                .find("bad.txt:4: row 2 of section "
                      "plot-z-distribution-pressure"),
            std::string::npos);
  EXPECT_NE(error("plot-z-distribution-pressure\nmany\n")
                .find("bad.txt:2: section plot-z-distribution-pressure has "
                      "no row count"),
            std::string::npos);
  EXPECT_NE(error("plot-z-distribution-pressure\n3\n0.0 1.0\n").find("ends after 1 of its 3 rows"), std::string::npos);
  EXPECT_THROW(read_conformance(folder.path("absent.txt")), InputError);
  test::write_bytes(folder.path("other.txt"), "dataset-comment\tLDV Data\tfluid-volumetric-flow-rate\t2.08E-05\n");
  EXPECT_TRUE(read_conformance(folder.path("other.txt")).sections.empty());
}

// The LDV files' format (the Re 2000 case's): tabs and carriage returns, blank fields, sections
// `<what>-at-z=` with their station and count, read as plot-profile-<what>-at-z sections; a row
// cut short and a count that is not one say which section and field.
TEST(Conformance, ReadsTheLdvFilesTabbedFormat) {
  test::TemporaryFolder folder;
  const std::string path = folder.path("ldv.txt");
  test::write_bytes(
      path,
      "dataset-comment\tLDV Data - FDA Nozzle Model\t\rfluid-density\t1056\t\r"
      "fluid-viscosity\t0.0035\rfluid-volumetric-flow-rate\t2.08E-05\t\r"
      "axial-velocity-at-z=\t-0.088\t2\t\t-6.00E-03\t0.0000E+00\t1.99E-17\t3.6135E-01\t\r"
      "axial-velocity-stdev-at-z=\t0.06\t1\t\t0.0\t5.785E-01\t\r");
  const ConformanceFile file = read_conformance(path);
  expect_fda_fluid(file, 2.08e-5);
  ASSERT_EQ(file.sections.size(), 2u);
  expect_section(file.sections[0], "plot-profile-axial-velocity-at-z", {-0.088}, {{-6e-3, 0.0}, {1.99e-17, 0.36135}});
  expect_section(file.sections[1], "plot-profile-axial-velocity-stdev-at-z", {0.06}, {{0.0, 0.5785}});

  const auto error = [&](const std::string& text) { return read_error(folder, text); };
  EXPECT_NE(error("axial-velocity-at-z=\t0.0\t2\t0.0\t1.0\t0.001\r")
                .find("the file ends where row 2 of section axial-velocity-at-z= at z = 0"),
            std::string::npos);
  EXPECT_NE(error("axial-velocity-at-z=\t0.0\t2\t0.0\tx\r").find("field 5 ('x'), row 1 of section"),
            std::string::npos);
  EXPECT_NE(
      error("axial-velocity-at-z=\t0.0\t1.5\t0.0\t1.0\r").find("row count 1.5 is not a count"),
      std::string::npos);
}

// The FDA nozzle's laminar case as published (one laboratory's file out of the zip): its flow rate
// gives Re_throat = 500, its centerline and profiles are there, and lab 468's wall shear stress.
TEST(Conformance, ReadsTheFdaNozzlesLaminarMeasurements) {
  VESSELMESH_REQUIRE_SHARED(zip, "reference/fda_nozzle/SE_exp_0500.zip");
  test::TemporaryFolder folder;
  const std::string path = folder.path("468.txt");
  const std::string command = "unzip -p '" + zip + "' experiment/PIV_Sudden_Expansion_500_468.txt > '" + path + "'";
  if (std::system(command.c_str()) != 0) GTEST_SKIP() << "unzip could not extract the laboratory's file";
  const ConformanceFile file = read_conformance(path);
  const double throat_velocity = file.flow / (3.141592653589793 * 4e-6);
  EXPECT_NEAR(file.density * throat_velocity * 4e-3 / file.viscosity, 500.0, 1.0);
  int profiles = 0;
  bool centerline = false, wall_shear = false;
  for (const ConformanceSection& s : file.sections) {
    profiles += s.keyword == "plot-profile-axial-velocity-at-z";
    if (s.keyword == "plot-z-distribution-axial-velocity") {
      centerline = true;
      for (const auto& [z, u] : s.rows) EXPECT_TRUE(z > -0.1 && z < 0.1 && u > 0.0 && u < 1.0) << z << " " << u;
    }
    wall_shear = wall_shear || (s.keyword == "plot-wall-distribution-wall-shear-stress" && s.rows.size() == 18u);
  }
  EXPECT_EQ(profiles, 9);
  EXPECT_TRUE(centerline);
  EXPECT_TRUE(wall_shear);
}

// The transitional case's LDV file as published (lab 297): Re_throat = 2000, twelve stations of
// the axial velocity and its standard deviation, the jet steady and quiet at the expansion and
// broken down at z = 60 mm (its fluctuation a quarter of the throat's mean velocity or more).
TEST(Conformance, ReadsTheFdaNozzlesTransitionalLdvMeasurements) {
  VESSELMESH_REQUIRE_SHARED(zip, "reference/fda_nozzle/SE_exp_2000.zip");
  test::TemporaryFolder folder;
  const std::string path = folder.path("297.txt");
  const std::string command =
      "unzip -p '" + zip + "' experiment/LDV_Sudden_Expansion_2000_297.txt > '" + path + "'";
  if (std::system(command.c_str()) != 0)
    GTEST_SKIP() << "unzip could not extract the laboratory's file";
  const ConformanceFile file = read_conformance(path);
  const double throat_velocity = file.flow / (3.141592653589793 * 4e-6);
  EXPECT_NEAR(file.density * throat_velocity * 4e-3 / file.viscosity, 2000.0, 10.0);
  std::map<std::string, int> stations;
  for (const ConformanceSection& s : file.sections) {
    ++stations[s.keyword];
    ASSERT_FALSE(s.parameters.empty());
    if (s.keyword != "plot-profile-axial-velocity-stdev-at-z") continue;
    const auto axis = std::min_element(
        s.rows.begin(), s.rows.end(),
        [](const auto& a, const auto& b) { return std::abs(a.first) < std::abs(b.first); });
    ASSERT_NE(axis, s.rows.end());
    if (std::abs(s.parameters[0]) < 1e-9) {
      EXPECT_LT(axis->second, 0.1 * throat_velocity);
    }
    if (std::abs(s.parameters[0] - 0.06) < 1e-9) {
      EXPECT_GT(axis->second, 0.25 * throat_velocity);
    }
  }
  EXPECT_EQ(stations["plot-profile-axial-velocity-at-z"], 12);
  EXPECT_EQ(stations["plot-profile-axial-velocity-stdev-at-z"], 12);
}

}  // namespace
}  // namespace vesselmesh::io
