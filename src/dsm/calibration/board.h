// SPDX-License-Identifier: MIT
// A planar calibration target, one of
//   checkerboard:COLSxROWS:SQUARE_M            COLSxROWS inner corners, SQUARE_M metres apart;
//   charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT   COLSxROWS squares (OpenCV's ChArUco board, as its
//                                              board generator draws it: the top-left square black,
//                                              an ArUco marker of MARKER_M metres from dictionary
//                                              DICT, e.g. DICT_4X4_50, in each white square).
// The board's frame: z into the board, x along a row of corners, y down the columns. A
// checkerboard's origin is its first inner corner; a ChArUco board's is the outer corner of its
// first square, so its inner corner (i, j) is at ((i + 1) SQUARE_M, (j + 1) SQUARE_M) as in
// OpenCV's CharucoBoard. Corners are listed (and numbered) row by row.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dsm {

enum class BoardKind { kCheckerboard, kCharuco };

struct BoardSpec {
  BoardKind kind = BoardKind::kCheckerboard;
  int cols = 0, rows = 0;  // Checkerboard: inner corners; ChArUco: squares.
  double square_m = 0.0;
  double marker_m = 0.0;       // ChArUco only.
  std::string dictionary;      // ChArUco only: OpenCV's name, e.g. "DICT_4X4_50".
  int dictionary_id = -1;      // Its cv::aruco::PREDEFINED_DICTIONARY_NAME.

  // Parses either form above; throws InputError naming `where` otherwise.
  static BoardSpec Parse(const std::string& text, const std::string& where);
  std::string ToString() const;
  int CornerCols() const { return kind == BoardKind::kCharuco ? cols - 1 : cols; }
  int CornerRows() const { return kind == BoardKind::kCharuco ? rows - 1 : rows; }
  int NumCorners() const { return CornerCols() * CornerRows(); }
  std::vector<Eigen::Vector3d> Corners() const;  // In the board's frame, row by row.
  // The printed area, [min, max] in x and y of the board's frame: a checkerboard's squares reach
  // one square beyond its inner corners, a ChArUco board is its squares.
  Eigen::Vector4d Extent() const;
  // The white margin between a ChArUco square's edge and its marker, as a share of the square.
  double MarkerMargin() const { return kind == BoardKind::kCharuco ? 0.5 * (square_m - marker_m) / square_m : 0.5; }
};

}  // namespace dsm
