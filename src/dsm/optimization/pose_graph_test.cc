// SPDX-License-Identifier: MIT
#include "dsm/optimization/pose_graph.h"

#include <cmath>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// Keyframes on a circle, looking outwards; the odometry drifted in scale and heading, and a loop
// edge from the last back to the first says where it really is.
TEST(PoseGraph, ALoopEdgeSpreadsScaleAndHeadingDriftOverTheLoop) {
  constexpr int kN = 24;
  const auto pose_on_circle = [](double a) {  // cam_from_world.
    const SE3d world_from_cam(SO3d::Exp(Eigen::Vector3d(0, 0, a)), Eigen::Vector3d(5 * std::cos(a), 5 * std::sin(a), 0));
    return Sim3d(world_from_cam.Inverse());
  };
  std::vector<Sim3d> truth, drifted;
  for (int i = 0; i < kN; ++i) truth.push_back(pose_on_circle(2 * M_PI * i / kN));
  // Odometry: each step's translation shrinks by 1% and turns 0.3 degrees too far.
  drifted.push_back(truth[0]);
  for (int i = 1; i < kN; ++i) {
    Sim3d step = truth[i] * truth[i - 1].Inverse();
    step = Sim3d(1.0, SO3d::Exp(Eigen::Vector3d(0, 0.005, 0)) * step.So3(), 0.99 * step.Translation());
    drifted.push_back(Sim3d(step * drifted[i - 1]));
  }
  // Re-expressed as SE3 poses at the map's scale (scale 1 per node), as the map holds them.
  std::vector<Sim3d> start;
  for (const Sim3d& s : drifted) start.emplace_back(1.0, s.So3(), s.Translation());
  std::vector<PoseGraphEdge> edges;
  for (int i = 1; i < kN; ++i) edges.push_back({i, i - 1, start[i] * start[i - 1].Inverse(), 1.0});
  edges.push_back({kN - 1, 0, truth[kN - 1] * truth[0].Inverse(), 1.0});
  const auto position_error = [&](const std::vector<Sim3d>& poses, int i) {
    return (poses[i].Inverse().Translation() - truth[i].Inverse().Translation()).norm();
  };
  const double before = position_error(start, kN - 1);
  const PoseGraphResult r = OptimizePoseGraph(start, edges, {0});
  ASSERT_EQ(r.cam_from_world.size(), static_cast<size_t>(kN));
  EXPECT_LT(r.final_cost, 0.05 * r.initial_cost);
  // Node 0 is held.
  EXPECT_LT((r.cam_from_world[0].Translation() - start[0].Translation()).norm(), 1e-9);
  // The last keyframe comes back to where the loop edge puts it; every keyframe is nearer the truth.
  const double after = position_error(r.cam_from_world, kN - 1);
  EXPECT_GT(before, 0.3);
  EXPECT_LT(after, 0.1 * before);
  for (int i = 1; i < kN; ++i) EXPECT_LE(position_error(r.cam_from_world, i), position_error(start, i) + 1e-3) << i;
}

}  // namespace
}  // namespace dsm
