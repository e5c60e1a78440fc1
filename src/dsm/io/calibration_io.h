// SPDX-License-Identifier: MIT
// Calibration files of the supported dataset formats. Every reader throws InputError naming the
// file (and key or line) on a missing, malformed or implausible value.
#pragma once

#include <filesystem>
#include <optional>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/undistorter.h"
#include "dsm/lie/se3.h"
#include "dsm/photometric/photometric_calibration.h"

namespace dsm {

// Generic folder `camera.yaml`:
//   model: pinhole | radtan | equidistant | fov
//   width: 640
//   height: 480
//   intrinsics: [fx, fy, cx, cy]
//   distortion: [...]        # omitted or [] for pinhole
//   rate_hz: 20              # optional, for folders without a times file
// Unknown keys are rejected.
struct CameraYaml {
  CameraCalibration camera;
  double rate_hz = 20.0;
  // Rolling shutter: microseconds between the exposures of two consecutive rows (key
  // line_delay_us; 0: a global shutter; none: the calibration does not say, and dsm run estimates
  // it from the recording). The frame's timestamp is its first row's.
  std::optional<double> line_delay_us;
};
// Whether a rolling shutter's readout, `rows` rows `line_delay_us` apart, fits within one frame
// interval (and the delay is not negative).
inline bool ReadoutFits(double line_delay_us, int rows, double frame_interval_us) {
  return line_delay_us >= 0.0 && line_delay_us * rows <= frame_interval_us;
}
CameraYaml ReadCameraYaml(const std::filesystem::path& path);
void WriteCameraYaml(const std::filesystem::path& path, const CameraYaml& camera);

// EuRoC `sensor.yaml`: intrinsics, distortion and T_BS (body_from_cam).
struct EurocSensor {
  CameraCalibration camera;
  SE3d body_from_cam;
  double rate_hz = 20.0;
};
EurocSensor ReadEurocSensorYaml(const std::filesystem::path& path);

// TUM monoVO `camera.txt`:
//   line 1  [Model] fx fy cx cy [params]  (Model: Pinhole, RadTan, EquiDistant, KannalaBrandt, FOV;
//           5 bare numbers mean FOV; values < 1 are relative to the image size)
//   line 2  width height
//   line 3  crop | full | none | fx fy cx cy 0   (output camera)
//   line 4  output width height
struct TumMonoCamera {
  CameraCalibration camera;
  UndistortMode mode = UndistortMode::kCrop;
};
TumMonoCamera ReadTumMonoCamera(const std::filesystem::path& path);

// KITTI odometry `calib.txt`: the P0 projection matrix. Width and height come from the images.
CameraCalibration ReadKittiCalib(const std::filesystem::path& path, int width, int height);

// `pcalib.txt` (256 inverse-response values) and `vignette.png` in `folder`, when present.
std::optional<PhotometricCalibration> ReadPhotometricCalibration(const std::filesystem::path& folder);

}  // namespace dsm
