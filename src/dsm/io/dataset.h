// SPDX-License-Identifier: MIT
// A dataset: frames in time order, the camera calibration and, when present, ground truth
// (world_from_cam camera poses) and photometric calibration. Formats, detected from the layout:
//   euroc     mav0/cam0/data.csv, sensor.yaml, state_groundtruth_estimate0/data.csv (body poses,
//             converted to camera poses with T_BS; see GroundTruthConvention)
//   tum-mono  times.txt (id, seconds, exposure ms), camera.txt, images/ or images.zip,
//             pcalib.txt, vignette.png
//   tum-rgbd  rgb.txt, groundtruth.txt, camera.yaml (or the published Freiburg 1/2/3 intrinsics)
//   kitti     image_0/, times.txt, calib.txt, poses.txt or ../../poses/<sequence>.txt
//   folder    images/, camera.yaml, optional times.txt, groundtruth.tum, pcalib.txt, vignette.png
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/geometry/undistorter.h"
#include "dsm/io/image_store.h"
#include "dsm/photometric/photometric_calibration.h"

namespace dsm {

struct FrameRecord {
  int64_t t_ns = 0;
  std::string image;         // Name inside the image store.
  double exposure_ms = 0.0;  // 0 when unknown.
};

// A frame whose size differs from the calibration's: the message names the image and both sizes.
class ImageSizeError : public InputError {
 public:
  using InputError::InputError;
};

// A recording whose container is damaged where a frame is (a chunk that does not decompress, an
// index that points outside the file): the frames after it cannot be trusted to come, so a run
// stops there (with its outputs written) instead of skipping the frame.
class DamagedRecordingError : public InputError {
 public:
  using InputError::InputError;
};

enum class LineDelaySource { kUnknown, kCalibration, kOption, kEstimated };
std::string LineDelaySourceName(LineDelaySource source);  // unknown, calibration, option, estimated

struct Dataset {
  std::string format;
  std::filesystem::path root;
  CameraCalibration camera;
  // The file `camera` was read from (empty when it was not read from a file: a Freiburg camera
  // of the TUM RGB-D benchmark, KITTI's calibration sized from the first image).
  std::filesystem::path calibration_file;
  UndistortMode undistort_mode = UndistortMode::kCrop;
  // Rolling shutter: microseconds between two rows' exposures; 0: a global shutter. A frame's
  // timestamp is its first row's. Where it comes from: the calibration (camera.yaml's
  // line_delay_us), an option (dsm run --line-delay-us), an estimate from the recording
  // (run/line_delay_estimate.h), or nowhere yet (kUnknown: the calibration does not say; the
  // value is then 0).
  double line_delay_us = 0.0;
  LineDelaySource line_delay_source = LineDelaySource::kUnknown;
  std::vector<FrameRecord> frames;  // Strictly increasing timestamps.
  Trajectory ground_truth;          // world_from_cam; empty when the dataset has none.
  std::optional<PhotometricCalibration> photometric;
  std::shared_ptr<const ImageStore> images;
  // Rendered depth (folder format, `depth/<image stem>.tiff`); empty when the dataset has none.
  std::filesystem::path depth_dir;

  size_t size() const { return frames.size(); }
  bool HasGroundTruth() const { return !ground_truth.empty(); }
  bool HasExposure() const;
  bool HasDepth() const { return !depth_dir.empty(); }

  // Frame i as 8-bit grey; throws InputError naming the file when it is unreadable, and
  // ImageSizeError when its size differs from the calibration.
  Image<uint8_t> LoadImage(size_t i) const;
  // Frame i's file brought into memory in the background, ahead of its LoadImage (ImageStore).
  void PrefetchImage(size_t i) const;
  // Depth of frame i in metres along the optical axis (0: nothing hit), in the calibration's
  // (distorted) pixels; throws InputError naming the file when it is missing or unreadable.
  Image<float> LoadDepth(size_t i) const;
};

// How the rows of a EuRoC ground-truth file are read. The ASL layout documents body (IMU) poses with
// Hamilton quaternions q = (w, x, y, z) of world_from_body:
//   kBody     world_from_cam = row * T_BS
//   kCamera   world_from_cam = row                (an export of camera poses)
//   kJpl      the quaternion is in the JPL sense, i.e. the conjugate: the row's rotation is R(q)^T
// `dsm gt-check` tells from the images which reading a dataset needs (eval/ground_truth_check.h).
enum class GtFrame { kBody, kCamera };
enum class GtQuaternion { kHamilton, kJpl };
struct GroundTruthConvention {
  GtFrame frame = GtFrame::kBody;
  GtQuaternion quaternion = GtQuaternion::kHamilton;
  bool IsDefault() const { return frame == GtFrame::kBody && quaternion == GtQuaternion::kHamilton; }
  std::string Name() const;  // "body-hamilton", "camera-jpl", ...
};
// Every reading, default first.
std::vector<GroundTruthConvention> AllGroundTruthConventions();
// Parses "body" | "camera" and "hamilton" | "jpl"; throws InputError naming `where`.
GtFrame ParseGtFrame(const std::string& name, const std::string& where);
GtQuaternion ParseGtQuaternion(const std::string& name, const std::string& where);

// Opens the dataset at `path`, detecting its format. Throws InputError with a message naming the
// path and what is missing or malformed. A non-default `gt` is only accepted for EuRoC datasets
// (the other formats store camera poses with Hamilton quaternions).
Dataset OpenDataset(const std::filesystem::path& path, const GroundTruthConvention& gt = {});

// Human-readable summary (what `dsm info` prints). The second form describes the undistortion of
// an undistorter already built for the dataset's camera and mode.
std::string DescribeDataset(const Dataset& dataset);
std::string DescribeDataset(const Dataset& dataset, const Undistorter& undistorter);

// Readers of the single formats (used by OpenDataset).
Dataset ReadEuroc(const std::filesystem::path& mav0, const GroundTruthConvention& gt = {});

// Writes camera poses `world_from_cam` as the rows of a EuRoC ground-truth CSV under the reading
// `gt` (the inverse of ReadEuroc's conversion): body rows are world_from_cam * body_from_cam^-1,
// JPL rows store the conjugate quaternion. Throws InputError when the file cannot be written.
void WriteEurocGroundTruth(const std::filesystem::path& csv, const Trajectory& world_from_cam,
                           const SE3d& body_from_cam, const GroundTruthConvention& gt = {});
Dataset ReadTumMono(const std::filesystem::path& root);
Dataset ReadTumRgbd(const std::filesystem::path& root);
Dataset ReadKitti(const std::filesystem::path& root);
Dataset ReadFolder(const std::filesystem::path& root);

// Frames from a times file whose rows pair one to one with the sorted image `names`:
// the timestamp in column `stamp_column` (units of `unit_ns`), the exposure in ms in
// `exposure_column` when the row has it (-1: never). Throws InputError naming the file and line.
struct TimesFormat {
  size_t stamp_column = 0;
  int64_t unit_ns = 1;
  int exposure_column = -1;
  std::string row_description;  // For messages, e.g. "timestamp_ns [exposure_ms]".
};
std::vector<FrameRecord> ReadTimesFile(const std::filesystem::path& times, const std::vector<std::string>& names,
                                       const TimesFormat& format);

// Checks the frames are non-empty with strictly increasing stamps; throws InputError naming `source`.
void ValidateFrames(const std::vector<FrameRecord>& frames, const std::string& source);

}  // namespace dsm
