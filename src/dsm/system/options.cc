// SPDX-License-Identifier: MIT
#include "dsm/system/options.h"

#include "dsm/util/check.h"

namespace dsm {

MapMode ParseMapMode(const std::string& name, const std::string& where) {
  if (name == "dsm") return MapMode::kFull;
  if (name == "sw") return MapMode::kSlidingWindow;
  throw InputError(where + ": expected dsm or sw, got '" + name + "'");
}

std::string MapModeName(MapMode mode) { return mode == MapMode::kSlidingWindow ? "sw" : "dsm"; }

void RelocalisationOptions::Validate() const {
  if (candidates < 0 || candidates > 50) throw InputError("relocalisation.candidates must be within 0..50");
  if (max_lost_frames < 0) throw InputError("relocalisation.max_lost_frames must be non-negative (0: never a new map)");
  if (max_predicted_frames < 0) throw InputError("relocalisation.max_predicted_frames must be non-negative");
  if (young_map_frames < 0) throw InputError("relocalisation.young_map_frames must be non-negative");
}

bool SystemOptions::YoungMapBaDue(int keyframes) const {
  if (mode != MapMode::kFull || keyframes < young_map_ba_first || keyframes > young_map_ba_last) return false;
  for (int n = young_map_ba_first; n <= keyframes; n *= 2)
    if (n == keyframes) return true;
  return false;
}

void LoopClosureOptions::Validate() const {
  if (consistent_keyframes < 1 || consistent_keyframes > 20)
    throw InputError("loop_closure.consistent_keyframes must be within 1..20");
  if (min_inliers < 6) throw InputError("loop_closure.min_inliers must be at least 6");
}

void SystemSetup::Validate() const {
  if (!(line_delay_s >= 0.0 && line_delay_s < 1e-3)) throw InputError("the line delay must be within 0..1000 us");
}

void SystemOptions::Validate() const {
  if (pyramid_levels < 1 || pyramid_levels > 6) throw InputError("pyramid_levels must be within 1..6");
  if (max_initialization_frames < 5) throw InputError("max_initialization_frames must be at least 5");
  if (interpolation != "auto" && interpolation != "bilinear" && interpolation != "bspline")
    throw InputError("system.interpolation must be auto, bilinear or bspline, not '" + interpolation + "'");
  if (!(texture_loss_min_noise >= 0.0)) throw InputError("system.texture_loss_min_noise must be non-negative");
  if (young_map_ba_first < 2) throw InputError("system.young_map_ba_first must be at least 2");
  if (young_map_ba_last < 0) throw InputError("system.young_map_ba_last must be non-negative (0: none)");
  if (loop_ba_min_gap < 0) throw InputError("system.loop_ba_min_gap must be non-negative (0: none)");
  if (loop_ba_after_relocalisation < 0)
    throw InputError("system.loop_ba_after_relocalisation must be non-negative (0: never)");
  if (seam_ba_count < 0) throw InputError("system.seam_ba_count must be non-negative (0: never)");
  if (seam_ba_step < 1) throw InputError("system.seam_ba_step must be at least 1");
  if (seam_ba_before < 0) throw InputError("system.seam_ba_before must be non-negative");
  if (rejoin_min_outliers < 0) throw InputError("system.rejoin_min_outliers must be non-negative (0: never)");
  if (loop_ba_max_keyframes < 2) throw InputError("system.loop_ba_max_keyframes must be at least 2");
  if (loop_ba_max_iterations < 0) throw InputError("system.loop_ba_max_iterations must be non-negative (0: as pba)");
  if (tracker.levels > pyramid_levels) throw InputError("tracker.levels cannot exceed pyramid_levels");
  if (pba.levels > pyramid_levels) throw InputError("pba.levels cannot exceed pyramid_levels");
  initializer.Validate();
  tracker.Validate();
  candidates.Validate();
  activation.Validate();
  keyframe.Validate();
  quality.Validate();
  relocalisation.Validate();
  loop_closure.Validate();
  window.Validate();
  occlusion.Validate();
  pba.Validate();
}

}  // namespace dsm
