#include "io/conformance.h"

#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace vesselmesh::io {
namespace {

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
  EXPECT_DOUBLE_EQ(file.flow, 5.20624e-6);
  EXPECT_DOUBLE_EQ(file.density, 1056.0);
  EXPECT_DOUBLE_EQ(file.viscosity, 0.0035);
  ASSERT_EQ(file.sections.size(),
            2u);  // the deleted- section's rows are not taken for sections either
  EXPECT_EQ(file.sections[0].keyword, "plot-z-distribution-axial-velocity");
  EXPECT_TRUE(file.sections[0].parameters.empty());
  ASSERT_EQ(file.sections[0].rows.size(), 2u);
  EXPECT_DOUBLE_EQ(file.sections[0].rows[0].first, 0.016);
  EXPECT_DOUBLE_EQ(file.sections[0].rows[1].second, 0.087);
  EXPECT_EQ(file.sections[1].keyword, "plot-profile-axial-velocity-at-z");
  ASSERT_EQ(file.sections[1].parameters.size(), 2u);
  EXPECT_DOUBLE_EQ(file.sections[1].parameters[0], -0.02);
  ASSERT_EQ(file.sections[1].rows.size(), 1u);
  EXPECT_DOUBLE_EQ(file.sections[1].rows[0].second, 0.65);
}

// What is wrong, where: a row that is not two numbers (its line), a missing count, a section cut
// short, a file that is not there; another format gives no sections.
TEST(Conformance, BadFilesSayWhereAndWhat) {
  test::TemporaryFolder folder;
  const auto error = [&](const std::string& text) {
    return test::input_error(folder.path("bad.txt"), text, [](const std::string& f) { read_conformance(f); });
  };
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

}  // namespace
}  // namespace vesselmesh::io
