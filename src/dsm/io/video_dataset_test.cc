// SPDX-License-Identifier: MIT
#include "dsm/io/video_dataset.h"

#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/videoio.hpp>

#include "dsm/io/calibration_io.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

constexpr int kWidth = 64, kHeight = 48, kFrames = 12;

// Grey level of pixel (x, y) in frame i: distinct per frame, smooth enough for any codec.
uint8_t Grey(int i, int x, int y) { return static_cast<uint8_t>(20 + 10 * i + x + y); }

// A lossless (FFV1) 20 Hz video of kFrames frames, and its camera.yaml.
struct VideoFiles {
  fs::path video, yaml;
};
VideoFiles WriteVideo(const std::string& name) {
  const fs::path dir = ScratchDir(name);
  VideoFiles f{dir / "clip.mkv", dir / "camera.yaml"};
  cv::VideoWriter writer(f.video.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('F', 'F', 'V', '1'), 20.0,
                         cv::Size(kWidth, kHeight), true);
  EXPECT_TRUE(writer.isOpened());
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat frame(kHeight, kWidth, CV_8UC3);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) frame.at<cv::Vec3b>(y, x) = cv::Vec3b::all(Grey(i, x, y));
    writer.write(frame);
  }
  writer.release();
  CameraYaml camera;
  camera.camera.model = CameraModel::kPinhole;
  camera.camera.width = kWidth;
  camera.camera.height = kHeight;
  camera.camera.fx = camera.camera.fy = 50;
  camera.camera.cx = 31.5;
  camera.camera.cy = 23.5;
  WriteCameraYaml(f.yaml, camera);
  return f;
}

std::string ErrorOf(const fs::path& video, const VideoInput& input) {
  try {
    OpenVideo(video, input);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Video, FramesTimesAndPixelsFromTheContainer) {
  const VideoFiles f = WriteVideo("video_frames");
  const Dataset d = OpenVideo(f.video, {f.yaml, {}, 0.0});
  EXPECT_EQ(d.format, "video");
  ASSERT_EQ(d.size(), static_cast<size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) EXPECT_EQ(d.frames[i].t_ns, 50'000'000LL * i) << i;
  EXPECT_FALSE(d.HasGroundTruth());
  // In order, then backwards (the video is reopened), then skipping ahead.
  for (int i : {0, 1, 2, 7, 3, 11}) {
    const Image<uint8_t> image = d.LoadImage(i);
    ASSERT_EQ(image.width(), kWidth);
    ASSERT_EQ(image.height(), kHeight);
    for (auto [x, y] : {std::pair{0, 0}, {63, 47}, {10, 30}}) EXPECT_EQ(image(x, y), Grey(i, x, y)) << i;
  }
}

TEST(Video, TimeOffsetAndGroundTruth) {
  const VideoFiles f = WriteVideo("video_offset");
  Trajectory gt;
  for (int i = 0; i < kFrames; ++i) gt.Add(1'600'000'000'000'000'000LL + 50'000'000LL * i, SE3d());
  const fs::path gt_file = f.video.parent_path() / "gt.tum";
  WriteTumTrajectory(gt_file, gt);
  const Dataset d = OpenVideo(f.video, {f.yaml, gt_file, 1.6e9});
  EXPECT_EQ(d.frames.front().t_ns, 1'600'000'000'000'000'000LL);
  EXPECT_EQ(d.frames.back().t_ns, gt.stamps_ns.back());
  EXPECT_EQ(d.ground_truth.size(), gt.size());
}

TEST(Video, ClearErrorsNamingTheFile) {
  const VideoFiles f = WriteVideo("video_errors");
  EXPECT_NE(ErrorOf(f.video, {}).find("--calib"), std::string::npos);
  EXPECT_NE(ErrorOf(f.video.parent_path() / "none.mp4", {f.yaml, {}, 0.0}).find("none.mp4: no such video file"),
            std::string::npos);
  const fs::path junk = f.video.parent_path() / "junk.mp4";
  std::ofstream(junk) << std::string(3000, 'x');
  EXPECT_NE(ErrorOf(junk, {f.yaml, {}, 0.0}).find("junk.mp4: cannot open as a video"), std::string::npos);
  CameraYaml wide = ReadCameraYaml(f.yaml);
  wide.camera.width = 2 * kWidth;
  const fs::path wide_yaml = f.video.parent_path() / "wide.yaml";
  WriteCameraYaml(wide_yaml, wide);
  EXPECT_NE(ErrorOf(f.video, {wide_yaml, {}, 0.0}).find("frames are 64x48 but"), std::string::npos);
  EXPECT_NE(ErrorOf(f.video, {f.yaml, f.video.parent_path() / "no_gt.tum", 0.0}).find("no_gt.tum"), std::string::npos);
}

TEST(Video, FileEndings) {
  EXPECT_TRUE(IsVideoFile("a/b.mp4"));
  EXPECT_TRUE(IsVideoFile("B.MKV"));
  EXPECT_TRUE(IsVideoFile("c.avi"));
  EXPECT_FALSE(IsVideoFile("images"));
  EXPECT_FALSE(IsVideoFile("x.png"));
}

}  // namespace
}  // namespace dsm
