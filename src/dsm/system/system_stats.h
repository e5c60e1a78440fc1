// SPDX-License-Identifier: MIT
// What a System counts and times over its run (System::stats): the tracking side's frames, losses
// and waits (TrackingStats), and the mapping side's keyframes, adjustments, culling, loops and a
// log per keyframe (MappingStats). Each side writes its own part only.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace dsm {

struct TrackingStats {
  int frames = 0, frames_tracked = 0;
  // Frames that failed the quality test after the map started (tracking_quality.h), the episodes
  // of consecutive lost frames (first and last frame index) and how many ended by relocalisation.
  int frames_lost = 0, relocalisations = 0;
  std::vector<std::pair<int, int>> lost_episodes;
  // Each confirmed relocalisation and its evidence (TrackingSide::Relocalise): the relocalised
  // frame, the keyframe it was aligned with, the frames since the last trusted one, whether its
  // pose was within reach of the prediction (else three sightings moved as one camera), the
  // alignment's inlier share beside the inlier level of tracking before the loss (0: not known),
  // its median residual over the residual level, and the margin: the median residual of the best
  // alignment that passed the quality test at another place over the winner's (0: no other place
  // passed).
  struct Relocalisation {
    int frame = -1, keyframe = -1, frames_lost = 0;
    bool predicted = false;
    double inlier_ratio = 0.0, inlier_level = 0.0, residual_ratio = 0.0, margin = 0.0;
  };
  std::vector<Relocalisation> relocalised;
  int initialized_at_frame = -1;
  std::string initialization;  // How the map started: "two-view" or "planar" (initializer.h).
  std::vector<double> tracking_ms;  // Per tracked frame: its pyramid and alignment.
  int keyframe_waits = 0;           // Frames whose tracking waited for a keyframe to be mapped.
  int keyframe_wait_timeouts = 0;   // Of those, the ones that gave up at their deadline (wait_until).
  // Frames that failed against the keyframe before a pending one and were tracked again against it.
  int keyframe_retracks = 0;
  // Frames whose candidate tracing was skipped (SystemSetup::skip_traces_while_mapping).
  int traces_skipped = 0;
  // Trackings redone with the brightness held: the contrast changed more than exposure can
  // (TrackerOptions::max_alpha_step).
  int brightness_holds = 0;
};

struct MappingStats {
  int keyframes = 0;
  double image_noise_sigma = -1.0;  // Noise level of the first frame (image/noise.h), grey levels.
  bool contrast_floor = false;      // Candidates kept off patterns at the noise's contrast.
  std::string interpolation = "bilinear";  // How the residuals sample images: bilinear | bspline.
  bool texture_loss = false;  // The bundle adjustment's texture-loss test is on (options.h).
  std::vector<double> tracing_ms;   // Per tracked frame: candidate tracing (mapping side).
  std::vector<double> mapping_ms;   // Per keyframe: everything the mapping side does to it.
  std::vector<double> pba_ms;       // Per keyframe.
  std::vector<double> young_map_ba_ms;  // Per young-map bundle adjustment.
  std::vector<double> loop_ba_ms;       // Per loop bundle adjustment.
  int points_created = 0;           // Initial points and activated candidates.
  int reobservations = 0;           // Observations created for points hosted outside the temporal window.
  int covisible_keyframes_selected = 0;  // Summed over keyframes.
  struct KeyframeLog {
    int frame = -1;             // Input frame index of the keyframe.
    int points_created = 0;     // Points activated when it was mapped.
    int reobservations = 0;
    std::vector<int> covisible; // Keyframe ids of the covisible part of its window.
    // Its bundle adjustment: keyframes in the problem (and how many of them fixed), points,
    // observations, LM iterations over all levels.
    int pba_keyframes = 0, pba_fixed_keyframes = 0, pba_points = 0, pba_observations = 0, pba_iterations = 0;
    double pba_ms = 0.0;           // Its bundle adjustment's time.
    // The young map's bundle adjustment that followed (SystemOptions::young_map_ba_first), if any:
    // its keyframes and time.
    int young_map_ba_keyframes = 0;
    double young_map_ba_ms = 0.0;
    int young_map_ba_iterations = 0, young_map_ba_observations = 0;
    int loop_ba_keyframes = 0;  // Keyframes the loop bundle adjustment after this one freed (0: none).
    double loop_ba_ms = 0.0;
    bool loop_ba_seam = false;  // That adjustment was a relocalisation's seam (SystemOptions::seam_ba_count).
    // The part mapped since the relocalisation moved onto the older map (rejoin_min_outliers):
    // the correction's translation over the old keyframe's mean depth, its rotation (degrees)
    // and the median shift of the old points in the keyframe (pixels).
    bool rejoined = false;
    double rejoin_step = 0.0, rejoin_deg = 0.0, rejoin_shift_px = 0.0;
    int observations_removed = 0;  // Marked outliers after its bundle adjustment.
    int observations_texture_lost = 0;  // Of those: the texture vanished in the target (texture_loss.h).
    int points_culled = 0;         // Removed after its bundle adjustment.
    // After it: the window's points it sees (hosts, or observes as an inlier), and of those the
    // ones the covisible keyframes host (the map it returned to).
    int points_seen = 0, old_points_seen = 0;
    // Tracking of the frame that became this keyframe (0 for the first two).
    double tracking_rmse = 0.0, tracking_inlier_ratio = 0.0;
  };
  std::vector<KeyframeLog> per_keyframe;
  double global_ba_ms = -1.0;       // -1: not run.
  int keyframe_queue_max = 0;       // Most keyframes handed to the mapping side and not yet mapped.
  // Young map's and loop adjustments that stopped for a keyframe waiting to be mapped or a
  // relocalisation (taken up after it; MappingSide::Adjust).
  int adjustments_yielded = 0;
  int keyframes_culled = 0;  // Retired by keyframe culling (SystemOptions::keyframe_culling) ...
  int points_rehosted = 0;   // ... their points re-hosted by other keyframes ...
  int points_dropped = 0;    // ... and those none could.
  // Loop closure (LoopClosureOptions): places recognised by consistent_keyframes keyframes in a
  // row (whether verified or not), and the loops closed.
  int loops_detected = 0;
  struct LoopClosure {
    int frame = -1;                   // Input frame of the keyframe that closed it ...
    int keyframe = -1, candidate = -1;  // ... its id, and the old keyframe it was matched with.
    int inliers = 0;                  // Sim(3) RANSAC inliers.
    // The keyframe's correction: the move of its centre as a share of the path the keyframes
    // travelled up to it, its rotation (degrees), and the scale its part of the map took.
    double translation_share = 0.0, rotation_deg = 0.0, scale = 1.0;
    double ms = 0.0;  // Verification and pose graph.
    // The evidence: the direct alignment's median residual over the keyframe's error scale, the
    // median move of the candidate's points in the keyframe (px), the correction (the centre's
    // move plus the turn at the scene's depth) over the path the map's links give since the
    // candidate, and the map as it is over the loop in median residual (0: aligned from the map's
    // own pose, the keyframe found the loop's pose or no fit).
    double residual_ratio = 0.0, shift_px = 0.0, correction_share = 0.0, margin = 0.0;
  };
  std::vector<LoopClosure> loops_closed;
  // Maps of the run merged into this one (System::MergeVerified).
  struct MapMerge {
    int frame = -1;                     // Input frame of the keyframe that recognised the other map ...
    int keyframe = -1, candidate = -1;  // ... its id, and the other map's keyframe (its id here).
    int map = -1;                       // The map taken in (system/atlas.h's id for it).
    int keyframes = 0, points = 0;      // Taken from it (live points).
    int inliers = 0;                    // Sim(3) RANSAC inliers.
    double scale = 1.0;                 // Of the other map's geometry here.
    double ms = 0.0;                    // The merge on the caller's thread (verification not included).
  };
  std::vector<MapMerge> maps_merged;
  int pyramids_rebuilt = 0;         // Keyframe pyramids rebuilt after they were released (Map).
  int pyramids_loaded_max = 0;      // Most keyframe pyramids held at once.
};

struct SystemStats : TrackingStats, MappingStats {};

}  // namespace dsm
