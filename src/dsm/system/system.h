// SPDX-License-Identifier: MIT
// The system facade: feed undistorted frames in order, get poses. Sequential and deterministic:
// every frame is tracked and every keyframe mapped before the next frame is processed.
//
// Per frame: initialise (until a two-view start succeeds), then track against the newest
// keyframe, refine the candidates of the temporal keyframes along their epipolar lines, and decide
// whether the frame becomes a keyframe. A new keyframe gets observations of the window's points,
// enters the temporal window (one keyframe leaves), old keyframes covisible with it join the
// window (DSM mode) and their points get observations in it (re-observations), candidates are
// activated into the areas still depleted, the photometric bundle adjustment runs over the whole
// window, points are culled, and the tracker's reference moves to the new keyframe.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/image/image.h"
#include "dsm/map/map.h"
#include "dsm/system/options.h"

namespace dsm {

enum class TrackingStatus { kInitializing, kOk, kLost };
std::string TrackingStatusName(TrackingStatus status);

struct FrameReport {
  int index = -1;
  TrackingStatus status = TrackingStatus::kInitializing;
  std::string reason;       // For kInitializing / kLost.
  bool keyframe = false;
  double tracking_ms = 0.0;
  double mapping_ms = 0.0;  // Keyframe creation and PBA, when this frame became one.
};

struct SystemStats {
  int frames = 0, frames_tracked = 0, keyframes = 0;
  int initialized_at_frame = -1;
  std::vector<double> tracking_ms;  // Per tracked frame.
  std::vector<double> mapping_ms;   // Per keyframe.
  std::vector<double> pba_ms;       // Per keyframe.
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
    int observations_removed = 0;  // Marked outliers after its bundle adjustment.
    int points_culled = 0;         // Removed after its bundle adjustment.
    // Tracking of the frame that became this keyframe (0 for the first two).
    double tracking_rmse = 0.0, tracking_inlier_ratio = 0.0;
  };
  std::vector<KeyframeLog> per_keyframe;
  double global_ba_ms = -1.0;       // -1: not run.
};

class System {
 public:
  System(const PinholeCamera& camera, const SystemOptions& options);
  ~System();

  // `image`: undistorted (and photometrically corrected) frame of the camera's size.
  // `exposure_ms`: 0 when unknown.
  FrameReport Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms);

  // world_from_cam of every keyframe / every tracked frame, with the latest keyframe poses.
  Trajectory KeyframeTrajectory() const;
  Trajectory FrameTrajectory() const;
  const SystemStats& stats() const { return stats_; }
  int NumMapPoints() const;
  const Map& map() const { return map_; }

  // Bundle adjustment of every keyframe and point of the map (keyframe 0 fixed), once, at the end.
  void RunGlobalBundleAdjustment();

  // The keyframes of the current window: temporal (oldest first) then covisible.
  std::vector<int> ActiveKeyframes() const;
  // Live points hosted by the window's keyframes.
  std::vector<int> ActivePointIds() const;

 private:
  struct FrameRecordInternal {
    int64_t t_ns = 0;
    int reference = -1;          // Keyframe id the pose is relative to.
    SE3d frame_from_reference;
  };
  struct PendingFrame {
    int index;
    int64_t t_ns;
    double exposure;
    std::unique_ptr<ImagePyramid> pyramid;
  };

  FrameReport Initialize(int index, int64_t t_ns, const Image<float>& image, double exposure);
  void StartMap(const struct InitResult& init);
  bool TrackFrame(const ImagePyramid& pyramid, double exposure, struct TrackResult* result);
  void TraceCandidates(const ImagePyramid& pyramid, const SE3d& frame_from_reference, double alpha, double beta,
                       double exposure);
  void CreateKeyframe(int index, int64_t t_ns, std::unique_ptr<ImagePyramid> pyramid, double exposure,
                      const SE3d& cam_from_world, const AffineBrightness& affine);
  void MapNewKeyframe(int kf);
  // Candidates activated where no active point seen in `newest` (SeenIn) nor old map point is near.
  void ActivateCandidates(int newest);
  // Per point of `ids`: 1 when it projects into `target` and looks consistent there
  // (observation_check.h), or is hosted there.
  std::vector<uint8_t> SeenIn(const std::vector<int>& ids, int target) const;
  int CullPoints();  // Returns how many it removed.
  void SelectCandidates(int kf);
  void SetTrackingReference();
  // Covisible keyframes and their points' re-observations in `newest`, except hidden ones.
  void SelectCovisible(int newest, OcclusionGrid* occlusion);
  void AddToOcclusionGrid(const std::vector<int>& keyframes, int target, OcclusionGrid* grid) const;

  PinholeCamera camera_;
  SystemOptions options_;
  Map map_;
  std::vector<int> window_;     // Temporal window, oldest first.
  std::vector<int> covisible_; // Covisible part of the window (DSM mode).
  std::vector<Eigen::Vector2f> old_pixels_;  // Newest-keyframe pixels of old, unselected map points.
  std::map<int, std::vector<Candidate>> candidates_;
  std::unique_ptr<class Initializer> initializer_;
  std::vector<PendingFrame> pending_;
  std::unique_ptr<class FrameTracker> tracker_;
  int reference_ = -1;  // Keyframe the tracker uses.
  std::vector<FrameRecordInternal> frames_;
  SE3d last_frame_from_reference_, velocity_;  // velocity: last frame motion (frame_from_previous)
  double last_alpha_ = 0.0, last_beta_ = 0.0;  // Brightness of the last frame relative to the reference.
  double last_exposure_ = 1.0;
  double first_rmse_after_keyframe_ = 0.0;
  float min_activation_distance_px_;
  SystemStats stats_;
};

}  // namespace dsm
