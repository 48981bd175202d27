// The FDA's "conformance" text files (the benchmark nozzle's and blood pump's measurements, data
// set doi:10.17917/C78G69): header lines `keyword value...` (dataset-..., geometry-..., fluid-...),
// then sections, each a line `plot-<what> [parameters...]` (a profile's station, for example
// `plot-profile-axial-velocity-at-z -0.02 0`), a line with the row count, and that many rows
// `position value`. Sections the data's authors withdrew are named `deleted-plot-...`.
// The LDV files of the Re 2000 case are another format (fields separated by tabs and carriage
// returns, sections `<what>-at-z=`, the station, the count, the rows), read into the same: each
// section named `plot-profile-<what>-at-z` with the station as its first parameter, for example
// `plot-profile-axial-velocity-stdev-at-z` (the standard deviation of the axial velocity).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::io {

struct ConformanceSection {
  std::string keyword;                          // plot-...
  std::vector<double> parameters;               // the keyword line's numbers after it
  std::vector<std::pair<double, double>> rows;  // (position, value) in the file's order
};

struct ConformanceFile {
  double flow = 0.0;  // fluid-volumetric-flow-rate (m^3/s), 0 when the header has none
  double density = 0.0,
         viscosity = 0.0;                    // fluid-density (kg/m^3), fluid-viscosity (Pa s); 0 when absent
  std::vector<ConformanceSection> sections;  // the plot- sections, in the file's order
};

// Reads one file. InputError naming the file, the section and the row when a section's count line
// or a row is not numbers, or the file ends before a section's last row (the LDV format: the
// field's number); an unreadable file too. A file with no plot- section gives no sections.
ConformanceFile read_conformance(const std::string& path);

}  // namespace vesselmesh::io
