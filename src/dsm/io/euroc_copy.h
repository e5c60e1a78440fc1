// SPDX-License-Identifier: MIT
// Test helper: a EuRoC dataset folder that shares the images of another one and stores its ground
// truth under a chosen reading (camera vs body rows, Hamilton vs JPL quaternions), as files from
// other sources do.
#pragma once

#include <filesystem>
#include <string>

#include "dsm/io/dataset.h"

namespace dsm::testing {

// Writes `dst`/mav0 with the first `frames` frames of the EuRoC dataset at `src` (images linked,
// not copied) and its ground truth, read as documented, written back under `reading`. `defects`
// (synth/defects.h, e.g. "black:100-114,corrupt:230"): those frames' images are written spoiled
// or their files damaged, in a folder of their own.
void WriteEurocCopy(const std::filesystem::path& src, const std::filesystem::path& dst, size_t frames,
                    const GroundTruthConvention& reading, const std::string& defects = "");

}  // namespace dsm::testing
