// SPDX-License-Identifier: MIT
#include "dsm/report/report.h"

#include <fstream>

#include <gtest/gtest.h>

#include "dsm/io/ply.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int64_t kT0 = 1'000'000'000'000LL;  // 1000 s.

// A run folder as dsm run writes it: 3 keyframes, 4 frames, 2 points, ground truth at a scale of 2
// (metres per map unit) with frame 2 off by 0.01 map units.
fs::path FakeRun(const std::string& name) {
  const fs::path dir = testing::ScratchDir(name);
  Trajectory keyframes, frames, gt;
  for (int i = 0; i < 4; ++i) {
    const SE3d pose(SO3d(), Eigen::Vector3d(0.1 * i, 0, 0));
    frames.Add(kT0 + i * 50'000'000LL, pose);
    if (i != 1) keyframes.Add(kT0 + i * 50'000'000LL, pose);
    gt.Add(kT0 + i * 50'000'000LL, SE3d(SO3d(), pose.Translation() + Eigen::Vector3d(0, i == 2 ? 0.01 : 0, 0)));
  }
  WriteTumTrajectory(dir / "keyframes.tum", keyframes);
  WriteTumTrajectory(dir / "frames.tum", frames);
  WriteTumTrajectory(dir / "groundtruth_in_map.tum", gt);
  PlyCloud points;
  points.xyz = {{1.f, 2.f, 3.f}, {-1.f, 0.5f, 4.f}};
  points.rgb = {{{7, 7, 7}}, {{200, 200, 200}}};
  WritePly(dir / "map.ply", points);
  std::ofstream(dir / "eval.json") << json{{"keyframes", {{"ape", {{"rmse", 0.0042}}}, {"scale", 2.0}}},
                                           {"frames", {{"ape", {{"rmse", 0.005}}}, {"scale", 2.0}}}}.dump();
  const json stats = {
      {"dataset", "/data/room_walk"}, {"frames", 4}, {"frames_tracked", 4}, {"keyframes", 3}, {"map_points", 2},
      {"mode", "dsm"}, {"pace", "sequential"}, {"lost_episodes", json::array()},
      {"camera", {{"width", 320}, {"height", 240}, {"fx", 200.0}, {"fy", 200.0}, {"cx", 160.0}, {"cy", 120.0}}},
      {"per_frame", {{"frame", {0, 1, 2, 3}}, {"tracking_ms", {0.5, 3.0, 2.5, 2.0}}}},
      {"per_keyframe", {{{"frame", 0}, {"points_created", 2}, {"reobservations", 0}, {"covisible", json::array()},
                         {"pba", {{"ms", 0.0}}}},
                        {{"frame", 2}, {"points_created", 0}, {"reobservations", 1}, {"covisible", json::array()},
                         {"pba", {{"ms", 12.5}}}},
                        {{"frame", 3}, {"points_created", 0}, {"reobservations", 2}, {"covisible", {0}},
                         {"pba", {{"ms", 20.0}}}}}},
      {"loops_closed", {{{"frame", 3}, {"keyframe", 2}, {"candidate_keyframe", 0}, {"translation_share", 0.01},
                         {"rotation_deg", 0.5}, {"scale", 1.02}}}},
      {"maps", {{{"dir", "."}, {"keyframes", 3}}}}};
  std::ofstream(dir / "stats.json") << stats.dump();
  return dir;
}

TEST(Report, DataFromTheRunFolder) {
  const json d = ReportData(FakeRun("report_data"));
  EXPECT_EQ(d["title"], "room_walk");
  EXPECT_EQ(d["summary"]["keyframes"], 3);
  EXPECT_NEAR(d["summary"]["keyframe_ate_mm"].get<double>(), 4.2, 1e-9);
  ASSERT_EQ(d["maps"].size(), 1u);
  const json& m = d["maps"][0];
  EXPECT_EQ(m["points"]["count"], 2);
  // 2 points x 3 floats = 24 bytes: 32 base64 characters; 2 grey bytes: "B8g=" (7, 200).
  EXPECT_EQ(m["points"]["xyz"].get<std::string>().size(), 32u);
  EXPECT_EQ(m["points"]["xyz"].get<std::string>().substr(0, 8), "AACAPwAA");  // 1.0f = 00 00 80 3f.
  EXPECT_EQ(m["points"]["grey"], "B8g=");
  ASSERT_EQ(m["keyframes"].size(), 3u);
  EXPECT_EQ(m["keyframes"][1]["frame"], 2);
  EXPECT_NEAR(m["keyframes"][2]["t"].get<double>(), 0.15, 1e-12);
  EXPECT_NEAR(m["keyframes"][2]["p"][0].get<double>(), 0.3, 1e-9);
  EXPECT_EQ(m["keyframes"][2]["q"][3], 1.0);
  EXPECT_EQ(m["covisibility"], json({{2, 0}}));
  EXPECT_EQ(m["groundtruth"].size(), 4u);
  ASSERT_EQ(d["errors"].size(), 1u);
  const json& e = d["errors"][0]["error_mm"];
  ASSERT_EQ(e.size(), 4u);
  EXPECT_NEAR(e[0].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(e[2].get<double>(), 20.0, 1e-6);  // 0.01 map units x 2 m per unit.
  EXPECT_EQ(d["per_keyframe"]["pba_ms"], json({0.0, 12.5, 20.0}));
  EXPECT_EQ(d["per_frame"]["tracking_ms"].size(), 4u);
  ASSERT_EQ(d["loops_closed"].size(), 1u);
  EXPECT_EQ(d["loops_closed"][0]["candidate_keyframe"], 0);
}

// A map merged into another (system/atlas.h) has no folder: it is left out of the maps drawn, and
// its keyframe rows (listed after the map's own) are not given to the map before it.
TEST(Report, AMergedMapIsDrawnWithTheMapThatTookItIn) {
  const fs::path dir = FakeRun("report_merged");
  json stats = json::parse(std::ifstream(dir / "stats.json"));
  stats["maps"] = {{{"dir", "."}, {"keyframes", 2}}, {{"dir", nullptr}, {"merged_into", 0}, {"keyframes", 1}}};
  stats["maps_merged"] = {{{"frame", 3}, {"keyframe", 2}, {"candidate_keyframe", 1}, {"map", 1}}};
  std::ofstream(dir / "stats.json") << stats.dump();
  const json d = ReportData(dir);
  ASSERT_EQ(d["maps"].size(), 1u);
  EXPECT_EQ(d["maps"][0]["keyframes"].size(), 3u);  // From keyframes.tum: both maps' keyframes.
  ASSERT_EQ(d["maps_merged"].size(), 1u);
  EXPECT_EQ(d["maps_merged"][0]["map"], 1);
}

TEST(Report, PageInlinesDataAndScriptSafely) {
  json data = ReportData(FakeRun("report_page"));
  data["title"] = "a </script> <b>title</b>";
  const std::string page = ReportPage(data);
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("<title>dsm report: a &lt;/script&gt; &lt;b&gt;title&lt;/b&gt;</title>"), std::string::npos);
  // Exactly the two script elements end: the data and the bundled script.
  size_t ends = 0;
  for (size_t at = 0; (at = page.find("</script>", at)) != std::string::npos; ++at) ++ends;
  EXPECT_EQ(ends, 2u);
  EXPECT_NE(page.find("a <\\/script> <b>title<\\/b>"), std::string::npos);
  EXPECT_NE(page.find("WebGLRenderer"), std::string::npos);  // three.js is in the page.
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);     // Nothing loaded from the network.
  EXPECT_NE(page.find("data-live=\"0\""), std::string::npos);
  EXPECT_NE(ReportPage(data, true).find("data-live=\"1\""), std::string::npos);
}

// A run whose map never started (or was interrupted before it did) writes empty trajectories.
TEST(Report, RunWithoutAMap) {
  const fs::path dir = testing::ScratchDir("report_no_map");
  WriteTumTrajectory(dir / "keyframes.tum", Trajectory{});
  WriteTumTrajectory(dir / "frames.tum", Trajectory{});
  std::ofstream(dir / "stats.json") << json{{"frames", 3}, {"keyframes", 0}, {"maps", {{{"dir", "."}}}}}.dump();
  const json d = ReportData(dir);
  ASSERT_EQ(d["maps"].size(), 1u);
  EXPECT_TRUE(d["maps"][0]["keyframes"].empty());
  EXPECT_EQ(d["maps"][0]["points"]["count"], 0);
  EXPECT_TRUE(d["errors"].empty());
  EXPECT_NO_THROW(ReportPage(d));
}

TEST(Report, MissingOutputsAreNamed) {
  const fs::path dir = testing::ScratchDir("report_missing");
  try {
    ReportData(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "stats.json").string()), std::string::npos) << e.what();
  }
  std::ofstream(dir / "stats.json") << "{\"maps\": [{\"dir\": \".\"}]}";
  try {
    ReportData(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("keyframes.tum"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "stats.json") << "{not json";
  EXPECT_THROW(ReportData(dir), InputError);
}

}  // namespace
}  // namespace dsm
