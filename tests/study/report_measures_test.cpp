// The reference's temporal error in the study's report (issue 46): the time step's and the
// start-up's parts of a quantity, their sum, the verdict they can overturn, and the quantities whose
// start-up's share exceeds the spatial uncertainty.
#include "study/report_document.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::study::report {
namespace {

TEST(ReportMeasures, TemporalErrorRanksItsPartsAndTheirSum) {
  Ranked rank{"point A", {}, 2.0, "2.00 %", {}, false};
  TemporalError{0.03, 0.01}.rank_into(rank, 2.0);  // Pa, of a reference value of 2 Pa
  EXPECT_DOUBLE_EQ(rank.time_band, 1.5);
  EXPECT_DOUBLE_EQ(rank.start_band, 0.5);
  EXPECT_DOUBLE_EQ(rank.temporal_band(), 2.0);
  EXPECT_EQ(rank.uncertainty, "2.00 % (time step: 1.50 %, start-up: 0.50 %)");
  EXPECT_DOUBLE_EQ((TemporalError{0.03, 0.01}.total()), 0.04);

  // One part measured: the other left out of the cell and the sum.
  Ranked only_time{"point B", {}, NAN, "not estimated", {}, false};
  TemporalError{0.02, NAN}.rank_into(only_time, 1.0);
  EXPECT_EQ(only_time.uncertainty, "not estimated (time step: 2.00 %)");
  EXPECT_DOUBLE_EQ(only_time.temporal_band(), 2.0);
  EXPECT_DOUBLE_EQ((TemporalError{NAN, 0.02}.total()), 0.02);
  // Neither: nothing added, no band.
  Ranked none{"point C", {}, NAN, "n/a", {}, false};
  TemporalError{}.rank_into(none, 1.0);
  EXPECT_EQ(none.uncertainty, "n/a");
  EXPECT_TRUE(std::isnan(none.temporal_band()));
  EXPECT_TRUE(std::isnan(TemporalError{}.total()));
}

TEST(ReportMeasures, ADifferenceWithinTheTemporalErrorIsNotCalledLarger) {
  EXPECT_EQ(timed_verdict("larger", 0.03, 0.04), "within the temporal error (time step, start-up)");
  EXPECT_EQ(timed_verdict("larger", -0.05, 0.04), "larger");
  EXPECT_EQ(timed_verdict("larger", 0.03, NAN), "larger");
  EXPECT_EQ(timed_verdict("within", 0.03, 0.04), "within");
}

TEST(ReportMeasures, TheStartUpsShareAboveTheSpatialBandIsNamed) {
  std::vector<Ranked> ranked(3);
  ranked[0].quantity = "whole wall: OSI L2";
  ranked[0].band = 2.36;
  ranked[0].start_band = 2.17;  // within
  ranked[1].quantity = "whole wall: OSI 95th percentile";
  ranked[1].band = 4.49;
  ranked[1].start_band = 6.09;  // beyond
  ranked[2].quantity = "point A";
  ranked[2].start_band = 9.0;  // the spatial band not known: not told
  const std::vector<std::string> named = unsettled_quantities(ranked);
  ASSERT_EQ(named.size(), 1u);
  EXPECT_EQ(named[0], "whole wall: OSI 95th percentile (start-up 6.09 % against 4.49 %)");
}

}  // namespace
}  // namespace vesselmesh::study::report
