// SPDX-License-Identifier: MIT
// OpenCV's ChArUco board (the aruco module of opencv_contrib) for a board of kind kCharuco: its
// inner corners are numbered as BoardSpec::Corners lists them.
#pragma once

#include <opencv2/aruco/charuco.hpp>

#include "dsm/calibration/board.h"

namespace dsm {

cv::Ptr<cv::aruco::CharucoBoard> CharucoBoardOf(const BoardSpec& board);

}  // namespace dsm
