// The study's report: DIR/report.md and DIR/report.html (the same content; the HTML has every
// picture inline as SVG, the Markdown links the PNGs), the figures in DIR/figures/ as SVG and
// PNG, and DIR/study.json with every number. Contents: Table 1 of the paper (surface
// triangles, nodes, volume nodes, tetrahedra per mesh), WSS along each ring for the refinement
// series and for the compared meshes (Fig. 11), bar charts of the relative differences of each
// ring's minimum WSS and of the WSS at each point against the reference (Figs. 12-14), pictures
// of the surface meshes and of the WSS field, the timings of every step, the version and the
// options.
#pragma once

#include "study/study.h"

namespace vesselmesh::study {

void write_report(const StudyConfig& config, StudyResult& result, const std::string& folder,
                  const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::study
