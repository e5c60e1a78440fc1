// SPDX-License-Identifier: MIT
// The generic folder format, which `dsm synth` writes and a user with their own camera fills:
//   camera.yaml        see calibration_io.h
//   images/            the frames, any common image format, in name order
//   times.txt          optional, one row per image in name order: "timestamp_ns [exposure_ms]"
//                      (without it frame i is at i / rate_hz seconds)
//   groundtruth.tum    optional, world_from_cam poses in TUM format
//   pcalib.txt, vignette.png   optional photometric calibration
//   depth/             optional per-frame depth (32-bit float TIFF, metres along the optical axis)
#pragma once

#include <filesystem>

#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"

namespace dsm {

// Writes times.txt for `frames`.
void WriteFolderTimes(const std::filesystem::path& root, const std::vector<FrameRecord>& frames);

// Image file name of frame i ("000042.png").
std::string FolderImageName(size_t i);

}  // namespace dsm
