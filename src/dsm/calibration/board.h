// SPDX-License-Identifier: MIT
// A planar calibration target: a checkerboard of `cols` x `rows` inner corners, `square_m` metres
// apart. The board's frame has its origin at the first inner corner, x along a row of corners
// (cols of them), y down the columns (rows of them), z into the board: corner (i, j) is at
// (i square_m, j square_m, 0), listed row by row as OpenCV's detector orders them.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dsm {

struct BoardSpec {
  int cols = 0, rows = 0;  // Inner corners.
  double square_m = 0.0;
  // Parses "checkerboard:COLSxROWS:SQUARE_M" (e.g. "checkerboard:9x6:0.04"); throws InputError
  // naming `where` otherwise.
  static BoardSpec Parse(const std::string& text, const std::string& where);
  std::string ToString() const;
  int NumCorners() const { return cols * rows; }
  std::vector<Eigen::Vector3d> Corners() const;  // In the board's frame, row by row.
  // Whether the point (x, y) of the board's plane lies on a dark square; the board's squares
  // extend one square beyond the inner corners on every side, with a white margin of another square.
  // -1: outside the board (margin or beyond), 0: white, 1: black.
  int Colour(double x, double y) const;
};

}  // namespace dsm
