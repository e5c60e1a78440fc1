// SPDX-License-Identifier: MIT
// The PBA recovers perturbed keyframe poses and point depths of rendered frames.
#include "dsm/optimization/pba.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "dsm/optimization/pba_problem.h"
#include "dsm/optimization/pba_selection.h"
#include "dsm/optimization/pba_world.h"
#include "dsm/synth/renderer.h"
#include "dsm/testing/motion_error.h"

namespace dsm {
namespace {

using testing::BuildWorld;
using testing::Perturb;
using testing::World;

double RotationErrorDeg(const SE3d& a, const SE3d& b) { return testing::RotationErrorDeg(a.So3(), b.So3()); }

TEST(Pba, RecoversPerturbedPosesAndDepths) {
  World w;
  BuildWorld({0, 6, 12, 18}, &w);
  ASSERT_GT(w.map.NumPoints(), 500);
  Perturb(&w);

  PbaOptions options;
  const PbaSummary s = RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, options);
  EXPECT_LT(s.final_energy, s.initial_energy);
  EXPECT_EQ(s.fixed_keyframes, 1);
  // Keyframe 0 is the gauge: it did not move.
  EXPECT_EQ(w.map.keyframe(0).cam_from_world.Matrix(), w.true_cam_from_world[0].Matrix());
  // Monocular scale is free: compare translations after the scale of keyframe 1.
  const auto centre = [](const SE3d& cam_from_world) { return cam_from_world.Inverse().Translation(); };
  const Eigen::Vector3d c0 = centre(w.true_cam_from_world[0]);
  const double scale = (centre(w.true_cam_from_world[1]) - c0).norm() /
                       (centre(w.map.keyframe(1).cam_from_world) - c0).norm();
  for (int k = 1; k < w.map.NumKeyframes(); ++k) {
    const Eigen::Vector3d est = c0 + scale * (centre(w.map.keyframe(k).cam_from_world) - c0);
    EXPECT_LT((est - centre(w.true_cam_from_world[k])).norm(), 2e-3) << "keyframe " << k;
    EXPECT_LT(RotationErrorDeg(w.map.keyframe(k).cam_from_world, w.true_cam_from_world[k]), 0.05) << "keyframe " << k;
    // The brightness did not change: the fitted transfer to keyframe 0 is the identity over the
    // used range (a and b are correlated, so they are checked through their effect).
    const AffineBrightness& a = w.map.keyframe(k).affine;
    for (double intensity : {30.0, 120.0, 220.0}) {
      EXPECT_NEAR(std::exp(-a.a) * (intensity - a.b), intensity, 2.0) << "keyframe " << k;
    }
  }
  std::printf("pba: %d iterations, %.1f ms, %d points, %d observations\n", s.iterations, s.time_ms, s.points,
              s.observations);
}

// An adjustment stopped between iterations (PbaYield) and taken up again where it stopped, part
// after part, ends where one run through ends.
TEST(Pba, AnAdjustmentTakenUpWhereItStoppedEndsWhereAWholeOneDoes) {
  World whole, parts;
  BuildWorld({0, 6, 12, 18}, &whole);
  BuildWorld({0, 6, 12, 18}, &parts);
  Perturb(&whole);
  Perturb(&parts);
  ASSERT_EQ(whole.map.keyframe(2).cam_from_world.Matrix(), parts.map.keyframe(2).cam_from_world.Matrix());
  const PbaOptions options;
  const PbaSummary one = RunPba(&whole.map, whole.seq.camera, {0, 1, 2, 3}, options);
  ASSERT_FALSE(one.yielded);

  int asked = 0;
  PbaYield yield;
  yield.now = [&asked] { return ++asked % 3 == 0; };  // Stops after every third iteration.
  PbaSummary s = RunPba(&parts.map, parts.seq.camera, {0, 1, 2, 3}, options, {}, yield);
  ASSERT_TRUE(s.yielded);
  EXPECT_EQ(s.iterations, 3);
  EXPECT_EQ(s.level, options.levels - 1);
  EXPECT_EQ(s.level_iterations, 3);
  EXPECT_EQ(s.observations_removed, 0);  // Left to the part that ends it.
  int pieces = 1;
  while (s.yielded && pieces < 50) {
    yield.level = s.level;
    yield.iterations = s.level_iterations;
    s = RunPba(&parts.map, parts.seq.camera, {0, 1, 2, 3}, options, {}, yield);
    ++pieces;
  }
  EXPECT_FALSE(s.yielded);
  EXPECT_GE(pieces, 3);
  for (int k = 1; k < 4; ++k) {
    const SE3d& a = whole.map.keyframe(k).cam_from_world;
    const SE3d& b = parts.map.keyframe(k).cam_from_world;
    std::printf("keyframe %d: %d parts, centres %.2e m apart, %.2e deg; %.2e deg from the truth\n", k, pieces,
                (a.Inverse().Translation() - b.Inverse().Translation()).norm(), RotationErrorDeg(a, b),
                RotationErrorDeg(b, parts.true_cam_from_world[k]));
    EXPECT_LT((a.Inverse().Translation() - b.Inverse().Translation()).norm(), 5e-4) << "keyframe " << k;
    EXPECT_LT(RotationErrorDeg(a, b), 0.01) << "keyframe " << k;
    EXPECT_LT(RotationErrorDeg(b, parts.true_cam_from_world[k]), 0.05) << "keyframe " << k;
  }
}

TEST(Pba, HeldKeyframesKeepTheirPosesWhileTheirPointsMove) {
  World w;
  BuildWorld({0, 6, 12, 18}, &w);
  Perturb(&w);
  const SE3d held_pose = w.map.keyframe(1).cam_from_world;
  std::vector<float> depths_before;
  for (int pid : w.map.keyframe(1).points) depths_before.push_back(w.map.point(pid).idepth);
  const PbaSummary s = RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, PbaOptions{}, {1});
  EXPECT_EQ(s.fixed_keyframes, 2);
  EXPECT_EQ(w.map.keyframe(1).cam_from_world.Matrix(), held_pose.Matrix());
  int moved = 0;
  for (size_t i = 0; i < depths_before.size(); ++i)
    moved += w.map.point(w.map.keyframe(1).points[i]).idepth != depths_before[i];
  EXPECT_GT(moved, 0.9 * depths_before.size());
  EXPECT_LT(s.final_energy, s.initial_energy);
}

// Localisation in a loaded map: the frozen keyframes (0-2, where the true poses and depths put
// them) are the reference the free one (3, moved ~1 cm) is adjusted onto; nothing of them changes:
// poses, brightness, error models, depths and their observations' outlier state.
TEST(Pba, FrozenKeyframesAndTheirPointsStayWhileTheOthersAreAdjusted) {
  World w;
  BuildWorld({0, 6, 12, 18}, &w);
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.008, -0.006, 0.005, 0.004, -0.003, 0.002;
  w.map.keyframe(3).cam_from_world = SE3d::Exp(xi) * w.true_cam_from_world[3];
  ErrorModel frozen_model;
  frozen_model.sigma = 5.0;
  frozen_model.fitted = true;
  for (int k = 0; k < 3; ++k) {
    w.map.keyframe(k).frozen = true;
    w.map.keyframe(k).error_model = frozen_model;
  }
  w.map.point(0).observations[0].outlier = true;  // In a frozen keyframe: stays an outlier ...
  Point& flagged = w.map.point(1);
  const int frozen_target = flagged.observations[1].target;
  ASSERT_TRUE(w.map.keyframe(frozen_target).frozen);
  std::vector<float> depths;
  for (int i = 0; i < w.map.NumPoints(); ++i) depths.push_back(w.map.point(i).idepth);

  const PbaSummary s = RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, PbaOptions{}, {});
  EXPECT_EQ(s.fixed_keyframes, 3);
  EXPECT_LT(s.final_energy, s.initial_energy);
  for (int k = 0; k < 3; ++k) {
    const Keyframe& kf = w.map.keyframe(k);
    EXPECT_EQ(kf.cam_from_world.Matrix(), w.true_cam_from_world[k].Matrix()) << "keyframe " << k;
    EXPECT_EQ(kf.affine.a, 0.0);
    EXPECT_EQ(kf.affine.b, 0.0);
    EXPECT_EQ(kf.error_model.sigma, 5.0) << "keyframe " << k;
  }
  for (int i = 0; i < w.map.NumPoints(); ++i) ASSERT_EQ(w.map.point(i).idepth, depths[i]) << "point " << i;
  EXPECT_TRUE(w.map.point(0).observations[0].outlier);
  EXPECT_FALSE(flagged.observations[1].outlier);
  // Only the observations in keyframe 3 are in the problem (the rest join fixed values alone).
  int in_free = 0;
  for (int i = 0; i < w.map.NumPoints(); ++i) in_free += w.map.point(i).FindObservation(3) != nullptr;
  EXPECT_EQ(s.observations, in_free);
  // Keyframe 3 is back where it was rendered, in the frozen keyframes' frame and scale.
  const SE3d& k3 = w.map.keyframe(3).cam_from_world;
  EXPECT_LT((k3.Inverse().Translation() - w.true_cam_from_world[3].Inverse().Translation()).norm(), 1e-3);
  EXPECT_LT(RotationErrorDeg(k3, w.true_cam_from_world[3]), 0.03);
  EXPECT_NE(w.map.keyframe(3).error_model.sigma, ErrorModel{}.sigma);  // The free keyframe's model is fitted.
}

TEST(Pba, OnlyTheNewestModelIsRefittedWhenAsked) {
  World w;
  BuildWorld({0, 6, 12, 18}, &w);
  Perturb(&w);
  ErrorModel old_model;
  old_model.sigma = 4.0;
  old_model.fitted = true;
  for (int k = 0; k < 3; ++k) w.map.keyframe(k).error_model = old_model;
  PbaOptions options;
  options.refit_all_models = false;
  RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, options);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(w.map.keyframe(k).error_model.sigma, 4.0) << "keyframe " << k;
  EXPECT_TRUE(w.map.keyframe(3).error_model.fitted);
  EXPECT_NE(w.map.keyframe(3).error_model.sigma, ErrorModel{}.sigma);
  // By default every keyframe observed in the problem gets a model fitted to its residuals.
  World all;
  BuildWorld({0, 6, 12, 18}, &all);
  Perturb(&all);
  for (int k = 0; k < 3; ++k) all.map.keyframe(k).error_model = old_model;
  RunPba(&all.map, all.seq.camera, {0, 1, 2, 3}, PbaOptions{});
  EXPECT_NE(all.map.keyframe(1).error_model.sigma, 4.0);
}

// A plain surface covering the left half of the newest keyframe's view (a near textureless
// occluder): the points behind it lose their texture there, and those observations are removed
// after the adjustment; where the view is uncovered they stay. With the test off (the PBA's default)
// none counts.
TEST(Pba, ObservationsThatLostTheirTextureAreRemoved) {
  const auto run = [](const TextureLossOptions& texture_loss, World* w) {
    BuildWorld({0, 6, 12, 18}, w);
    Image<float> covered = synth::RenderSequenceFrame(w->seq, 18, synth::FormationOptions{}).image;
    for (int y = 0; y < covered.height(); ++y)
      for (int x = 0; x < covered.width() / 2; ++x) covered(x, y) = 128.f;
    w->map.keyframe(3).pyramid = std::make_shared<const ImagePyramid>(covered, 4);
    PbaOptions options;
    options.texture_loss = texture_loss;
    return RunPba(&w->map, w->seq.camera, {0, 1, 2, 3}, options);
  };
  World w;
  TextureLossOptions on;
  on.max_variance_ratio = kTextureLossRatio;
  const PbaSummary s = run(on, &w);
  int behind = 0, behind_removed = 0, beside = 0, beside_removed = 0;
  for (int i = 0; i < w.map.NumPoints(); ++i) {
    const Point& p = w.map.point(i);
    // Where the point lies in keyframe 3, at the true poses and depth.
    const Eigen::Vector3d in_host = w.seq.camera.Unproject(p.pixel.x(), p.pixel.y()) / p.idepth;
    const Eigen::Vector3d x = w.true_cam_from_world[3] * (w.true_cam_from_world[p.host].Inverse() * in_host);
    const double u = w.seq.camera.Project(x).x();
    const Observation* o = nullptr;
    for (const Observation& ob : p.observations)
      if (ob.target == 3) o = &ob;
    if (!o || u < 4 || u > w.seq.camera.width - 4) continue;
    if (u < w.seq.camera.width / 2 - 4) {
      ++behind;
      behind_removed += o->outlier;
    } else if (u > w.seq.camera.width / 2 + 4) {
      ++beside;
      beside_removed += o->outlier;
    }
  }
  ASSERT_GT(behind, 50);
  ASSERT_GT(beside, 50);
  // Left in the energy, a hidden observation can end where its texture is not judged lost.
  EXPECT_GE(behind_removed, 0.99 * behind);
  EXPECT_LT(beside_removed, 0.1 * beside);
  EXPECT_GE(s.observations_texture_lost, 0.9 * behind);
  EXPECT_LE(s.observations_texture_lost, s.observations_removed);
  World w_off;
  EXPECT_EQ(run(TextureLossOptions{}, &w_off).observations_texture_lost, 0);  // Off by default.
}

TEST(Pba, KeepsTheNewestObservationsOutsideTheWindow) {
  World w;
  BuildWorld({0, 6, 12, 18}, &w);
  // Active {0, 1}, both held: every point has one observation in the other active keyframe and
  // two outside (keyframes 2 and 3); a cap of one keeps the newer (3), so keyframe 2 is not in the
  // problem. Points of keyframes that are optimised keep all their observations.
  PbaOptions options;
  options.max_iterations = 1;
  options.max_outside_observations = 1;
  const PbaSummary capped = RunPba(&w.map, w.seq.camera, {0, 1}, options, {0, 1});
  EXPECT_EQ(capped.observations, 2 * capped.points);
  EXPECT_EQ(capped.keyframes, 3);
  World fresh;  // The first run marked outlier observations.
  BuildWorld({0, 6, 12, 18}, &fresh);
  options.max_outside_observations = 2;
  const PbaSummary all = RunPba(&fresh.map, fresh.seq.camera, {0, 1}, options, {0, 1});
  World free;
  BuildWorld({0, 6, 12, 18}, &free);
  options.max_outside_observations = 1;
  EXPECT_EQ(RunPba(&free.map, free.seq.camera, {0, 1}, options).observations, 3 * all.points);
  EXPECT_EQ(all.observations, 3 * all.points);
  EXPECT_EQ(all.keyframes, 4);
}

TEST(Pba, TakesInTheMostObservedKeyframesOutsideTheWindow) {
  World w;
  BuildWorld({0, 6, 12, 18, 24}, &w);
  // Active {0, 1}: their points are observed in keyframes 2, 3 and 4 outside the window. Keyframe 3
  // loses a third of its observations, so it is the least observed; 2 and 4 tie.
  int dropped = 0;
  for (int i = 0; i < w.map.NumPoints(); ++i) {
    Point& p = w.map.point(i);
    if (p.host > 1) continue;
    for (Observation& o : p.observations) {
      if (o.target != 3 || i % 3 != 0) continue;
      o.outlier = true;
      ++dropped;
    }
  }
  ASSERT_GT(dropped, 50);
  const auto outside = [&](int cap) {
    PbaOptions options;
    options.max_outside_keyframes = cap;
    std::vector<int> fixed_outside;
    const PbaSelection s = SelectPbaProblem(w.map, {0, 1}, {}, options);
    for (size_t c = 0; c < s.cams.size(); ++c) {
      if (s.cams[c] <= 1) continue;
      fixed_outside.push_back(s.cams[c]);
      EXPECT_TRUE(s.fixed[c]) << "keyframe " << s.cams[c];
    }
    std::sort(fixed_outside.begin(), fixed_outside.end());
    return fixed_outside;
  };
  EXPECT_EQ(outside(0), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(outside(3), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(outside(2), (std::vector<int>{2, 4}));
  EXPECT_EQ(outside(1), (std::vector<int>{4}));  // On a tie the newer.
}

TEST(Pba, AKeyframeInFewObservationsStaysFixed) {
  World w;
  BuildWorld({0, 6, 12, 18}, &w);
  // Keyframe 3 keeps only a handful of observations: the data barely constrain it.
  int kept = 0;
  for (int i = 0; i < w.map.NumPoints(); ++i) {
    auto& obs = w.map.point(i).observations;
    for (Observation& o : obs)
      if (o.target == 3 && kept++ >= 10) o.outlier = true;
  }
  Perturb(&w);
  const SE3d before = w.map.keyframe(3).cam_from_world;
  const PbaSummary s = RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, PbaOptions{});
  EXPECT_EQ(s.fixed_keyframes, 2);
  EXPECT_EQ(w.map.keyframe(3).cam_from_world.Matrix(), before.Matrix());
}

TEST(Pba, AKeyframeTiedByFarFewerObservationsThanPlacedItStaysFixed) {
  // Keyframe 3 is placed by a solve with all its observations; later it keeps 60 (above
  // min_camera_observations) of them, its own points and the rest gone from the problem.
  const auto strip = [](World* w) {
    int kept = 0;
    for (int i = 0; i < w->map.NumPoints(); ++i)
      for (Observation& o : w->map.point(i).observations)
        if (w->map.point(i).host == 3 || (o.target == 3 && kept++ >= 60)) o.outlier = true;
  };
  for (const double ratio : {PbaOptions{}.min_link_ratio, 0.0}) {
    World w;
    BuildWorld({0, 6, 12, 18}, &w);
    PbaOptions options;
    options.min_link_ratio = ratio;
    RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, options);
    const int placed = w.map.keyframe(3).most_pba_links;
    EXPECT_GT(placed, 1000);
    strip(&w);
    Perturb(&w);
    const SE3d before = w.map.keyframe(3).cam_from_world;
    const PbaSummary s = RunPba(&w.map, w.seq.camera, {0, 1, 2, 3}, options);
    EXPECT_EQ(w.map.keyframe(3).most_pba_links, placed);  // Not raised by a solve that held it.
    if (ratio > 0) {
      EXPECT_EQ(s.fixed_keyframes, 2);
      EXPECT_EQ(w.map.keyframe(3).cam_from_world.Matrix(), before.Matrix());
    } else {
      EXPECT_EQ(s.fixed_keyframes, 1);
      EXPECT_NE(w.map.keyframe(3).cam_from_world.Matrix(), before.Matrix());
    }
  }
}

// One pattern pixel of an observation for Ceres: parameters are increments on the starting state
// (pose: left increment of cam_from_world, then a and b); numeric derivatives through the same
// residual function. The gradient weight is held at its value at the PBA's solution (the PBA
// treats it as a constant weight in each step), so both share the optimality conditions.
struct CeresPixel {
  const Map* map;
  const PinholeCamera* camera;
  int target;
  SE3d host0, target0;
  AffineBrightness host_affine0, target_affine0;
  HostPatch patch;
  float weight_g = 1.f;
  int pixel = 0;

  bool operator()(const double* dh, const double* dt, const double* rho, double* residual) const {
    const SE3d T_h = SE3d::Exp(Eigen::Map<const Eigen::Matrix<double, 6, 1>>(dh)) * host0;
    const SE3d T_t = SE3d::Exp(Eigen::Map<const Eigen::Matrix<double, 6, 1>>(dt)) * target0;
    const SE3d T_th = T_t * T_h.Inverse();
    ObservationInput in;
    in.camera = camera;
    in.target = &map->keyframe(target).Pyramid();
    in.R = T_th.Rotation().cast<float>();
    in.t = T_th.Translation().cast<float>();
    in.idepth = static_cast<float>(*rho);
    in.host_affine = {host_affine0.a + dh[6], host_affine0.b + dh[7]};
    in.target_affine = {target_affine0.a + dt[6], target_affine0.b + dt[7]};
    ObservationResiduals res;
    if (!EvaluateObservation(patch, in, false, &res)) return false;
    residual[0] = std::sqrt(weight_g) * res.r[pixel];
    return true;
  }
};

TEST(Pba, AgreesWithACeresSolveOfTheSameProblem) {
  World ours, theirs;
  // Wide baselines; blurred images keep interpolated gradients close to the bilinear slopes.
  BuildWorld({0, 20, 40}, &ours, 10, 2.0);
  BuildWorld({0, 20, 40}, &theirs, 10, 2.0);
  Perturb(&ours, 0.3);
  Perturb(&theirs, 0.3);
  PbaOptions options;
  options.levels = 1;
  options.max_iterations = 100;
  options.robust.kind = RobustKind::kHuberFixed;
  options.max_rotation_step = options.max_translation_step = options.max_a_step = options.max_b_step = 1e-9;
  RunPba(&ours.map, ours.seq.camera, {0, 1, 2}, options);

  ceres::Problem problem;
  const int nk = theirs.map.NumKeyframes();
  std::vector<std::array<double, 8>> cam(nk);
  for (auto& c : cam) c.fill(0.0);
  std::vector<double> rho(theirs.map.NumPoints());
  for (int i = 0; i < theirs.map.NumPoints(); ++i) rho[i] = theirs.map.point(i).idepth;
  ceres::NumericDiffOptions diff;
  diff.relative_step_size = 1e-3;
  int blocks = 0;
  for (int i = 0; i < theirs.map.NumPoints(); ++i) {
    const Point& p = theirs.map.point(i);
    const Point& q = ours.map.point(i);
    HostPatch patch;
    if (!SampleHostPatch(theirs.map.keyframe(p.host).Pyramid(), 0, p.pixel, theirs.map.interpolation(), &patch)) continue;
    for (size_t oi = 0; oi < p.observations.size(); ++oi) {
      if (q.observations[oi].outlier) continue;  // what the PBA dropped
      const Keyframe& h = ours.map.keyframe(p.host);
      const Keyframe& t = ours.map.keyframe(q.observations[oi].target);
      const SE3d T_th = t.cam_from_world * h.cam_from_world.Inverse();
      ObservationInput in;
      in.camera = &ours.seq.camera;
      in.target = &t.Pyramid();
      in.R = T_th.Rotation().cast<float>();
      in.t = T_th.Translation().cast<float>();
      in.idepth = q.idepth;
      in.host_affine = h.affine;
      in.target_affine = t.affine;
      ObservationResiduals res;
      if (!EvaluateObservation(patch, in, false, &res)) continue;
      for (int k = 0; k < kPatternSize; ++k) {
        auto* functor = new CeresPixel{&theirs.map, &theirs.seq.camera, q.observations[oi].target,
                                       theirs.map.keyframe(p.host).cam_from_world,
                                       theirs.map.keyframe(q.observations[oi].target).cam_from_world,
                                       theirs.map.keyframe(p.host).affine,
                                       theirs.map.keyframe(q.observations[oi].target).affine, patch, res.weight_g[k], k};
        problem.AddResidualBlock(
            new ceres::NumericDiffCostFunction<CeresPixel, ceres::CENTRAL, 1, 8, 8, 1>(functor, ceres::TAKE_OWNERSHIP, 1, diff),
            new ceres::HuberLoss(9.0), cam[p.host].data(), cam[q.observations[oi].target].data(), &rho[i]);
        ++blocks;
      }
    }
  }
  problem.SetParameterBlockConstant(cam[0].data());
  // Our solution as Ceres parameters.
  std::vector<std::array<double, 8>> ours_cam(nk);
  for (int k = 0; k < nk; ++k) {
    const Eigen::Matrix<double, 6, 1> xi =
        (ours.map.keyframe(k).cam_from_world * theirs.map.keyframe(k).cam_from_world.Inverse()).Log();
    for (int j = 0; j < 6; ++j) ours_cam[k][j] = xi(j);
    ours_cam[k][6] = ours.map.keyframe(k).affine.a - theirs.map.keyframe(k).affine.a;
    ours_cam[k][7] = ours.map.keyframe(k).affine.b - theirs.map.keyframe(k).affine.b;
  }
  std::vector<double> ours_rho(rho.size());
  for (size_t i = 0; i < rho.size(); ++i) ours_rho[i] = ours.map.point(static_cast<int>(i)).idepth;
  const auto cost_at = [&](const std::vector<std::array<double, 8>>& c, const std::vector<double>& r) {
    const auto saved_c = cam;
    const auto saved_r = rho;
    cam = c;
    rho = r;
    double cost = 0.0;
    problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
    cam = saved_c;
    rho = saved_r;
    return cost;
  };
  const double our_cost = cost_at(ours_cam, ours_rho);
  ASSERT_GT(blocks, 400);

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_num_iterations = 200;
  solver.function_tolerance = solver.gradient_tolerance = solver.parameter_tolerance = 1e-14;
  // 1. From the same perturbed start, Ceres finds no better minimum than the PBA.
  ceres::Solver::Summary from_start;
  ceres::Solve(solver, &problem, &from_start);
  ASSERT_TRUE(from_start.IsSolutionUsable()) << from_start.BriefReport();
  EXPECT_LT(our_cost, from_start.final_cost * 1.001) << "ours " << our_cost << ", ceres " << from_start.final_cost;
  // 2. Started at the PBA's solution, Ceres stays close: it is (nearly) a minimum of the same
  // function. Not exactly: the PBA differentiates with interpolated image gradients, Ceres takes
  // numeric derivatives of the bilinear image itself, and the valley is flat along the gauge-like
  // directions of three keyframes; they agree to 0.5% in cost and within the bounds below.
  cam = ours_cam;
  rho = ours_rho;
  ceres::Solver::Summary from_ours;
  ceres::Solve(solver, &problem, &from_ours);
  EXPECT_GT(from_ours.final_cost, our_cost * 0.995) << "ceres improved the PBA's solution";
  // Monocular scale is a gauge freedom: compare with the first two camera centres 1 apart.
  const auto centre = [](const SE3d& cam_from_world) { return cam_from_world.Inverse().Translation(); };
  std::vector<SE3d> ceres_pose(nk);
  for (int k = 0; k < nk; ++k) {
    ceres_pose[k] = SE3d::Exp(Eigen::Map<const Eigen::Matrix<double, 6, 1>>(cam[k].data())) *
                    theirs.map.keyframe(k).cam_from_world;
  }
  const Eigen::Vector3d c0 = centre(ceres_pose[0]);
  const double s_ours = (centre(ours.map.keyframe(1).cam_from_world) - c0).norm();
  const double s_ceres = (centre(ceres_pose[1]) - c0).norm();
  for (int k = 1; k < nk; ++k) {
    const SE3d& our_pose = ours.map.keyframe(k).cam_from_world;
    const Eigen::Vector3d d = (centre(our_pose) - c0) / s_ours - (centre(ceres_pose[k]) - c0) / s_ceres;
    EXPECT_LT(d.norm(), 0.01) << "keyframe " << k;
    EXPECT_LT(RotationErrorDeg(our_pose, ceres_pose[k]), 0.05) << "keyframe " << k;
  }
  std::vector<double> rel;
  for (size_t i = 0; i < rho.size(); ++i) rel.push_back(std::abs(ours_rho[i] * s_ours / (rho[i] * s_ceres) - 1.0));
  std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
  EXPECT_LT(rel[rel.size() / 2], 5e-3);
}

TEST(Pba, PatternEnergyCountsTheOutliersAsTheDoubleThresholdDoes) {
  // The pattern's energy compares float residuals with the threshold in float: the count must be
  // that of the double comparison at the threshold's neighbouring floats, whether or not the
  // threshold is a float itself, and the energy ErrorModel::Energy's, pixel by pixel.
  for (const double threshold : {15.1, 16.0, 0.7}) {
    ErrorModel model;
    model.nu = 3.7;
    model.sigma = 6.3;
    model.inlier_threshold = threshold;
    const float t = static_cast<float>(threshold);
    internal::PatternValues r = {std::nextafter(t, 0.f), t, std::nextafter(t, 100.f), -std::nextafter(t, 100.f),
                                 -t, 0.f, 3.f * t, -0.5f * t};
    internal::PatternValues sqrt_w;
    sqrt_w.fill(1.f);
    sqrt_w[7] = 3.f;  // -1.5 t weighted.
    int expected_bad = 0;
    double expected_energy = 0.0;
    for (int k = 0; k < kPatternSize; ++k) {
      const double rw = static_cast<double>(sqrt_w[k] * r[k]);
      expected_bad += std::abs(rw) > threshold;
      expected_energy += model.Energy(rw);
    }
    int bad = -1;
    const double energy = internal::Problem::PixelEnergy(r, sqrt_w, model, &bad);
    EXPECT_EQ(bad, expected_bad) << "threshold " << threshold;
    EXPECT_NEAR(energy, expected_energy, 1e-9 * expected_energy) << "threshold " << threshold;
  }
}

}  // namespace
}  // namespace dsm
