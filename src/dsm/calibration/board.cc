// SPDX-License-Identifier: MIT
#include "dsm/calibration/board.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <regex>
#include <stdexcept>

#include "dsm/util/check.h"

namespace dsm {

namespace {

constexpr const char* kForms =
    "checkerboard:COLSxROWS:SQUARE_M (COLSxROWS the inner corners, e.g. checkerboard:9x6:0.04) or "
    "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT (COLSxROWS the squares, e.g. charuco:8x6:0.04:0.03:DICT_4X4_50)";

// OpenCV's predefined ArUco dictionaries in the order of cv::aruco::PREDEFINED_DICTIONARY_NAME,
// with how many markers each holds.
struct Dictionary {
  const char* name;
  int markers;
};
constexpr Dictionary kDictionaries[] = {
    {"DICT_4X4_50", 50},     {"DICT_4X4_100", 100},   {"DICT_4X4_250", 250},         {"DICT_4X4_1000", 1000},
    {"DICT_5X5_50", 50},     {"DICT_5X5_100", 100},   {"DICT_5X5_250", 250},         {"DICT_5X5_1000", 1000},
    {"DICT_6X6_50", 50},     {"DICT_6X6_100", 100},   {"DICT_6X6_250", 250},         {"DICT_6X6_1000", 1000},
    {"DICT_7X7_50", 50},     {"DICT_7X7_100", 100},   {"DICT_7X7_250", 250},         {"DICT_7X7_1000", 1000},
    {"DICT_ARUCO_ORIGINAL", 1024}, {"DICT_APRILTAG_16h5", 30}, {"DICT_APRILTAG_25h9", 35},
    {"DICT_APRILTAG_36h10", 2320}, {"DICT_APRILTAG_36h11", 587}};

std::string Upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

}  // namespace

BoardSpec BoardSpec::Parse(const std::string& text, const std::string& where) {
  static const std::string kNumber = R"(([0-9]*\.?[0-9]+(?:[eE][-+]?\d+)?))";
  static const std::regex kCheckerboard("checkerboard:(\\d+)x(\\d+):" + kNumber);
  static const std::regex kCharuco("charuco:(\\d+)x(\\d+):" + kNumber + ":" + kNumber + ":([A-Za-z0-9_]+)");
  const std::string bad = where + ": '" + text + "'";
  std::smatch m;
  BoardSpec b;
  if (std::regex_match(text, m, kCheckerboard)) {
    b.kind = BoardKind::kCheckerboard;
  } else if (std::regex_match(text, m, kCharuco)) {
    b.kind = BoardKind::kCharuco;
    const std::string dict = Upper(m[5]);
    for (int id = 0; id < static_cast<int>(std::size(kDictionaries)); ++id) {
      if (Upper(kDictionaries[id].name) == dict || Upper(kDictionaries[id].name) == "DICT_" + dict) {
        b.dictionary = kDictionaries[id].name;
        b.dictionary_id = id;
      }
    }
    if (b.dictionary_id < 0) {
      std::string names;
      for (const Dictionary& d : kDictionaries) names += std::string(names.empty() ? "" : ", ") + d.name;
      throw InputError(bad + ": no ArUco dictionary '" + std::string(m[5]) + "' (one of " + names + ")");
    }
  } else {
    throw InputError(bad + " is not a board: " + kForms);
  }
  try {
    b.cols = std::stoi(m[1]);
    b.rows = std::stoi(m[2]);
    b.square_m = std::stod(m[3]);
    if (b.kind == BoardKind::kCharuco) b.marker_m = std::stod(m[4]);
  } catch (const std::out_of_range&) {
    throw InputError(bad + ": a number out of range");
  }
  if (b.CornerCols() < 3 || b.CornerRows() < 3 || b.cols > 100 || b.rows > 100)
    throw InputError(bad + ": a board has 3..100 inner corners each way (a ChArUco board one square more)");
  if (b.kind == BoardKind::kCheckerboard && b.cols == b.rows)
    throw InputError(bad + ": a square grid of corners has no orientation; use a board with different counts each "
                     "way (e.g. 9x6), or a ChArUco board");
  if (!(b.square_m > 0.0) || b.square_m > 10.0) throw InputError(bad + ": the square size is 0..10 m");
  if (b.kind == BoardKind::kCharuco) {
    if (!(b.marker_m > 0.0) || b.marker_m >= b.square_m)
      throw InputError(bad + ": a marker is smaller than its square (MARKER_M < SQUARE_M)");
    const int markers = b.cols * b.rows / 2;
    if (markers > kDictionaries[b.dictionary_id].markers)
      throw InputError(bad + ": the board has " + std::to_string(markers) + " markers, " + b.dictionary + " only " +
                       std::to_string(kDictionaries[b.dictionary_id].markers));
  }
  return b;
}

std::string BoardSpec::ToString() const {
  char s[160];
  if (kind == BoardKind::kCharuco)
    std::snprintf(s, sizeof(s), "charuco:%dx%d:%g:%g:%s", cols, rows, square_m, marker_m, dictionary.c_str());
  else
    std::snprintf(s, sizeof(s), "checkerboard:%dx%d:%g", cols, rows, square_m);
  return s;
}

std::vector<Eigen::Vector3d> BoardSpec::Corners() const {
  const double origin = kind == BoardKind::kCharuco ? square_m : 0.0;
  std::vector<Eigen::Vector3d> out;
  for (int j = 0; j < CornerRows(); ++j)
    for (int i = 0; i < CornerCols(); ++i) out.emplace_back(origin + i * square_m, origin + j * square_m, 0.0);
  return out;
}

Eigen::Vector4d BoardSpec::Extent() const {
  if (kind == BoardKind::kCharuco) return {0.0, cols * square_m, 0.0, rows * square_m};
  return {-square_m, cols * square_m, -square_m, rows * square_m};
}

}  // namespace dsm
