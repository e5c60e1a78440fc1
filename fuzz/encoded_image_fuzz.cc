// SPDX-License-Identifier: MIT
// Image files of a recording, as every frame is read: DecodeGray8 runs the integrity check
// (encoded_image_check.h), the header check (image_header.h), then the decoder.
#include <vector>

#include "dsm/io/image_io.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  try {
    const dsm::Image<uint8_t> image = dsm::DecodeGray8(bytes, "fuzz input");
    DSM_CHECK(image.width() > 0 && image.height() > 0, "an empty image was decoded without an error");
    dsm::fuzz::Report("accepted");
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
  }
  return 0;
}
