// SPDX-License-Identifier: MIT
#include "dsm/io/dataset.h"

#include <fstream>

#include <gtest/gtest.h>
#include <zip.h>

#include "dsm/io/euroc_copy.h"
#include "dsm/io/folder_dataset.h"
#include "dsm/io/image_io.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::SharedDataDir;
using testing::WriteText;

Image<uint8_t> Pattern(int w, int h) {
  Image<uint8_t> img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = static_cast<uint8_t>((x * 7 + y * 13) % 256);
  return img;
}

// T_BS of the shared EuRoC sequence's sensor.yaml (body_from_cam).
Eigen::Matrix4d SharedBodyFromCam() {
  Eigen::Matrix4d T_BS;
  T_BS << 0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975, 0.999557249008, 0.0149672133247,
      0.025715529948, -0.064676986768, -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949, 0, 0,
      0, 1;
  return T_BS;
}

TEST(EurocDataset, SharedSequence) {
  const Dataset d = OpenDataset(SharedDataDir() / "euroc_mh01_shake");
  EXPECT_EQ(d.format, "euroc");
  ASSERT_EQ(d.size(), 340u);
  EXPECT_EQ(d.frames.front().t_ns, 1403636584763555584LL);
  EXPECT_EQ(d.frames[1].t_ns, 1403636584813555456LL);
  EXPECT_EQ(d.camera.model, CameraModel::kRadTan);
  EXPECT_EQ(d.camera.width, 752);
  EXPECT_DOUBLE_EQ(d.camera.fx, 458.654);
  ASSERT_TRUE(d.HasGroundTruth());
  EXPECT_EQ(d.ground_truth.size(), 380u);
  EXPECT_FALSE(d.photometric.has_value());

  // The documented reading: the rows are body poses (Hamilton), and the camera pose is
  // world_from_body * T_BS, so world_from_body^-1 * world_from_cam is T_BS exactly.
  const SE3d world_from_body(Eigen::Quaterniond(0.5456446923, -0.1683940534, -0.8148495803, -0.0996768477),
                             Eigen::Vector3d(4.7042890000, -1.7647550000, 0.7783510000));
  EXPECT_EQ(d.ground_truth.stamps_ns[0], 1403636583763555584LL);
  const Eigen::Matrix4d body_from_cam = (world_from_body.Inverse() * d.ground_truth.poses[0]).Matrix();
  EXPECT_LT((body_from_cam - SharedBodyFromCam()).norm(), 1e-9);

  const Image<uint8_t> img = d.LoadImage(0);
  EXPECT_EQ(img.width(), 752);
  EXPECT_EQ(img.height(), 480);
}

// Ground truth stored under each reading (camera or body rows, Hamilton or JPL quaternions) and read
// back with that reading gives the same camera poses; read with the default reading, the copies
// that are not body-hamilton are far off.
TEST(EurocDataset, GroundTruthReadingsRoundTrip) {
  const fs::path shared = SharedDataDir() / "euroc_mh01_shake";
  const Dataset reference = OpenDataset(shared);
  for (const GroundTruthConvention& reading : AllGroundTruthConventions()) {
    const fs::path dir = ScratchDir("euroc_" + reading.Name());
    WriteEurocCopy(shared, dir, 20, reading);
    const Dataset copy = OpenDataset(dir, reading);
    EXPECT_EQ(copy.size(), 20u);
    ASSERT_EQ(copy.ground_truth.size(), reference.ground_truth.size()) << reading.Name();
    double worst = 0.0;
    for (size_t i = 0; i < copy.ground_truth.size(); ++i) {
      EXPECT_EQ(copy.ground_truth.stamps_ns[i], reference.ground_truth.stamps_ns[i]);
      worst = std::max(worst, (copy.ground_truth.poses[i].Matrix() - reference.ground_truth.poses[i].Matrix()).norm());
    }
    EXPECT_LT(worst, 1e-9) << reading.Name();
    const Dataset as_documented = OpenDataset(dir);
    const double off = (as_documented.ground_truth.poses[0].Matrix() - reference.ground_truth.poses[0].Matrix()).norm();
    if (reading.IsDefault()) {
      // The body-hamilton copy stores the shared file's own rows.
      EXPECT_LT(off, 1e-9);
      const fs::path csv = fs::path("mav0") / "state_groundtruth_estimate0" / "data.csv";
      const Trajectory original = ReadTrajectory(shared / csv, TrajectoryFormat::kEuroc);
      const Trajectory stored = ReadTrajectory(dir / csv, TrajectoryFormat::kEuroc);
      ASSERT_EQ(stored.size(), original.size());
      for (size_t i = 0; i < stored.size(); i += 37) {
        EXPECT_LT((stored.poses[i].Matrix() - original.poses[i].Matrix()).norm(), 1e-9);
      }
    } else {
      EXPECT_GT(off, 0.05) << reading.Name();
    }
  }
}

TEST(EurocDataset, GroundTruthConventionNames) {
  EXPECT_EQ((GroundTruthConvention{GtFrame::kCamera, GtQuaternion::kJpl}.Name()), "camera-jpl");
  EXPECT_EQ(AllGroundTruthConventions().size(), 4u);
  EXPECT_EQ(AllGroundTruthConventions().front().Name(), "body-hamilton");
  EXPECT_THROW(ParseGtFrame("imu", "--gt-frame"), InputError);
  EXPECT_THROW(ParseGtQuaternion("xyzw", "--gt-quaternion"), InputError);
  EXPECT_EQ(ParseGtQuaternion("jpl", "--gt-quaternion"), GtQuaternion::kJpl);
}

TEST(FolderDataset, ReadsWhatItWrites) {
  const fs::path root = ScratchDir("folder_dataset");
  fs::create_directories(root / "images");
  CameraYaml cam;
  cam.camera = {CameraModel::kPinhole, 65, 49, 50, 50, 32, 24, {}};
  WriteCameraYaml(root / "camera.yaml", cam);
  std::vector<FrameRecord> frames;
  for (size_t i = 0; i < 3; ++i) {
    WriteGray8(root / "images" / FolderImageName(i), Pattern(65, 49));
    frames.push_back({static_cast<int64_t>(1000 + 50000000 * i), FolderImageName(i), 10.0 + i});
  }
  WriteFolderTimes(root, frames);
  WriteText(root / "groundtruth.tum", "0.000001 0 0 0 0 0 0 1\n0.050001 0.1 0 0 0 0 0 1\n");
  const Dataset d = OpenDataset(root);
  EXPECT_EQ(d.format, "folder");
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d.frames[2].t_ns, 100001000);
  EXPECT_DOUBLE_EQ(d.frames[2].exposure_ms, 12.0);
  EXPECT_TRUE(d.HasExposure());
  EXPECT_EQ(d.ground_truth.size(), 2u);
  EXPECT_EQ(d.LoadImage(1)(10, 3), Pattern(65, 49)(10, 3));
  EXPECT_NE(DescribeDataset(d).find("frames:       3"), std::string::npos);
  // Camera-pose formats take no EuRoC ground-truth reading.
  EXPECT_THROW(OpenDataset(root, {GtFrame::kCamera, GtQuaternion::kJpl}), InputError);
  // An odd image size still yields a pyramid-friendly undistorted size (64 x 48).
  EXPECT_NE(DescribeDataset(d).find("pinhole 64x48"), std::string::npos);

  // Corrupt image: a clear error naming the file.
  WriteText(root / "images" / FolderImageName(1), "not a png");
  try {
    d.LoadImage(1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("000001.png"), std::string::npos) << e.what();
  }
  // Timestamps that go back in time.
  WriteText(root / "times.txt", "1000\n900\n2000\n");
  EXPECT_THROW(OpenDataset(root), InputError);
  WriteText(root / "times.txt", "1000\n2000\n");
  EXPECT_THROW(OpenDataset(root), InputError);
}

TEST(KittiDataset, OddSizeAndPoses) {
  const fs::path root = ScratchDir("kitti/sequences/05");
  fs::create_directories(root / "image_0");
  for (int i = 0; i < 2; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.png", i);
    WriteGray8(root / "image_0" / name, Pattern(1241, 376));
  }
  WriteText(root / "times.txt", "0.000000e+00\n1.036224e-01\n");
  WriteText(root / "calib.txt", "P0: 718.856 0 607.1928 0 0 718.856 185.2157 0 0 0 1 0\n");
  fs::create_directories(root.parent_path().parent_path() / "poses");
  WriteText(root.parent_path().parent_path() / "poses" / "05.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 0.8\n");
  const Dataset d = OpenDataset(root);
  EXPECT_EQ(d.format, "kitti");
  EXPECT_EQ(d.camera.width, 1241);
  EXPECT_EQ(d.frames[1].t_ns, 103622400);
  ASSERT_EQ(d.ground_truth.size(), 2u);
  EXPECT_EQ(d.ground_truth.stamps_ns[1], 103622400);
  EXPECT_NE(DescribeDataset(d).find("pinhole 1232x368"), std::string::npos);
}

TEST(TumMonoDataset, ImagesFromZipWithExposure) {
  const fs::path root = ScratchDir("tum_mono");
  WriteText(root / "camera.txt", "Pinhole 100 100 63.5 47.5 0\n128 96\ncrop\n128 96\n");
  WriteText(root / "times.txt", "00000 1.000000 10.5\n00001 1.050000 11.5\n");
  // Zip two PNGs.
  int error = 0;
  zip_t* z = zip_open((root / "images.zip").c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  ASSERT_NE(z, nullptr);
  std::vector<std::vector<char>> blobs;
  for (int i = 0; i < 2; ++i) {
    const fs::path tmp = root / ("tmp" + std::to_string(i) + ".png");
    WriteGray8(tmp, Pattern(128, 96));
    std::ifstream in(tmp, std::ios::binary);
    blobs.emplace_back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    zip_source_t* src = zip_source_buffer(z, blobs.back().data(), blobs.back().size(), 0);
    zip_file_add(z, ("0000" + std::to_string(i) + ".png").c_str(), src, ZIP_FL_OVERWRITE);
  }
  ASSERT_EQ(zip_close(z), 0);
  const Dataset d = OpenDataset(root);
  EXPECT_EQ(d.format, "tum-mono");
  ASSERT_EQ(d.size(), 2u);
  EXPECT_DOUBLE_EQ(d.frames[1].exposure_ms, 11.5);
  EXPECT_EQ(d.LoadImage(1)(5, 5), Pattern(128, 96)(5, 5));
}

TEST(TumRgbdDataset, FreiburgIntrinsicsFromTheFolderName) {
  const fs::path root = ScratchDir("rgbd_dataset_freiburg1_xyz");
  fs::create_directories(root / "rgb");
  WriteGray8(root / "rgb" / "1305031102.175304.png", Pattern(640, 480));
  WriteGray8(root / "rgb" / "1305031102.211214.png", Pattern(640, 480));
  WriteText(root / "rgb.txt", "# color images\n# timestamp filename\n1305031102.175304 rgb/1305031102.175304.png\n"
                              "1305031102.211214 rgb/1305031102.211214.png\n");
  WriteText(root / "groundtruth.txt", "# timestamp tx ty tz qx qy qz qw\n1305031102.1758 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n");
  const Dataset d = OpenDataset(root);
  EXPECT_EQ(d.format, "tum-rgbd");
  EXPECT_EQ(d.camera.model, CameraModel::kRadTan);
  EXPECT_DOUBLE_EQ(d.camera.fx, 517.3);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d.frames[1].t_ns, 1305031102211214000LL);
  EXPECT_EQ(d.ground_truth.size(), 1u);
  EXPECT_EQ(d.LoadImage(0).width(), 640);
  // Another folder name has no built-in calibration: a clear error asks for camera.yaml.
  const fs::path other = ScratchDir("my_rgbd");
  fs::copy(root, other, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  try {
    OpenDataset(other);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera.yaml"), std::string::npos);
  }
}

TEST(OpenDataset, UnknownLayoutIsAClearError) {
  const fs::path root = ScratchDir("unknown_layout");
  try {
    OpenDataset(root);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot detect"), std::string::npos);
  }
  EXPECT_THROW(OpenDataset(root / "does_not_exist"), InputError);
}

}  // namespace
}  // namespace dsm
