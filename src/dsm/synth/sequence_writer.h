// SPDX-License-Identifier: MIT
// Renders a synthetic sequence into the generic folder format (see io/folder_dataset.h).
#pragma once

#include <filesystem>
#include <functional>

#include "dsm/synth/scenes.h"

namespace dsm::synth {

struct WriteSummary {
  size_t frames = 0;
  double render_ms_mean = 0.0;  // Ray casting per frame on one core.
  double path_length_m = 0.0;
};

// Writes camera.yaml, images/, times.txt (with exposure), groundtruth.tum, vignette.png (when
// options.vignette > 0) and depth/ (when options.depth). `progress` is called after each frame.
WriteSummary WriteSequence(const SynthSequence& sequence, const SynthOptions& options,
                           const std::filesystem::path& out_dir,
                           const std::function<void(size_t done, size_t total)>& progress = {});

}  // namespace dsm::synth
