// SPDX-License-Identifier: MIT
#include "dsm/geometry/undistorter.h"

#include <cmath>
#include <utility>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// A smooth image function, so bilinear sampling is near exact.
float Smooth(double u, double v) { return 100.f + 50.f * std::sin(u * 0.05) * std::cos(v * 0.04); }

Image<float> RenderSmooth(int w, int h) {
  Image<float> img(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) img(u, v) = Smooth(u, v);
  return img;
}

TEST(Undistorter, RemapSamplesTheRightSourcePixel) {
  const CameraCalibration cams[] = {
      {CameraModel::kRadTan, 752, 480, 458.654, 457.296, 367.215, 248.375,
       {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}},
      {CameraModel::kEquidistant, 512, 512, 190.98, 190.98, 254.93, 256.90,
       {0.0034823894, 0.0007150348, -0.0020532361, 0.0002029688}},
      {CameraModel::kFov, 640, 480, 277.4, 291.1, 312.9, 239.0, {0.9}},
  };
  for (const auto& cam : cams) {
    for (UndistortMode mode : {UndistortMode::kCrop, UndistortMode::kFull}) {
      const Undistorter und(cam, {mode, 16});
      const PinholeCamera& out = und.output();
      EXPECT_EQ(out.width % 16, 0);
      EXPECT_EQ(out.height % 16, 0);
      const Image<float> result = und.Apply(RenderSmooth(cam.width, cam.height));
      // A 3-D point seen by both cameras has the same intensity in both images.
      int checked = 0;
      for (int v = 3; v < out.height; v += 23) {
        for (int u = 5; u < out.width; u += 29) {
          if (!und.valid_mask()(u, v)) continue;
          const Eigen::Vector3d p = out.Unproject(u, v) * 2.7;
          const Eigen::Vector2d src = cam.Project(p);
          EXPECT_NEAR(result(u, v), Smooth(src.x(), src.y()), 0.1);
          ++checked;
        }
      }
      EXPECT_GT(checked, 100);
      if (mode == UndistortMode::kCrop) {
        EXPECT_DOUBLE_EQ(und.ValidFraction(), 1.0) << CameraModelName(cam.model);
      }
    }
  }
}

TEST(Undistorter, OddSizesAreCroppedToPyramidFriendlySizes) {
  const CameraCalibration kitti{CameraModel::kPinhole, 1241, 376, 718.856, 718.856, 607.1928, 185.2157, {}};
  const Undistorter und(kitti, {UndistortMode::kCrop, 16});
  EXPECT_EQ(und.output().width, 1232);
  EXPECT_EQ(und.output().height, 368);
  EXPECT_DOUBLE_EQ(und.output().cx, 607.1928 - 4);
  EXPECT_DOUBLE_EQ(und.output().cy, 185.2157 - 4);
  Image<float> in(1241, 376);
  for (int v = 0; v < 376; ++v)
    for (int u = 0; u < 1241; ++u) in(u, v) = static_cast<float>(u + 2000 * v);
  const Image<float> out = und.Apply(in);
  EXPECT_EQ(out(0, 0), in(4, 4));
  EXPECT_EQ(out(1231, 367), in(1235, 371));
}

// An 8-bit frame undistorted directly gives the floats its float copy gives, bit for bit, in the
// remap (radtan) and the crop (pinhole) paths.
TEST(Undistorter, EightBitInputIsItsFloatCopy) {
  // The vectorised 8-bit path (undistorter_remap.cc) against the float one: whole runs of eight,
  // runs with invalid pixels (full view), a row tail of six (size multiple 1, width 750).
  const CameraCalibration radtan{CameraModel::kRadTan, 752, 480, 458.654, 457.296, 367.215, 248.375,
                                 {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}};
  CameraCalibration narrow = radtan;
  narrow.width = 750;
  const std::pair<CameraCalibration, Undistorter::Options> cases[] = {
      {radtan, {UndistortMode::kCrop, 16}},
      {radtan, {UndistortMode::kFull, 16}},
      {narrow, {UndistortMode::kFull, 1}},
      {{CameraModel::kPinhole, 645, 482, 400.0, 400.0, 322.0, 240.0, {}}, {UndistortMode::kCrop, 16}},
  };
  for (const auto& [cam, options] : cases) {
    const Undistorter und(cam, options);
    Image<uint8_t> raw(cam.width, cam.height);
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) raw(u, v) = static_cast<uint8_t>((u * 7 + v * 13 + u * v * 31) % 256);
    const Image<float> direct = und.Apply(raw), copied = und.Apply(ToFloat(raw));
    ASSERT_EQ(direct.width(), copied.width());
    ASSERT_EQ(direct.height(), copied.height());
    int differ = 0;
    for (int v = 0; v < direct.height(); ++v)
      for (int u = 0; u < direct.width(); ++u) differ += direct(u, v) != copied(u, v);
    EXPECT_EQ(differ, 0) << CameraModelName(cam.model);
    EXPECT_NE(direct(direct.width() / 2, direct.height() / 2), 0.f);
  }
}

}  // namespace
}  // namespace dsm
