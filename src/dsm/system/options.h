// SPDX-License-Identifier: MIT
// All options of the system in one validated struct (nested per component).
#pragma once

#include <string>

#include "dsm/mapping/activation.h"
#include "dsm/mapping/candidate.h"
#include "dsm/mapping/candidate_selector.h"
#include "dsm/mapping/keyframe_decision.h"
#include "dsm/mapping/occlusion.h"
#include "dsm/mapping/window.h"
#include "dsm/optimization/pba.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/initializer.h"
#include "dsm/tracking/tracking_quality.h"

namespace dsm {

enum class MapMode {
  kSlidingWindow,  // DSM-SW: a temporal window of N_t + N_c keyframes (DSM's size), no covisible part.
  kFull,           // DSM: temporal + covisible keyframes (window.covisible_keyframes).
};
MapMode ParseMapMode(const std::string& name, const std::string& where);  // dsm | sw
std::string MapModeName(MapMode mode);

// What the system does once a frame is lost (tracking_quality.h): every following frame is tried
// against the map's keyframes (the last reference first, then the `candidates` most similar by
// thumbnail); after `max_lost_frames` frames in a row that had texture enough to be tried and
// still failed, the camera is taken to be somewhere new and a new map is started (0: never); a
// map that tracked at most `young_map_frames` frames is given up after `max_predicted_frames`
// such frames already (its few points, from a short baseline, are seldom found again once the
// prediction is gone, and a new map loses less of the recording). By frames, not keyframes: a
// camera that stays in place (`shake`) keeps an old map of a few keyframes.
// A relocalised pose is accepted when it lies within reach of the constant-velocity prediction
// from the last trusted frame (TrackingQuality::CheckJump), while at most `max_predicted_frames`
// frames were lost; otherwise (a longer loss, or a camera that turned away from the prediction)
// only when three lost frames in a row relocalise to poses that move as one camera does
// (tracking_relocalisation.cc).
struct RelocalisationOptions {
  int candidates = 3;
  int max_lost_frames = 30;
  int max_predicted_frames = 10;
  int young_map_frames = 20;

  void Validate() const;
};

// Loop closure (--mode dsm; mapping_loop.cc): each new keyframe's ORB features are scored against
// the map's keyframes outside the window by their bags of words (place/vocabulary.h); a place
// found again by `consistent_keyframes` keyframes in a row is verified by a Sim(3) between the
// two views (RANSAC on ORB matches with map depths, at least `min_inliers`, then direct
// alignment), and the loop is closed by a Sim(3) pose graph over the map's keyframes, after which
// the window re-observes the old points and the loop is bundle-adjusted.
struct LoopClosureOptions {
  bool enabled = true;
  int consistent_keyframes = 3;
  int min_inliers = 20;
  std::string vocabulary;  // A file written by `dsm vocabulary`; empty: the one built into dsm.

  void Validate() const;
};

// How the caller runs a System (system.h): set from the run's pace (run/run.h), its viewer and
// the camera's calibration, never by option files.
struct SystemSetup {
  // The camera's rolling shutter: seconds between two rows' exposures, from its calibration
  // (line_delay_us); 0: a global shutter. Tracking predicts each point where the rolling shutter
  // saw it (ReadoutTurn), and the mapping side resamples each frame as a global shutter at its
  // timestamp would have seen it (tracking/rolling_shutter.h), the camera turning as over the
  // last frame step.
  double line_delay_s = 0.0;
  // Mapping on a thread of its own beside tracking (system.h); false: every keyframe is mapped
  // before the next frame is tracked, deterministically.
  bool threaded = false;
  // Threaded: when tracking wants a keyframe while the last one is still being mapped, wait for it
  // (true), or go on against the older keyframe and make the keyframe once it is mapped (false:
  // a live camera does not wait).
  bool wait_for_mapping = true;
  // Threaded: the young map's and the loop adjustments stop for a keyframe waiting to be mapped
  // and are taken up after it (MappingSide::Adjust), so that a live camera's keyframes do not wait
  // through a second-long adjustment. Not when frames wait for the mapping side anyway (free
  // pace), where taking an adjustment up again costs building its problem anew.
  bool yield_adjustments = false;
  // Threaded: the mapping side computes each keyframe's ORB features (for relocalisation) once it
  // is mapped, instead of the first relocalisation that ranks it: a live camera's relocalisation
  // then has no features to detect first, and its mapping side has time between keyframes.
  bool keyframe_features = false;
  // Threaded: a frame tracked while the mapping side still maps a keyframe hands it no candidate
  // tracing. When frames come as fast as tracking takes them (free pace) the mapping side is the
  // slower of the two, and these frames add little that the frames after them do not. Not for a
  // live camera (realtime pace), whose frames come far apart.
  bool skip_traces_while_mapping = false;
  // Every tracking reference carries a MapSnapshot (system.h) for a live viewer: the mapping side
  // spends about a microsecond per live point on it per keyframe.
  bool map_snapshots = false;

  void Validate() const;  // Throws InputError naming the setting.
};

struct SystemOptions {
  MapMode mode = MapMode::kFull;
  int pyramid_levels = 5;          // Image pyramid (the undistorted size divides by 2^(levels-1)).
  int max_initialization_frames = 40;  // Frames on one initialiser reference before it restarts.
  // A keyframe's pyramid is released when no mapping step used it in the last this many keyframes
  // (the compact image stays; Map::LoadPyramids rebuilds it).
  static constexpr int keep_pyramid_keyframes = 2;
  // How residuals sample images (photometric/residual.h): "bilinear", "bspline", or "auto" (the
  // default): the cubic B-spline when the first frame's noise level reaches bspline_min_noise grey
  // levels, bilinear below. Bilinear interpolation of independent pixel noise leaves a one-pixel
  // ripple in the energy that pulls every depth and pose; on camera images the ripple is weak and
  // the B-spline's blur and cost buy nothing.
  std::string interpolation = "auto";
  static constexpr double bspline_min_noise = 2.5;
  // The bundle adjustment's texture-loss test (texture_loss.h) in --mode dsm, when the first
  // frame's noise level reaches this many grey levels (0: never): at kTextureLossRatio, judging
  // the error models' fit and the removal after the adjustment. On noisy images a point seen through a
  // plain near surface widens its target's error model the most. Not in --mode sw, which has no
  // persistent map to re-observe a removed observation's point from.
  double texture_loss_min_noise = 2.5;
  // Bundle adjustments of the whole young map (--mode dsm): every keyframe but the first free,
  // when the map reaches young_map_ba_first keyframes, then twice, four times as many, ..., up to
  // young_map_ba_last (0: none), each after the keyframe is published (MappingSide::FinishKeyframe; it
  // is then published again). A keyframe that leaves the window is held where the window left
  // it, and every later keyframe builds on it, while the first ones stand on short baselines and
  // the two-view start. Not before 10 keyframes: a map of 5 may still be little more than a
  // rotation, and freeing all its poses bends it. The bound keeps the cost (about a second at 40
  // keyframes) independent of the map's size.
  int young_map_ba_first = 10;
  int young_map_ba_last = 40;
  // A bundle adjustment of the loop when the camera comes back (--mode dsm): when the new
  // keyframe's covisible keyframes reach at least loop_ba_min_gap keyframes back, the keyframes
  // after the oldest of them are adjusted (the newest loop_ba_max_keyframes at most), the
  // covisible ones and all before held, with loop_ba_max_iterations LM iterations per level (0:
  // as pba.max_iterations); at most once every loop_ba_min_gap keyframes, after the keyframe is
  // published (MappingSide::FinishKeyframe; it is then published again). The window alone moves only
  // its own keyframes onto the old map, and what drifted over the loop stays. Not when the camera
  // has stayed within loop_ba_min_reach scene depths (the inverse of the mean inverse depth of
  // the window's points) of the oldest covisible keyframe since: a camera turning in place sees its
  // old keyframes again without a loop, and freeing keyframes on baselines that short leaves
  // their depths and scale loose. 0: never.
  int loop_ba_min_gap = 20;
  static constexpr double loop_ba_min_reach = 0.5;
  // The same adjustment once after a relocalisation, at the first keyframe whose covisible
  // keyframes reach this many back (0: never). The part mapped after a loss joins the part before
  // through one relocalised pose, and the two disagree where the camera comes back. From then on
  // the map is also adjusted as loop_ba_min_gap would, every this many keyframes (when
  // loop_ba_min_gap is 0). A recording without losses never pays for it.
  int loop_ba_after_relocalisation = 20;
  // The seam a relocalisation leaves (--mode dsm): the part mapped after it joins the part before
  // through the relocalised pose and the few old points it sees, and the window, which frees the
  // keyframes before the loss as well, bends those towards it. At every seam_ba_step-th of the
  // first seam_ba_step * seam_ba_count keyframes after the relocalisation, the seam_ba_before
  // keyframes before it and all after it are adjusted together, the older keyframes whose points
  // these observe held; not in a map of fewer than 2 * seam_ba_before keyframes at the loss, which
  // has too little before them to hold it.
  int seam_ba_count = 4;  // 0: never.
  int seam_ba_step = 2;
  int seam_ba_before = 8;
  // The part mapped since a relocalisation is joined to the older map by the relocalised pose
  // alone, which a small overlap leaves a few percent of the baseline off. When the camera later
  // sees the older map again and at least rejoin_min_outliers of a new keyframe's observations of
  // its points are outliers (three times its inlier ones), the keyframe is aligned with the old
  // keyframe they come from, and the whole part is moved by the correction (mapping_rejoin.cc).
  // 0: never.
  int rejoin_min_outliers = 50;
  // Keyframe culling (--mode dsm): a keyframe that has left the temporal window and is no longer
  // in the window's adjustment is retired (Map::Retire) when the map already has it covered: at
  // least 90% of the points it sees (hosted or observed) are seen by three other keyframes, it
  // hosts at most a tenth of them, and half of them are the older map's (a place seen before);
  // its points are re-hosted by the keyframe outside the window that sees each nearest to where
  // it was (dropped when none can). The map then grows with the area covered rather than the
  // time spent in it (mapping_culling.cc).
  bool keyframe_culling = true;
  int loop_ba_max_keyframes = 120;
  int loop_ba_max_iterations = 0;  // Per level; 0: as pba.max_iterations.
  InitializerOptions initializer;
  TrackerOptions tracker;
  CandidateSelectorOptions candidates;
  EpipolarOptions epipolar;
  ActivationOptions activation;
  KeyframeOptions keyframe;
  QualityOptions quality;
  RelocalisationOptions relocalisation;
  LoopClosureOptions loop_closure;
  WindowOptions window;
  OcclusionOptions occlusion;  // Observations of hidden points are not created.
  PbaOptions pba;

  // Throws InputError naming the first invalid option (including rules across options).
  void Validate() const;
  // Whether a map that has just reached `keyframes` keyframes gets a young-map bundle adjustment.
  bool YoungMapBaDue(int keyframes) const;
};

}  // namespace dsm
