// SPDX-License-Identifier: MIT
// A calibration board rendered as a camera of any model sees it (camera.h), so that tests of the
// calibration know the answer: each pixel averages 4 x 4 rays spread over its area, 16 x 16 where
// an edge crosses it (from its corners' rays, CameraCalibration::Unproject once per camera), each
// intersected with the board's plane: black
// 40 or white 210 where they hit the board (a ChArUco board as OpenCV draws it) or its white margin
// of a square, a grey 120 wall beyond; then the synthetic world's image formation
// (synth::FormImage: Gaussian noise, 8-bit quantisation).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "dsm/calibration/board.h"
#include "dsm/geometry/camera.h"
#include "dsm/image/image.h"
#include "dsm/lie/se3.h"
#include "dsm/synth/lens_rays.h"

namespace dsm {

// A camera of `model` as the tests and `dsm synth --board` use it: 640x480, fx 420 (300 for the
// wide models), its principal point off the centre, the distortion of a typical lens.
CameraCalibration ExampleCamera(CameraModel model);

class BoardRenderer {
 public:
  explicit BoardRenderer(const CameraCalibration& camera);  // Unprojects every pixel corner's ray once.
  Image<uint8_t> Render(const BoardSpec& board, const SE3d& cam_from_board, double noise_sigma, uint32_t seed) const;

 private:
  synth::LensRays lens_;
};

// `count` views of the board as a person calibrating takes them: the board 0.35..0.75 of the
// image's width across, its centre anywhere in the image (a checkerboard's corners all within it,
// two thirds of a ChArUco board's), tilted up to 45 deg about both of its axes and turned up to
// 20 deg in its plane. Deterministic in `seed`.
std::vector<SE3d> BoardViews(const CameraCalibration& camera, const BoardSpec& board, int count, uint32_t seed);

// A folder dataset (io/folder_dataset.h) of the views: images/, times.txt (10 Hz) and
// camera.yaml with `camera`, the truth a calibration should find.
void WriteBoardSequence(const std::filesystem::path& dir, const CameraCalibration& camera, const BoardSpec& board,
                        int count, uint32_t seed);

}  // namespace dsm
