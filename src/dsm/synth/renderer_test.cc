// SPDX-License-Identifier: MIT
// The synthetic world must be right before anything is measured on it: rendered depth matches the
// geometry, and warping one frame into another with the true depth and poses reproduces it.
#include "dsm/synth/renderer.h"

#include <cmath>

#include <gtest/gtest.h>

#include "dsm/testing/input_error.h"
#include "dsm/util/check.h"

namespace dsm::synth {
namespace {

struct WarpError {
  double mean_abs = 0.0;
  double fraction_within_8 = 0.0;
  size_t pixels = 0;
};

// For each pixel of B: back-project with B's depth, project into A, and compare A's bilinear
// intensity with B's. Pixels occluded in A (A's depth disagrees by more than `depth_tolerance`)
// are skipped. The warp uses B's pose moved by `pose_error` (B itself is rendered at its true pose).
WarpError Warp(const SynthSequence& seq, size_t a, size_t b, const Eigen::Vector3d& pose_error = Eigen::Vector3d::Zero(),
               double depth_tolerance = 0.01) {
  Image<float> albedo_a, depth_a, albedo_b, depth_b;
  RenderFrame(seq.scene, seq.camera, seq.world_from_cam[a], &albedo_a, &depth_a);
  RenderFrame(seq.scene, seq.camera, seq.world_from_cam[b], &albedo_b, &depth_b);
  // Noise-free 8-bit images through the full photometric model.
  const Image<uint8_t> img_a = FormImage(albedo_a, seq.photometry[a], {});
  const Image<uint8_t> img_b = FormImage(albedo_b, seq.photometry[b], {});
  // Photometric parameters differ in the exposure scene: compare irradiance-normalised values.
  const auto normalise = [&](float value, size_t i) {
    const Photometry& p = seq.photometry[i];
    return (value - p.offset) / (p.gain * p.exposure_ms / 10.0);
  };
  const SE3d world_from_b(seq.world_from_cam[b].So3(), seq.world_from_cam[b].Translation() + pose_error);
  const SE3d a_from_b = seq.world_from_cam[a].Inverse() * world_from_b;
  WarpError e;
  size_t within = 0;
  for (int v = 0; v < seq.camera.height; v += 2) {
    for (int u = 0; u < seq.camera.width; u += 2) {
      const float z = depth_b(u, v);
      if (!(z > 0.f)) continue;
      const Eigen::Vector3d p_a = a_from_b * (seq.camera.Unproject(u, v) * z);
      if (p_a.z() < 0.1) continue;
      const Eigen::Vector2d px = seq.camera.Project(p_a);
      if (!img_a.InBounds(px.x(), px.y(), 1.0)) continue;
      const float za = depth_a(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())));
      if (std::abs(za - p_a.z()) > depth_tolerance * p_a.z()) continue;
      const double diff = std::abs(normalise(Bilinear(img_a, px.x(), px.y()), a) - normalise(img_b(u, v), b));
      e.mean_abs += diff;
      within += diff < 8.0;
      ++e.pixels;
    }
  }
  if (e.pixels) {
    e.mean_abs /= e.pixels;
    e.fraction_within_8 = static_cast<double>(within) / e.pixels;
  }
  return e;
}

class EveryScene : public ::testing::TestWithParam<std::string> {
 protected:
  // The scene's full trajectory, rendered at 320 x 240.
  SynthSequence Sequence() const {
    SynthOptions options;
    options.scene = GetParam();
    options.width = 320;
    options.height = 240;
    return MakeSequence(options);
  }
};

TEST_P(EveryScene, WarpingWithTrueDepthAndPosesReproducesTheFrame) {
  const SynthSequence seq = Sequence();
  for (auto [a, b] : {std::pair<size_t, size_t>{0, 4}, {100, 103}, {200, 210}}) {
    // At most 0.3 m and 20 degrees apart: walking down a corridor, or turning to see a wall
    // obliquely, the footprint of the band-limited textures changes, and with it what a pixel sees.
    const SE3d world_from_a = seq.world_from_cam[a];  // A lambda does not capture a structured binding.
    const auto apart = [&](size_t j) {
      const SE3d a_from_j = world_from_a.Inverse() * seq.world_from_cam[j];
      return a_from_j.Translation().norm() > 0.3 || a_from_j.So3().Log().norm() > 20.0 * M_PI / 180.0;
    };
    while (b > a + 1 && apart(b)) --b;
    const WarpError e = Warp(seq, a, b);
    EXPECT_GT(e.pixels, 5000u) << a << " -> " << b;
    EXPECT_LT(e.mean_abs, 3.0) << a << " -> " << b;
    EXPECT_GT(e.fraction_within_8, 0.95) << a << " -> " << b;
  }
}

TEST_P(EveryScene, WarpWithAWrongPoseFails) {
  // The same check detects a 5 cm error in the pose (a few pixels): the test above can fail. The
  // wrong pose moves depths by a few percent too: the occlusion test is loosened to 10%.
  const SynthSequence seq = Sequence();
  const WarpError e = Warp(seq, 0, 4, Eigen::Vector3d(0.05, -0.05, 0.0), 0.1);
  EXPECT_GT(e.pixels, 5000u);
  EXPECT_GT(e.mean_abs, 5.0);
}

INSTANTIATE_TEST_SUITE_P(Synth, EveryScene,
                         ::testing::ValuesIn(SceneNames()));

TEST(Renderer, DepthOfAKnownWall) {
  // Camera in the room centre looking at the +x wall (x = 4): the centre pixel sees it at 4 m.
  SynthOptions options;
  options.scene = "loop";
  const SynthSequence seq = MakeSequence(options);
  PinholeCamera cam{64, 48, 40, 40, 31.5, 23.5};
  Image<float> albedo, depth;
  RenderFrame(seq.scene, cam, LookAt({0, 0, 1.5}, {1, 0, 1.5}), &albedo, &depth);
  EXPECT_NEAR(depth(31, 23), 4.0f, 1e-3f);
  EXPECT_NEAR(depth(32, 24), 4.0f, 1e-3f);
  // Off-axis pixels still report z (not ray length): the whole wall is at z = 4.
  EXPECT_NEAR(depth(50, 10), 4.0f, 1e-3f);
  EXPECT_GT(albedo(31, 23), 0.f);
}

// Each lens sees what the pinhole of its focal length sees, moved by its distortion: every pixel of
// the lens image whose ray falls inside the pinhole's image is found there at the same depth with
// the same brightness (the texture filter differs a little: the pixels span other angles), and the
// wide models see beyond the pinhole's field.
class EveryLens : public ::testing::TestWithParam<CameraModel> {};

TEST_P(EveryLens, SeesThePinholesSceneThroughItsDistortion) {
  SynthOptions options;
  options.scene = "orbit";  // A pillar and a table close by: culling errors would show as holes.
  options.width = 320;
  options.height = 240;
  const SynthSequence pinhole = MakeSequence(options);
  options.model = GetParam();
  const SynthSequence lensed = MakeSequence(options);
  ASSERT_TRUE(lensed.lens != nullptr);
  EXPECT_EQ(lensed.lens->camera().model, GetParam());
  for (const size_t i : {size_t{0}, size_t{150}}) {
    Image<float> albedo_p, depth_p, albedo_l, depth_l;
    RenderFrame(pinhole.scene, pinhole.camera, pinhole.world_from_cam[i], &albedo_p, &depth_p);
    RenderSequenceAlbedo(lensed, i, &albedo_l, &depth_l);
    size_t inside = 0, same_depth = 0, same_albedo = 0, outside = 0;
    for (int v = 0; v < lensed.camera.height; ++v)
      for (int u = 0; u < lensed.camera.width; ++u) {
        Eigen::Vector2d n;
        ASSERT_TRUE(lensed.lens->camera().Unproject({double(u), double(v)}, &n));
        ASSERT_GT(depth_l(u, v), 0.f) << u << ", " << v;  // A closed room: every ray hits.
        const Eigen::Vector2d px = pinhole.camera.Project({n.x(), n.y(), 1.0});
        if (!albedo_p.InBounds(px.x(), px.y(), 1.0)) {
          ++outside;
          continue;
        }
        ++inside;
        const int pu = static_cast<int>(std::lround(px.x())), pv = static_cast<int>(std::lround(px.y()));
        same_depth += std::abs(depth_p(pu, pv) - depth_l(u, v)) < 0.01f * depth_l(u, v);
        same_albedo += std::abs(Bilinear(albedo_p, px.x(), px.y()) - albedo_l(u, v)) < 0.03f;
      }
    EXPECT_GT(inside, 0.5 * lensed.camera.width * lensed.camera.height);
    EXPECT_GT(same_depth, 0.98 * inside) << i;
    EXPECT_GT(same_albedo, 0.9 * inside) << i;
    EXPECT_GT(outside, 0.05 * lensed.camera.width * lensed.camera.height) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Synth, EveryLens,
                         ::testing::Values(CameraModel::kRadTan, CameraModel::kEquidistant, CameraModel::kFov),
                         [](const ::testing::TestParamInfo<CameraModel>& p) { return CameraModelName(p.param); });

TEST(Renderer, APinholeLensIsThePinhole) {
  SynthOptions options;
  options.scene = "orbit";
  options.width = 160;
  options.height = 120;
  const SynthSequence seq = MakeSequence(options);
  const PinholeCamera& c = seq.camera;
  const LensRays lens(seq.Calibration());
  Image<float> albedo_p, depth_p, albedo_l, depth_l;
  RenderFrame(seq.scene, c, seq.world_from_cam[40], &albedo_p, &depth_p);
  RenderFrame(seq.scene, lens, seq.world_from_cam[40], &albedo_l, &depth_l);
  double worst_depth = 0.0, mean_albedo = 0.0;
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      worst_depth = std::max(worst_depth, std::abs(double(depth_p(u, v)) - depth_l(u, v)) / depth_p(u, v));
      mean_albedo += std::abs(albedo_p(u, v) - albedo_l(u, v)) / (c.width * c.height);
    }
  EXPECT_LT(worst_depth, 1e-4);
  EXPECT_LT(mean_albedo, 0.005);
}

TEST(Scene, PlainPillarsKeepATenthOfTheirContrast) {
  // A pillar from the floor to 3 m and a stool of 0.5 m; a camera sees each from 1 m.
  Scene scene;
  const Texture texture{7, 0.5f, 0.3f, 0.3f};
  scene.AddCylinder({{1.f, 0.f}, 0.2f, 0.f, 3.f, texture});
  scene.AddCylinder({{-1.f, 0.f}, 0.2f, 0.f, 0.5f, texture});
  const auto spread = [&](const Eigen::Vector3f& origin, const Eigen::Vector3f& centre) {
    float lo = 1.f, hi = 0.f;
    for (int i = -10; i <= 10; ++i) {
      Hit hit;
      const Eigen::Vector3f target = centre + Eigen::Vector3f(0.f, 0.015f * i, 0.f);
      EXPECT_TRUE(scene.Intersect(origin, (target - origin).normalized(), &hit));
      const float albedo = EvaluateTexture(*hit.texture, hit.u, hit.v, 1e-3f);
      lo = std::min(lo, albedo), hi = std::max(hi, albedo);
    }
    return hi - lo;
  };
  const Eigen::Vector3f eye(0.f, 0.f, 0.25f);
  const float pillar = spread(eye, {0.8f, 0.f, 0.25f}), stool = spread(eye, {-0.8f, 0.f, 0.25f});
  scene.PlainPillars();
  EXPECT_NEAR(spread(eye, {0.8f, 0.f, 0.25f}), 0.1f * pillar, 0.02f * pillar);
  EXPECT_FLOAT_EQ(spread(eye, {-0.8f, 0.f, 0.25f}), stool);  // Not a pillar.
  EXPECT_GT(pillar, 0.05f);
}

// A short sequence of `scene` at 160 x 120.
SynthOptions SmallSequence(const std::string& scene, int frames) {
  SynthOptions options;
  options.scene = scene;
  options.frames = frames;
  options.width = 160;
  options.height = 120;
  return options;
}

TEST(Sequences, DeterministicPerSeed) {
  SynthOptions options = SmallSequence("shake", 20);
  const SynthSequence a = MakeSequence(options), b = MakeSequence(options);
  options.seed = 2;
  const SynthSequence c = MakeSequence(options);
  Image<float> ia, ib, ic;
  RenderFrame(a.scene, a.camera, a.world_from_cam[7], &ia, nullptr);
  RenderFrame(b.scene, b.camera, b.world_from_cam[7], &ib, nullptr, /*parallel=*/false);
  RenderFrame(c.scene, c.camera, c.world_from_cam[7], &ic, nullptr);
  EXPECT_EQ(std::vector<float>(ia.data(), ia.data() + ia.size()), std::vector<float>(ib.data(), ib.data() + ib.size()));
  EXPECT_EQ(a.world_from_cam[7].Matrix(), b.world_from_cam[7].Matrix());
  EXPECT_NE(a.world_from_cam[7].Matrix(), c.world_from_cam[7].Matrix());
  double diff = 0;
  for (size_t i = 0; i < ia.size(); ++i) diff += std::abs(ia.data()[i] - ic.data()[i]);
  EXPECT_GT(diff / ia.size(), 0.01);
}

TEST(Sequences, OptionsAreValidated) {
  SynthOptions options;
  options.scene = "moon";
  EXPECT_THROW(MakeSequence(options), InputError);
  options.scene = "loop";
  options.width = 10;
  EXPECT_THROW(MakeSequence(options), InputError);
  options.width = 640;
  options.noise_sigma = -1;
  EXPECT_THROW(MakeSequence(options), InputError);
}

TEST(RollingShutter, EachRowIsSeenFromTheCameraAtItsOwnTime) {
  SynthOptions options = SmallSequence("handheld", 40);
  options.rate_hz = 30;
  options.line_delay_us = 200;  // The readout takes 24 ms of the 33 ms between frames.
  const SynthSequence seq = MakeSequence(options);
  const size_t frame = 30;  // Turning at about 60 deg/s.
  const std::vector<SE3d> rows = seq.RowPoses(frame);
  ASSERT_EQ(rows.size(), 120u);
  EXPECT_EQ(rows[0].Matrix(), seq.world_from_cam[frame].Matrix());  // The timestamp is the first row's.
  // Row 119 is exposed 119 * 200 us later: the camera's pose 0.714 frame intervals on.
  EXPECT_TRUE(rows[119].Matrix().isApprox(seq.pose_at(frame + 119 * 200e-6 * 30).Matrix(), 1e-12));
  Image<float> rolling, global, at_row;
  RenderRollingShutterFrame(seq.scene, seq.camera, rows, &rolling, nullptr);
  RenderFrame(seq.scene, seq.camera, rows[0], &global, nullptr);
  for (int v : {0, 60, 119}) {
    RenderFrame(seq.scene, seq.camera, rows[v], &at_row, nullptr);
    for (int u = 0; u < 160; ++u) ASSERT_NEAR(rolling(u, v), at_row(u, v), 1e-6f) << "row " << v << ", column " << u;
  }
  // The last rows are seen from elsewhere than the first: the image differs from a global shutter's.
  double diff = 0.0;
  for (int u = 0; u < 160; ++u) diff += std::abs(rolling(u, 119) - global(u, 119));
  EXPECT_GT(diff / 160, 0.02);
  for (int u = 0; u < 160; ++u) ASSERT_NEAR(rolling(u, 0), global(u, 0), 1e-6f) << "column " << u;
}

TEST(RollingShutter, TheReadoutFitsInTheFrameInterval) {
  SynthOptions options;
  options.scene = "handheld";
  options.rate_hz = 30;
  options.height = 480;
  options.line_delay_us = 69;  // 33.1 ms of rows within 33.3 ms.
  EXPECT_NO_THROW(options.Validate());
  options.line_delay_us = 70;
  EXPECT_NE(testing::MessageOf([&] { options.Validate(); }).find("--rolling-shutter"), std::string::npos);
  options.line_delay_us = -1;
  EXPECT_THROW(options.Validate(), InputError);
}

TEST(FormImage, NoiseVignetteAndBlur) {
  Image<float> albedo(64, 48, 0.5f);
  const Image<uint8_t> clean = FormImage(albedo, {}, {});
  EXPECT_EQ(clean(10, 10), 128);  // 0.5 * 255 = 127.5 rounds up
  const Image<float> vignette = MakeVignette(64, 48, 0.5);
  FormationOptions options;
  options.vignette = &vignette;
  const Image<uint8_t> vig = FormImage(albedo, {}, options);
  EXPECT_EQ(vig(0, 0), 64);  // corner: 127.5 * 0.5
  options = {};
  options.noise_sigma = 3.0;
  options.noise_seed = 5;
  const Image<uint8_t> noisy = FormImage(albedo, {}, options);
  double var = 0;
  for (size_t i = 0; i < noisy.size(); ++i) var += (noisy.data()[i] - 127.5) * (noisy.data()[i] - 127.5);
  EXPECT_NEAR(std::sqrt(var / noisy.size()), 3.0, 0.3);
  // Blur keeps a constant image constant.
  options = {};
  options.blur_sigma = 1.5;
  EXPECT_EQ(FormImage(albedo, {}, options)(0, 0), 128);
}

}  // namespace
}  // namespace dsm::synth
