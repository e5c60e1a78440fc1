// SPDX-License-Identifier: MIT
// Boards found in rendered views (board_render.h), where every corner's place is known: the
// corners come out where the camera projects them, numbered as BoardSpec::Corners lists them, and
// a ChArUco board is found in part when part of it is hidden.
#include "dsm/calibration/detect.h"

#include <gtest/gtest.h>

#include "dsm/calibration/board_render.h"
#include "dsm/calibration/charuco.h"
#include "dsm/io/mat_gray.h"
#include "dsm/testing/input_error.h"

namespace dsm {
namespace {

// The largest distance between a corner found and where the true pose projects it; with
// `half_turn`, the corners numbered from the board's other end.
double WorstCornerPx(const BoardDetection& d, const BoardSpec& board, const CameraCalibration& camera,
                     const SE3d& cam_from_board, bool half_turn = false) {
  const std::vector<Eigen::Vector3d> all = board.Corners();
  double worst = 0.0;
  for (size_t i = 0; i < d.ids.size(); ++i) {
    const int id = half_turn ? board.NumCorners() - 1 - d.ids[i] : d.ids[i];
    const Eigen::Vector2d px = camera.Project(cam_from_board * all[id]);
    worst = std::max(worst, (px - Eigen::Vector2d(d.corners[i].x, d.corners[i].y)).norm());
  }
  return worst;
}

// The corners' error over many views, lens by lens: refined by their symmetry (corner_symmetry.h)
// they lie within 0.03 px RMS of the truth (cornerSubPix alone: 0.066 px on these renderings,
// whatever the noise: its error follows where the sharp edges cross the pixels).
TEST(DetectBoard, CornersAreFoundToHundredthsOfAPixel) {
  const BoardSpec board = BoardSpec::Parse("checkerboard:9x6:0.04", "test");
  const std::vector<Eigen::Vector3d> all = board.Corners();
  for (const CameraModel model : {CameraModel::kPinhole, CameraModel::kRadTan}) {
    const CameraCalibration camera = ExampleCamera(model);
    const BoardRenderer renderer(camera);
    double sum = 0.0;
    int corners = 0;
    for (const SE3d& view : BoardViews(camera, board, 8, 3)) {
      const std::optional<BoardDetection> d = DetectBoard(Gray8View(renderer.Render(board, view, 1.0, 5)), board);
      ASSERT_TRUE(d.has_value());
      // A checkerboard's corners are numbered from either end: the numbering that fits.
      const bool half_turn = WorstCornerPx(*d, board, camera, view, true) < WorstCornerPx(*d, board, camera, view);
      for (size_t i = 0; i < d->ids.size(); ++i) {
        const int id = half_turn ? board.NumCorners() - 1 - d->ids[i] : d->ids[i];
        sum += (camera.Project(view * all[id]) - Eigen::Vector2d(d->corners[i].x, d->corners[i].y)).squaredNorm();
        ++corners;
      }
    }
    const double rms = std::sqrt(sum / corners);
    std::printf("%s: %d corners within %.4f px RMS\n", CameraModelName(model).c_str(), corners, rms);
    EXPECT_LT(rms, 0.03) << CameraModelName(model);
  }
}

TEST(DetectBoard, FindsEveryCornerWhereTheCameraSeesIt) {
  const CameraCalibration camera = ExampleCamera(CameraModel::kPinhole);
  const BoardRenderer renderer(camera);
  for (const char* spec : {"checkerboard:9x6:0.04", "charuco:8x6:0.04:0.03:DICT_4X4_50"}) {
    const BoardSpec board = BoardSpec::Parse(spec, "test");
    const SE3d view = BoardViews(camera, board, 1, 3)[0];
    const Image<uint8_t> image = renderer.Render(board, view, 1.0, 5);
    const std::optional<BoardDetection> d = DetectBoard(Gray8View(image), board);
    ASSERT_TRUE(d.has_value()) << spec;
    // A checkerboard whole; a ChArUco board's view may leave part of it out (BoardViews): every
    // corner whose four squares around it (two with markers) lie in the image, 8 px in.
    int in_view = 0;
    for (const Eigen::Vector3d& corner : board.Corners()) {
      bool inside = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector3d p = corner + board.square_m * Eigen::Vector3d(dx, dy, 0.0);
          const Eigen::Vector2d px = camera.Project(view * p);
          inside = inside && px.x() >= 8 && px.y() >= 8 && px.x() < camera.width - 8 && px.y() < camera.height - 8;
        }
      in_view += inside;
    }
    const bool checkerboard = board.kind == BoardKind::kCheckerboard;
    if (checkerboard) {
      EXPECT_EQ(static_cast<int>(d->ids.size()), board.NumCorners()) << spec;
    }
    EXPECT_GE(static_cast<int>(d->ids.size()), in_view) << spec;
    EXPECT_GE(in_view, kMinCorners) << spec;
    EXPECT_LT(std::min(WorstCornerPx(*d, board, camera, view),
                       checkerboard ? WorstCornerPx(*d, board, camera, view, true) : INFINITY),
              0.25)
        << spec;
    EXPECT_LT(d->edge_width, 3.0) << spec;
    EXPECT_GT(d->edge_width, 0.5) << spec;
  }
}

TEST(DetectBoard, FindsPartOfAChArUcoBoard) {
  const CameraCalibration camera = ExampleCamera(CameraModel::kRadTan);
  const BoardSpec board = BoardSpec::Parse("charuco:8x6:0.04:0.03:DICT_4X4_50", "test");
  const SE3d view = BoardViews(camera, board, 1, 11)[0];
  Image<uint8_t> image = BoardRenderer(camera).Render(board, view, 1.0, 5);
  // Hide the right part of the board behind a grey wall.
  const Eigen::Vector2d middle = camera.Project(view * Eigen::Vector3d(0.16, 0.12, 0.0));
  for (int y = 0; y < image.height(); ++y)
    for (int x = static_cast<int>(middle.x()); x < image.width(); ++x) image(x, y) = 120;
  const std::optional<BoardDetection> d = DetectBoard(Gray8View(image), board);
  ASSERT_TRUE(d.has_value());
  EXPECT_GE(static_cast<int>(d->ids.size()), kMinCorners);
  EXPECT_LT(static_cast<int>(d->ids.size()), board.NumCorners());
  EXPECT_LT(WorstCornerPx(*d, board, camera, view), 0.25);
  EXPECT_TRUE(std::is_sorted(d->ids.begin(), d->ids.end()));
}

TEST(DetectBoard, AChArUcoBoardIsNumberedAsOpenCvNumbersIt) {
  const BoardSpec board = BoardSpec::Parse("charuco:7x5:0.05:0.035:DICT_5X5_100", "test");
  const std::vector<cv::Point3f> opencv = CharucoBoardOf(board)->chessboardCorners;
  const std::vector<Eigen::Vector3d> ours = board.Corners();
  ASSERT_EQ(opencv.size(), ours.size());
  for (size_t i = 0; i < ours.size(); ++i)
    EXPECT_LT((Eigen::Vector3d(opencv[i].x, opencv[i].y, opencv[i].z) - ours[i]).norm(), 1e-6) << i;
}

TEST(BoardSpec, ReadsBothKindsAndNamesWhatIsWrong) {
  const BoardSpec c = BoardSpec::Parse("charuco:8x6:0.04:0.03:dict_4x4_50", "--board");
  EXPECT_EQ(c.kind, BoardKind::kCharuco);
  EXPECT_EQ(c.dictionary, "DICT_4X4_50");
  EXPECT_EQ(c.NumCorners(), 7 * 5);
  EXPECT_EQ(c.ToString(), "charuco:8x6:0.04:0.03:DICT_4X4_50");
  EXPECT_EQ(BoardSpec::Parse("charuco:5x5:0.04:0.03:APRILTAG_36h11", "--board").dictionary, "DICT_APRILTAG_36h11");
  const auto message = [](const char* spec) { return testing::MessageOf([&] { BoardSpec::Parse(spec, "--board"); }); };
  EXPECT_NE(message("charuco:8x6:0.04:0.03:DICT_9X9_50").find("no ArUco dictionary 'DICT_9X9_50'"), std::string::npos);
  EXPECT_NE(message("charuco:8x6:0.04:0.05:DICT_4X4_50").find("MARKER_M < SQUARE_M"), std::string::npos);
  EXPECT_NE(message("charuco:20x12:0.04:0.03:DICT_4X4_50").find("120 markers, DICT_4X4_50 only 50"),
            std::string::npos);
  EXPECT_NE(message("charuco:3x6:0.04:0.03:DICT_4X4_50").find("3..100 inner corners"), std::string::npos);
  EXPECT_NE(message("charuco:8x6:0.04").find("charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT"), std::string::npos);
}

}  // namespace
}  // namespace dsm
