// SPDX-License-Identifier: MIT
// `dsm run --debug DIR`: what the system saw and did at every keyframe, written right after the
// keyframe was mapped (so it shows the state that the next frames were tracked against).
//
//   keyframes.csv       one row per keyframe:
//     keyframe, frame, t_s              ids and time
//     tracking_rmse, inlier_ratio       the tracking of the frame that became the keyframe
//     window, covisible                 keyframes in the window, of which covisible (old)
//     points, points_created, points_culled, observations_removed, reobservations, pba_iterations
//     step, median_depth, step_over_depth
//                                       distance to the previous keyframe, median depth of the
//                                       window's points seen from this keyframe (map units), and
//                                       their ratio: the motion measured against the map's depth
//     gt_step_m, scale, scale_drift     with ground truth: the true step, step / gt_step_m (map
//                                       units per metre) and that scale over the one the map was
//                                       started with (keyframes 0 -> 1); 1 = no scale drift
//     depth_scale_drift, depth_bad_share
//                                       with rendered depth (synthetic datasets): the window's
//                                       point depths in their hosts over the true depths, as a
//                                       median relative to the start scale, and the share of
//                                       points more than 20 % off that median
//     error_sigma, error_nu, inlier_threshold
//                                       the keyframe's fitted error model (robust.h)
//     observations_texture_lost         of observations_removed, those whose target showed no
//                                       trace of the point's texture (texture_loss.h)
//   frames.csv          one row per frame read: frame, map (0 the first, 1 the next, ...),
//                       status (initializing | ok | lost | skipped), keyframe and relocalised
//                       (0 | 1; the map's first keyframe, the start's reference frame, is not
//                       marked: its row was written while the map was still initialising),
//                       tracking_ms, reason (why it is lost or still initialising, or why its
//                       file was skipped; quoted)
//   kf_<id>.png         the keyframe with the window's points projected into it, coloured by
//                       inverse depth (near red .. far blue over the window's 5-95 % range);
//                       filled squares: observed in this keyframe; crosses (magenta): observation
//                       marked outlier; single pixels: no observation here
//   kf_<id>_points.csv  the window's points: id, host, host pixel, inverse depth, world position,
//                       pixel and inverse depth in this keyframe, observations (good / outlier),
//                       state in this keyframe (none | good | outlier); with rendered depth also
//                       the true depth at the host pixel and whether a nearer surface hides the
//                       point in this keyframe
// Cost: one PNG and two CSV rows per point per keyframe; meant for diagnosis, not for timing.
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "dsm/geometry/undistorter.h"
#include "dsm/io/dataset.h"
#include "dsm/system/system.h"

namespace dsm {

class DebugWriter {
 public:
  // Creates `dir`; throws InputError when it cannot.
  DebugWriter(const std::filesystem::path& dir, const Dataset& dataset, const Undistorter& undistorter);

  // Writes every keyframe the system made since the last call.
  void AddKeyframes(const System& system);
  // A row of frames.csv: a processed frame of map `map`, or one whose file was skipped.
  void AddFrame(const FrameReport& report, int map);
  void AddSkipped(int frame, int map, const std::string& error);

 private:
  void WriteKeyframe(const System& system, int kf);
  void WriteFrameRow(int frame, int map, const std::string& status, bool keyframe, bool relocalised,
                     double tracking_ms, const std::string& reason);
  // Undistorted depth of input frame `frame`, cached; nullptr when the dataset has none.
  const Image<float>* Depth(int frame);

  std::filesystem::path dir_;
  const Dataset& dataset_;
  const Undistorter& undistorter_;
  std::ofstream table_;
  std::ofstream frames_;
  int written_ = 0;
  std::optional<double> start_scale_;  // Map units per metre between keyframes 0 and 1.
  std::map<int, Image<float>> depth_cache_;
};

}  // namespace dsm
