// SPDX-License-Identifier: MIT
#include "dsm/calibration/charuco.h"

#include "dsm/util/check.h"

namespace dsm {

cv::Ptr<cv::aruco::CharucoBoard> CharucoBoardOf(const BoardSpec& board) {
  DSM_CHECK(board.kind == BoardKind::kCharuco, "CharucoBoardOf: not a ChArUco board");
  return cv::aruco::CharucoBoard::create(board.cols, board.rows, static_cast<float>(board.square_m),
                                         static_cast<float>(board.marker_m),
                                         cv::aruco::getPredefinedDictionary(board.dictionary_id));
}

}  // namespace dsm
