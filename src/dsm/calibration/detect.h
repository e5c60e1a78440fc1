// SPDX-License-Identifier: MIT
// A calibration board (board.h) found in one frame:
//   checkerboard: OpenCV's sector-based detector (findChessboardCornersSB, the whole board or
//     nothing); sharpness from estimateChessboardSharpness;
//   ChArUco: the ArUco markers (detectMarkers), the inner corners between them
//     (interpolateCornersCharuco), any part of the board with at least kMinCorners corners not all
//     on one line; sharpness from the profile across each edge between two neighbouring corners
//     found (ChArUcoEdgeWidth).
// Either board's corners are refined by cornerSubPix and then by their point symmetry
// (corner_symmetry.h) in a window a third of the corners' spacing and short of a ChArUco board's
// markers (unbiased by the board's tilt, as the corner's edges stay straight lines through it).
// Sharpness is the median width of the board's edges in pixels: the rise from dark to light over
// the steepest step, contrast / largest gradient (a Gaussian blur of sigma s widens it by 2.5 s).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "dsm/calibration/board.h"

namespace dsm {

struct BoardDetection {
  int frame = -1;
  // The corners found, as numbered by BoardSpec::Corners (a checkerboard's up to a half turn of
  // the board: the detector cannot always tell which end is which) ...
  std::vector<int> ids;
  std::vector<cv::Point2f> corners;  // ... and where they are in the image.
  double edge_width = 0.0;           // Pixels.
  // Where and how the board lies in the image: its centre (x, y over the image's size), size (the
  // square root of its inner corners' bounding area over the image's) and tilt (the log ratios of
  // its first to last row's and column's lengths), from the whole grid (a part's completed by its
  // homography).
  std::array<double, 5> place{};
};

constexpr int kMinCorners = 8;  // Of a ChArUco board, for a view.

std::optional<BoardDetection> DetectBoard(const cv::Mat& grey, const BoardSpec& board);

}  // namespace dsm
