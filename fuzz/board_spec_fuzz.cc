// SPDX-License-Identifier: MIT
// Calibration board specs (`dsm calibrate --board`, `dsm synth --board`): BoardSpec::Parse, then
// what an accepted board promises: its corners, its spec written back parses to the same board,
// and a ChArUco board is one OpenCV builds with as many corners.
#include <string>

#include "dsm/calibration/board.h"
#include "dsm/calibration/charuco.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dsm::BoardSpec board;
  try {
    board = dsm::BoardSpec::Parse(std::string(reinterpret_cast<const char*>(data), size), "--board");
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
    return 0;
  }
  DSM_CHECK(board.CornerCols() >= 3 && board.CornerRows() >= 3 && board.cols <= 100 && board.rows <= 100,
            "accepted a board out of bounds");
  DSM_CHECK(static_cast<int>(board.Corners().size()) == board.NumCorners(), "corners miscounted");
  const dsm::BoardSpec again = dsm::BoardSpec::Parse(board.ToString(), "--board");
  DSM_CHECK(again.kind == board.kind && again.cols == board.cols && again.rows == board.rows &&
                again.dictionary_id == board.dictionary_id,
            "the spec written back is another board");
  if (board.kind == dsm::BoardKind::kCharuco)
    DSM_CHECK(static_cast<int>(dsm::CharucoBoardOf(board)->chessboardCorners.size()) == board.NumCorners(),
              "OpenCV's board has other corners");
  dsm::fuzz::Report("accepted: " + board.ToString());
  return 0;
}
