// SPDX-License-Identifier: MIT
#include "dsm/calibration/board.h"

#include <cmath>
#include <cstdio>
#include <regex>

#include "dsm/util/check.h"

namespace dsm {

BoardSpec BoardSpec::Parse(const std::string& text, const std::string& where) {
  static const std::regex kCheckerboard(R"(checkerboard:(\d+)x(\d+):([0-9]*\.?[0-9]+(?:[eE][-+]?\d+)?))");
  std::smatch m;
  if (!std::regex_match(text, m, kCheckerboard)) {
    throw InputError(where + ": '" + text +
                     "' is not a board: checkerboard:COLSxROWS:SQUARE_M, COLSxROWS the inner corners (e.g. "
                     "checkerboard:9x6:0.04)");
  }
  BoardSpec b;
  b.cols = std::stoi(m[1]);
  b.rows = std::stoi(m[2]);
  b.square_m = std::stod(m[3]);
  if (b.cols < 3 || b.rows < 3 || b.cols > 100 || b.rows > 100)
    throw InputError(where + ": '" + text + "': a board has 3..100 inner corners each way");
  if (b.cols == b.rows)
    throw InputError(where + ": '" + text + "': a square grid of corners has no orientation; use a board with "
                     "different counts each way (e.g. 9x6)");
  if (!(b.square_m > 0.0) || b.square_m > 10.0) throw InputError(where + ": '" + text + "': the square size is 0..10 m");
  return b;
}

std::string BoardSpec::ToString() const {
  char s[96];
  std::snprintf(s, sizeof(s), "checkerboard:%dx%d:%g", cols, rows, square_m);
  return s;
}

std::vector<Eigen::Vector3d> BoardSpec::Corners() const {
  std::vector<Eigen::Vector3d> out;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) out.emplace_back(i * square_m, j * square_m, 0.0);
  return out;
}

int BoardSpec::Colour(double x, double y) const {
  // Squares k = floor(x / s) from -1 (before the first corner) to cols - 1 (after the last).
  const double u = x / square_m, v = y / square_m;
  if (u < -2.0 || v < -2.0 || u >= cols + 1.0 || v >= rows + 1.0) return -1;
  const int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
  if (i < -1 || j < -1 || i >= cols || j >= rows) return 0;  // The white margin.
  return ((i + j) & 1) == 0 ? 1 : 0;
}

}  // namespace dsm
