// SPDX-License-Identifier: MIT
// Test helper: the expectations on a run over a sequence with image defects (image/defects.h),
// shared by the rendered and the EuRoC end-to-end tests.
#pragma once

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "dsm/io/dataset.h"
#include "dsm/run/run.h"

namespace dsm::testing {

// Timestamps (ns) of the poses of a TUM file.
std::set<int64_t> TumStamps(const std::filesystem::path& file);

struct DefectRange {
  int first = 0, last = 0;
  bool cover = false;  // A hand over the lens: it slides in and out over two frames.
};

// Googletest expectations on the run `s` of `dataset`, written to `out`: one map; one lost episode
// per defect, each relocalised, beginning at its first frame and ending within 5 frames of its
// last; no defect frame in frames.tum or keyframes.tum, and every frame after the last episode in
// frames.tum. A cover hides a quarter of the view on its first and last frame (which may be tracked
// and make keyframes, as behind a near occluder) and half on the next ones (which may be tracked).
// `name` labels the failures.
void ExpectDefectsCostTheirFramesOnly(const Dataset& dataset, const RunSummary& s, const std::filesystem::path& out,
                                      const std::vector<DefectRange>& defects, const std::string& name);

}  // namespace dsm::testing
