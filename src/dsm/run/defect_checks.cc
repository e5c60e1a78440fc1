// SPDX-License-Identifier: MIT
#include "dsm/run/defect_checks.h"

#include <algorithm>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "dsm/io/trajectory_io.h"
#include "dsm/tracking/tracking_quality.h"

namespace dsm::testing {

std::set<int64_t> TumStamps(const std::filesystem::path& file) {
  const Trajectory t = ReadTrajectory(file, TrajectoryFormat::kTum);
  return {t.stamps_ns.begin(), t.stamps_ns.end()};
}

namespace {

// Whether the frame of timestamp t is in `stamps` (within 1 ms: TUM files store seconds).
bool Holds(const std::set<int64_t>& stamps, int64_t t) {
  const auto it = stamps.lower_bound(t - 1000000);
  return it != stamps.end() && *it <= t + 1000000;
}

}  // namespace

void ExpectDefectsCostTheirFramesOnly(const Dataset& dataset, const RunSummary& s, const std::filesystem::path& out,
                                      const std::vector<DefectRange>& defects, const std::string& name) {
  EXPECT_EQ(s.stats["maps"].size(), 1u) << name;
  EXPECT_EQ(s.stats["relocalisations"].get<size_t>(), defects.size()) << name;
  const auto episodes = s.stats["lost_episodes"].get<std::vector<std::pair<int, int>>>();
  ASSERT_EQ(episodes.size(), defects.size()) << name;
  const std::set<int64_t> tracked = TumStamps(out / "frames.tum"), keyframes = TumStamps(out / "keyframes.tum");
  for (size_t e = 0; e < defects.size(); ++e) {
    const DefectRange& d = defects[e];
    const int edge = d.cover ? 2 : 0;
    EXPECT_GE(episodes[e].first, d.first) << name;
    EXPECT_LE(episodes[e].first, d.first + edge) << name;
    EXPECT_GE(episodes[e].second, d.last - edge) << name;
    EXPECT_LE(episodes[e].second, d.last + 5) << name;
    for (int i = d.first; i <= d.last; ++i) {
      const int into = std::min(i - d.first, d.last - i);
      if (into >= edge) {
        EXPECT_FALSE(Holds(tracked, dataset.frames[i].t_ns)) << name << " frame " << i;
      }
      if (into >= edge / 2) {
        EXPECT_FALSE(Holds(keyframes, dataset.frames[i].t_ns)) << name << " frame " << i;
      }
    }
  }
  // Each relocalisation's evidence: the frame after its episode, the frames lost since the last
  // trusted one, an alignment that passed the quality test.
  const nlohmann::json& relocalised = s.stats["relocalised"];
  ASSERT_EQ(relocalised.size(), defects.size()) << name;
  for (size_t e = 0; e < defects.size(); ++e) {
    const nlohmann::json& r = relocalised[e];
    EXPECT_EQ(r["frame"].get<int>(), episodes[e].second + 1) << name;
    EXPECT_GE(r["frames_lost"].get<int>(), episodes[e].second - episodes[e].first + 2) << name;
    EXPECT_GE(r["inlier_ratio"].get<double>(), QualityOptions::min_inlier_ratio) << name;
    EXPECT_LE(r["inlier_ratio"].get<double>(), 1.0) << name;
    const double level = r["inlier_level"].get<double>();  // 0: fewer trusted frames than the level needs.
    EXPECT_TRUE(level == 0.0 || (level >= QualityOptions::min_inlier_ratio && level <= 1.0)) << name << " " << level;
    EXPECT_GT(r["residual_ratio"].get<double>(), 0.0) << name;
    EXPECT_LE(r["residual_ratio"].get<double>(), QualityOptions::max_relocalisation_residual_ratio) << name;
  }
  for (int i = episodes.back().second + 1; i < static_cast<int>(dataset.size()); ++i)
    EXPECT_TRUE(Holds(tracked, dataset.frames[i].t_ns)) << name << " frame " << i;
}

}  // namespace dsm::testing
