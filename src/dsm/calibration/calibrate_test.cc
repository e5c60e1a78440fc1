// SPDX-License-Identifier: MIT
// Calibration from rendered boards (board_render.h), where the truth is known: for each camera
// model dsm calibrates, the focal lengths come out within 0.3% and the principal point within 1 px
// of the truth, with a reprojection RMS under 0.2 px; input it cannot calibrate from is a clear
// message, not a calibration.
#include "dsm/calibration/calibrate.h"

#include <gtest/gtest.h>

#include "dsm/calibration/board_render.h"
#include "dsm/testing/input_error.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

const BoardSpec kBoard = BoardSpec::Parse("checkerboard:9x6:0.04", "test");

void ExpectFound(CameraModel model, const BoardSpec& board = kBoard) {
  const CameraCalibration truth = ExampleCamera(model);
  const std::string kind = board.kind == BoardKind::kCharuco ? "_charuco" : "";
  const auto dir = testing::ScratchDir("calibrate_" + CameraModelName(model) + kind);
  WriteBoardSequence(dir, truth, board, 24, 7);
  CalibrationOptions options;
  options.board = board;
  options.model = model;
  const CalibrationResult r = Calibrate(dir, options);
  std::printf("%s: fx %.3f fy %.3f cx %.3f cy %.3f rms %.3f px, %d views\n", CameraModelName(model).c_str(),
              r.camera.fx, r.camera.fy, r.camera.cx, r.camera.cy, r.rms_px, r.views_used);
  EXPECT_EQ(r.frames, 24);
  EXPECT_EQ(r.camera.model, model);
  EXPECT_NEAR(r.camera.fx, truth.fx, 0.003 * truth.fx);
  EXPECT_NEAR(r.camera.fy, truth.fy, 0.003 * truth.fy);
  EXPECT_NEAR(r.camera.cx, truth.cx, 1.0);
  EXPECT_NEAR(r.camera.cy, truth.cy, 1.0);
  EXPECT_LT(r.rms_px, 0.05);  // The acceptance asks for 0.2 px: symmetry-refined corners reach 0.02-0.03.
  EXPECT_GE(r.views_used, kMinViews);
  ASSERT_EQ(r.camera.distortion.size(), truth.distortion.size());
  std::string uncovered;
  for (const std::string& cell : r.uncovered) uncovered += cell + " ";
  std::printf("  no corner in: %s\n", uncovered.c_str());
  // The model maps the image as the truth does where the views' corners reach (the image's corners
  // stay out of reach of a whole board seen by a wide lens): every ray within 0.1 px; 0.2 px from
  // a ChArUco board, whose corners are fewer and refined in smaller windows (short of its
  // markers).
  const double ray_px = board.kind == BoardKind::kCharuco ? 0.2 : 0.1;
  for (int y = 72; y <= 408; y += 48)
    for (int x = 96; x <= 544; x += 64) {
      Eigen::Vector2d n;
      ASSERT_TRUE(truth.Unproject({double(x), double(y)}, &n));
      EXPECT_LT((r.camera.Project({n.x(), n.y(), 1.0}) - Eigen::Vector2d(x, y)).norm(), ray_px) << x << " " << y;
    }
}

TEST(Calibrate, FindsAPinholeCamera) { ExpectFound(CameraModel::kPinhole); }
TEST(Calibrate, FindsARadTanCamera) { ExpectFound(CameraModel::kRadTan); }
TEST(Calibrate, FindsAnEquidistantCamera) { ExpectFound(CameraModel::kEquidistant); }
TEST(Calibrate, FindsAFovCamera) { ExpectFound(CameraModel::kFov); }
TEST(Calibrate, FindsARadTanCameraFromAChArUcoBoard) {
  ExpectFound(CameraModel::kRadTan, BoardSpec::Parse("charuco:8x6:0.04:0.03:DICT_4X4_50", "test"));
}
TEST(Calibrate, FindsAnEquidistantCameraFromAChArUcoBoard) {
  ExpectFound(CameraModel::kEquidistant, BoardSpec::Parse("charuco:7x5:0.05:0.035:DICT_5X5_100", "test"));
}

TEST(Calibrate, ABoardNeverFoundIsAMessage) {
  const auto dir = testing::ScratchDir("calibrate_wrong_board");
  WriteBoardSequence(dir, ExampleCamera(CameraModel::kPinhole), kBoard, 3, 1);
  CalibrationOptions options;
  options.board = BoardSpec::Parse("checkerboard:11x8:0.04", "test");  // More corners than the board has.
  EXPECT_NE(testing::MessageOf([&] { Calibrate(dir, options); }).find("is in none of the 3 frames"), std::string::npos);
}

TEST(Calibrate, TooFewViewsIsAMessage) {
  const auto dir = testing::ScratchDir("calibrate_few");
  WriteBoardSequence(dir, ExampleCamera(CameraModel::kPinhole), kBoard, 3, 1);
  CalibrationOptions options;
  options.board = kBoard;
  EXPECT_NE(testing::MessageOf([&] { Calibrate(dir, options); }).find("views are needed"), std::string::npos);
}

TEST(Calibrate, ABoardSpecIsChecked) {
  EXPECT_NE(testing::MessageOf([] { BoardSpec::Parse("chess:9x6", "--board"); }).find("checkerboard:COLSxROWS"),
            std::string::npos);
  EXPECT_NE(testing::MessageOf([] { BoardSpec::Parse("checkerboard:6x6:0.03", "--board"); }).find("orientation"),
            std::string::npos);
  const BoardSpec b = BoardSpec::Parse("checkerboard:9x6:0.025", "--board");
  EXPECT_EQ(b.cols, 9);
  EXPECT_EQ(b.rows, 6);
  EXPECT_DOUBLE_EQ(b.square_m, 0.025);
  EXPECT_EQ(b.Corners()[10], Eigen::Vector3d(0.025, 0.025, 0.0));
}

}  // namespace
}  // namespace dsm
