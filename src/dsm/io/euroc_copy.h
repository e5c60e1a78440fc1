// SPDX-License-Identifier: MIT
// A EuRoC dataset folder that shares the images of another one and stores its ground truth under a
// chosen reading (camera vs body rows, Hamilton vs JPL quaternions), as files from other sources
// do (tests); with defects, a damaged copy of a recording (`dsm damage`).
#pragma once

#include <filesystem>
#include <string>

#include "dsm/io/dataset.h"

namespace dsm {

// Writes `dst`/mav0 with the first `frames` frames of the EuRoC dataset at `src` (images linked,
// not copied) and its ground truth if it has one, read as documented, written back under
// `reading`. `defects` (image/defects.h, e.g. "black:100-114,corrupt:230"): those frames' images
// are written spoiled or their files damaged, in a folder of their own; frames cut are left out of
// the image list (the ground truth keeps them). Throws InputError for a folder of another format
// or a bad spec.
void WriteEurocCopy(const std::filesystem::path& src, const std::filesystem::path& dst, size_t frames,
                    const GroundTruthConvention& reading, const std::string& defects = "");

}  // namespace dsm
