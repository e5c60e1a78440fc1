// SPDX-License-Identifier: MIT
#include "dsm/io/calibration_io.h"

#include <gtest/gtest.h>

#include "dsm/testing/input_error.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

using testing::MessageOf;
using testing::ScratchDir;
using testing::WriteText;

TEST(CameraYaml, RoundTrip) {
  const auto dir = ScratchDir("camera_yaml_roundtrip");
  CameraYaml c;
  c.camera = {CameraModel::kEquidistant, 512, 512, 190.5, 190.25, 254.5, 256.75, {0.01, -0.02, 0.003, -0.0004}};
  c.rate_hz = 30;
  WriteCameraYaml(dir / "camera.yaml", c);
  const CameraYaml back = ReadCameraYaml(dir / "camera.yaml");
  EXPECT_EQ(back.camera.model, CameraModel::kEquidistant);
  EXPECT_EQ(back.camera.width, 512);
  EXPECT_DOUBLE_EQ(back.camera.fy, 190.25);
  EXPECT_EQ(back.camera.distortion, c.camera.distortion);
  EXPECT_DOUBLE_EQ(back.rate_hz, 30);
  EXPECT_FALSE(back.line_delay_us.has_value());  // The file says nothing of the shutter.
  c.line_delay_us = 29.5;
  WriteCameraYaml(dir / "rolling.yaml", c);
  EXPECT_EQ(ReadCameraYaml(dir / "rolling.yaml").line_delay_us, 29.5);
  c.line_delay_us = 0.0;  // A global shutter, said.
  WriteCameraYaml(dir / "global.yaml", c);
  EXPECT_EQ(ReadCameraYaml(dir / "global.yaml").line_delay_us, 0.0);
}

TEST(CameraYaml, MalformedFilesGiveClearErrors) {
  const auto dir = ScratchDir("camera_yaml_bad");
  const std::string good = "model: pinhole\nwidth: 640\nheight: 480\nintrinsics: [400, 400, 320, 240]\n";
  WriteText(dir / "unknown.yaml", good + "focal: 3\n");
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "unknown.yaml"); }).find("unknown key 'focal'"), std::string::npos);
  WriteText(dir / "missing.yaml", "model: pinhole\nwidth: 640\nheight: 480\n");
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "missing.yaml"); }).find("missing key 'intrinsics'"), std::string::npos);
  WriteText(dir / "type.yaml", "model: pinhole\nwidth: wide\nheight: 480\nintrinsics: [400, 400, 320, 240]\n");
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "type.yaml"); }).find("'width'"), std::string::npos);
  WriteText(dir / "neg.yaml", "model: pinhole\nwidth: 640\nheight: 480\nintrinsics: [-400, 400, 320, 240]\n");
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "neg.yaml"); }).find("focal"), std::string::npos);
  WriteText(dir / "delay.yaml", good + "rate_hz: 30\nline_delay_us: 80\n");  // 38 ms of rows in 33 ms.
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "delay.yaml"); }).find("'line_delay_us'"), std::string::npos);
  WriteText(dir / "syntax.yaml", "model: [pinhole\n");
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "syntax.yaml"); }).find("syntax.yaml"), std::string::npos);
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "none.yaml"); }).find("not found"), std::string::npos);
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir); }).find("a folder, not a YAML file"), std::string::npos);
  // Not a file but readable: /dev/null reads as an empty file, which names what it lacks.
  EXPECT_NE(MessageOf([&] { ReadCameraYaml("/dev/null"); }).find("/dev/null"), std::string::npos);
  // A key that is itself a sequence (found by fuzz/folder_dataset).
  WriteText(dir / "key.yaml", good + "[rate_hz]: 20\n");
  EXPECT_NE(MessageOf([&] { ReadCameraYaml(dir / "key.yaml"); }).find("line 5: a key must be a plain name"),
            std::string::npos);
}

TEST(TumMonoCamera, RelativeFovCalibration) {
  const auto dir = ScratchDir("tum_mono_camera");
  WriteText(dir / "camera.txt", "0.349153000000000 0.436593000000000 0.493140000000000 0.499021000000000 0.933271000000000\n"
                                "1280 1024\ncrop\n640 480\n");
  const TumMonoCamera c = ReadTumMonoCamera(dir / "camera.txt");
  EXPECT_EQ(c.camera.model, CameraModel::kFov);
  EXPECT_NEAR(c.camera.fx, 0.349153 * 1280, 1e-9);
  EXPECT_NEAR(c.camera.cx, 0.49314 * 1280 - 0.5, 1e-9);
  ASSERT_EQ(c.camera.distortion.size(), 1u);
  EXPECT_EQ(c.mode, UndistortMode::kCrop);
  WriteText(dir / "radtan.txt", "RadTan 458.654 457.296 367.215 248.375 -0.28 0.07 0.0002 0.00002\n752 480\nfull\n752 480\n");
  const TumMonoCamera r = ReadTumMonoCamera(dir / "radtan.txt");
  EXPECT_EQ(r.camera.model, CameraModel::kRadTan);
  EXPECT_EQ(r.mode, UndistortMode::kFull);
  WriteText(dir / "bad.txt", "Banana 1 2 3 4\n640 480\n");
  EXPECT_NE(MessageOf([&] { ReadTumMonoCamera(dir / "bad.txt"); }).find("bad.txt:1"), std::string::npos);
  WriteText(dir / "nosize.txt", "Pinhole 400 400 320 240 0\n");
  EXPECT_THROW(ReadTumMonoCamera(dir / "nosize.txt"), InputError);
}

TEST(KittiCalib, ReadsP0) {
  const auto dir = ScratchDir("kitti_calib");
  WriteText(dir / "calib.txt", "P0: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 "
                               "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 "
                               "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n");
  const CameraCalibration c = ReadKittiCalib(dir / "calib.txt", 1241, 376);
  EXPECT_DOUBLE_EQ(c.fx, 718.856);
  EXPECT_DOUBLE_EQ(c.cy, 185.2157);
  WriteText(dir / "bad.txt", "P1: 1 2 3\n");
  EXPECT_NE(MessageOf([&] { ReadKittiCalib(dir / "bad.txt", 1241, 376); }).find("P0"), std::string::npos);
}

TEST(PhotometricFiles, ReadsResponseAndRejectsWrongCounts) {
  const auto dir = ScratchDir("pcalib");
  EXPECT_FALSE(ReadPhotometricCalibration(dir).has_value());
  std::string values;
  for (int i = 0; i < 256; ++i) values += std::to_string(i * i) + " ";
  WriteText(dir / "pcalib.txt", values + "\n");
  const auto calib = ReadPhotometricCalibration(dir);
  ASSERT_TRUE(calib.has_value());
  EXPECT_TRUE(calib->has_response());
  EXPECT_NEAR(calib->inverse_response()[128], 255.0 * 128 * 128 / (255.0 * 255), 1e-3);
  WriteText(dir / "pcalib.txt", "1 2 3\n");
  EXPECT_NE(MessageOf([&] { ReadPhotometricCalibration(dir); }).find("256"), std::string::npos);
}

}  // namespace
}  // namespace dsm
