// SPDX-License-Identifier: MIT
// Defect specs (`dsm synth --defects`, `dsm damage --defects`): ParseDefects, then the defects
// applied as those commands apply them, to a small image and a small file at each spec's ends.
#include <string>
#include <vector>

#include "dsm/image/defects.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<dsm::Defect> defects;
  try {
    defects = dsm::ParseDefects(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
    return 0;
  }
  // Accepted: frame indices in order, within the bound the parser promises.
  const std::filesystem::path file = dsm::fuzz::Scratch() / "frame.bin";
  for (const dsm::Defect& d : defects) {
    DSM_CHECK(d.first >= 0 && d.first <= d.last && d.last <= 1000000, "accepted a range out of order or bounds");
    for (int frame : {d.first, d.last}) {
      dsm::Image<uint8_t> image(16, 8);
      for (size_t i = 0; i < image.size(); ++i) image.data()[i] = static_cast<uint8_t>(i * 7);
      dsm::ApplyImageDefects(defects, frame, 1, &image);
      dsm::fuzz::WriteFile(file, "0123456789abcdef");
      dsm::ApplyFileDefects(defects, frame, file);
      DSM_CHECK(dsm::IsCut(defects, frame) || d.kind != dsm::DefectKind::kCut, "a cut frame is not cut");
    }
  }
  dsm::fuzz::Report("accepted: " + std::to_string(defects.size()) + " defects");
  return 0;
}
