// SPDX-License-Identifier: MIT
// The mapping side of a System (the paper's mapping thread, section III): it owns the map, the
// window (temporal and covisible keyframes), the candidates, the adjustments, keyframe culling,
// loop closure and map merging. It takes work from the tracking side only through MappingInbox
// (handover.h) and hands back only TrackingReferences, frame records and an IdleMap.
//
// With every tracked frame it refines the candidates of the temporal keyframes along their
// epipolar lines; a new keyframe gets observations of the window's points, enters the temporal
// window (one keyframe leaves), old keyframes covisible with it join the window (DSM mode) with
// their points' re-observations, candidates are activated where the view is still depleted, the
// photometric bundle adjustment runs over the window, points are culled, and the keyframe is
// published as the tracking reference; then its own candidates are selected, and the young map's,
// loop and merge adjustments run when due (FinishKeyframe: the tracking side goes on meanwhile).
//
// Threaded (RunOn), the jobs run on the mapping thread (mapping_thread.h), one at a time; every
// method below but the MappingInbox's is called on that thread, or on the caller's while the
// mapping side is idle (System::Finish first).
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/map/map.h"
#include "dsm/map/stored_map.h"
#include "dsm/mapping/candidate.h"
#include "dsm/optimization/pba.h"
#include "dsm/system/atlas_places.h"
#include "dsm/system/handover.h"
#include "dsm/system/loop_state.h"
#include "dsm/system/options.h"
#include "dsm/system/system_stats.h"

namespace dsm {

class MappingThread;
class OcclusionGrid;

class MappingSide final : public MappingInbox, private IdleMap, private PlaceMap {
 public:
  // `options` as the System runs them (the sliding window's already made all temporal).
  MappingSide(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup, MappingStats* stats);
  ~MappingSide();
  // Threaded: the jobs run on `thread` from here on (null: sequential, each inside its call).
  void RunOn(MappingThread* thread) { thread_ = thread; }
  // The place index this map's keyframes go into: a run's Atlas's, given before the first frame
  // or map taken up (else the mapping side's own). As what that index knows the map by: place_map.
  void UsePlaces(AtlasPlaces* places);
  PlaceMap* place_map() { return this; }

  // MappingInbox (handover.h).
  void StartMap(MapStart start) override;
  void Submit(MappingJob job) override;
  std::shared_ptr<const TrackingReference> Published() const override;
  bool threaded() const override { return thread_ != nullptr; }
  int KeyframesPending() const override;
  int KeyframesUnsettled() const override;
  void WaitForKeyframes() override;
  bool WaitForSettledKeyframesUntil(std::chrono::steady_clock::time_point until) override;
  IdleMap& WaitUntilIdle(bool urgent) override;

  // Waits until every job is done, ends the adjustments that stopped for a relocalisation, and
  // tracks the frames between the two initial keyframes if the run ended before the map matured.
  void Finish();
  // On the first frame (or a loaded map's): its noise level, and from it whether the candidates'
  // contrast floor applies (candidate_selector.h: from candidates.contrast_min_noise on), how
  // residuals sample images and whether the texture-loss test is on.
  void ChooseNoiseHandling(double noise_sigma);
  bool NoiseChosen() const { return stats_->image_noise_sigma >= 0.0; }
  // The frames between the two initial keyframes as TrackInitFrames tracked them, taken (Finish first).
  std::vector<FramePose> TakeInitTracked() { return std::move(init_tracked_); }

  const Map& map() const override { return map_; }
  std::vector<int> ActiveKeyframes() const;  // The window: temporal (oldest first) then covisible.
  std::vector<int> ActivePointIds() const;   // Live points hosted by the window's keyframes.
  double InitBaseline() const;  // Distance between keyframes 0 and 1 (their camera centres); 0 without both.
  // The product of the scales loop closures gave keyframe k (its hosted geometry is that much
  // smaller than when it was mapped).
  double KeyframeScale(int k) const {
    return k < static_cast<int>(keyframe_scale_.size()) ? keyframe_scale_[k] : 1.0;
  }
  // World_from_cam of every keyframe the run made (a loaded map's left out), in time order.
  Trajectory KeyframeTrajectory() const;
  void RunGlobalBundleAdjustment();
  void AdjustWholeMapFrom(const Trajectory& world_from_cam);  // System::AdjustWholeMapFrom.

  // Map files (System::TakeStoredMap, System::RestoreMap). Take: the quality levels the tracking
  // side judged frames with go into the file. Restore: returns the reference keyframe lost
  // frames are tried against first.
  StoredMap TakeStoredMap(double residual_level, double texture_level);
  int RestoreMap(StoredMap* stored, bool localize);
  bool localizing() const { return localizing_; }
  int loaded_keyframes() const { return loaded_keyframes_; }
  int loaded_points() const { return loaded_points_; }
  int retired_keyframes() const { return retired_keyframes_; }
  // The camera's speed per frame as a loaded map has it (between consecutive keyframes).
  double loaded_speed() const { return loaded_speed_; }

  // Map merging (mapping_merge.cc): the Atlas's id of the merge candidate a keyframe recognised
  // and verified (-1: none), and the merge of that map's mapping side, `other` (System::MergeVerified):
  // returns the offset of the taken keyframes' ids.
  int MergeReady() const { return loop_.merge_ready.load(); }
  bool MergeReadyWith(const MappingSide& other) const {
    return loop_.pending_merge && loop_.pending_merge->source == static_cast<const PlaceMap*>(&other);
  }
  int TakeMerge(MappingSide& other, int taken_id);

 private:
  // IdleMap (handover.h) and PlaceMap (atlas_places.h).
  std::vector<ReferencePoint> PointsSeenIn(int kf) override;
  const OrbFeatures& KeyframeFeatures(int k) override;  // Detected on first use (keyframe_features_).
  std::shared_ptr<const TrackingReference> MakeReference(int kf, std::vector<ReferencePoint> points,
                                                         std::shared_ptr<const ImagePyramid> pyramid) const override;
  std::map<int, OrbFeatures>& keyframe_features() override { return keyframe_features_; }
  void Republish(std::shared_ptr<const TrackingReference> ref) override;

  // A job of the mapping side, after the ones handed over before (inline when sequential);
  // `keyframe`: counted as a keyframe being mapped (the tracking side may wait for it).
  void Run(std::function<void()> job, bool keyframe = false);
  void RunJob(const MappingJob& job);  // Traces candidates; maps the frame when it is a keyframe.
  void RunFinishJob(int kf);           // FinishKeyframe, timed.
  void MapFirstKeyframe(SE3d pose, double alpha, double exposure, double start_ms);  // StartMap's job.
  void TraceCandidates(const ImagePyramid& pyramid, int reference, const SE3d& frame_from_reference, double alpha,
                       double beta, double exposure);
  void CreateKeyframe(int index, int64_t t_ns, std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                      const SE3d& cam_from_world, const AffineBrightness& affine);
  // Hands keyframe kf with `points` to the tracking side.
  void PublishReference(int kf, std::vector<ReferencePoint> points);
  void PublishTrackingReference();  // The newest keyframe of the window, with the window's points.
  // The points among `ids` the bundle adjustment saw in keyframe `kf`, projected into it
  // (`adjusted` false: before kf's first bundle adjustment, every point that projects into it).
  std::vector<ReferencePoint> ReferencePointsIn(int kf, const std::vector<int>& ids, bool adjusted = true);
  // On the mapping side, once keyframe kInitTrackingKeyframe is mapped (or at Finish): tracks
  // init_between_ into init_tracked_.
  void TrackInitFrames();
  static constexpr int kInitTrackingKeyframe = 4;
  void MapNewKeyframe(int kf);  // Maps keyframe kf and publishes it as the tracking reference.
  PbaSummary AdjustWholeMap();  // One bundle adjustment of every keyframe (keyframe 0 fixed) and point.
  // `held` and the keyframes of a loaded map: the map a later session extends is its reference,
  // so their poses stay where the file has them in every adjustment (their points' depths are
  // still refined).
  std::vector<int> HeldWithLoaded(std::vector<int> held) const;
  std::vector<int> AllKeyframes() const;  // 0 .. NumKeyframes() - 1 but the retired ones.
  // A young map's or loop bundle adjustment. Threaded (SystemSetup::yield_adjustments), it stops
  // for a keyframe waiting to be mapped and is taken up after it, as another mapping job, and for
  // a relocalisation waiting for the mapping side to be idle, taken up after the next keyframe
  // (parked_): a whole-map adjustment of the young map takes about a second, which the next
  // keyframe, and the frames tracked against the one before it, would otherwise wait through.
  struct Adjustment {
    bool young = false;                // All keyframes at the time each part runs.
    std::vector<int> keyframes, held;  // Else these (RunPba's active and held).
    PbaOptions options;
    size_t log = 0;   // The stats_->per_keyframe entry of the keyframe it follows.
    size_t stat = 0;  // Its entry in stats_->young_map_ba_ms or stats_->loop_ba_ms.
    int level = -1, iterations = 0;  // Where to take it up (PbaYield).
  };
  void Adjust(Adjustment a);
  bool RunParked();  // The rest of the adjustments that stopped for a relocalisation; true when any.
  // After keyframe `newest` is published (FinishKeyframe), when due; each true when it ran: the
  // loop bundle adjustment (SystemOptions::loop_ba_min_gap), the seam adjustment after a
  // relocalisation (seam_ba_count), the part mapped since the relocalisation moved onto the
  // older map when `newest` sees that map's points as outliers (rejoin_min_outliers), and the
  // young map's adjustment (young_map_ba_first).
  bool AdjustLoop(int newest);
  bool AdjustSeam(int newest);
  bool RejoinAfterRelocalisation(int newest);
  bool AdjustYoungMap();
  PbaOptions LoopBaOptions() const;  // Of a loop or merge adjustment (loop_ba_max_iterations).
  // A loop or seam adjustment of `keyframes` (`held` among them fixed), logged with the newest
  // keyframe's entry and in stats_->loop_ba_ms.
  void AdjustAfterNewest(std::vector<int> keyframes, std::vector<int> held, const PbaOptions& pba, bool seam);
  // What the tracking reference does not need, done after it is published: kf's candidates,
  // the adjustments when due, and the release of pyramids no longer used.
  void FinishKeyframe(int kf);
  // Candidates activated where no active point seen in `newest` (SeenIn) nor old map point is near.
  void ActivateCandidates(int newest);
  // Per point of `ids`: 1 when it projects into `target` and looks consistent there
  // (observation_check.h), or is hosted there.
  std::vector<uint8_t> SeenIn(const std::vector<int>& ids, int target);
  int CullPoints();  // Returns how many it removed; never a frozen keyframe's point.
  // SystemOptions::keyframe_culling: retires keyframe k, which has left the temporal window, when
  // the map has it covered; true when it did.
  bool CullKeyframe(int k);
  // Judges the keyframes that left the temporal window (cull_pending_) once the window's
  // adjustment no longer has them among its cameras (`in_use`).
  void CullUnusedKeyframes(const std::vector<int>& in_use);
  // Localisation: once keyframe `newest` sees the loaded map again, the temporary keyframes
  // outside the window leave the map (Map::Retire).
  void RetireTemporaries(int newest);
  // Loop closure (mapping_loop.cc; LoopClosureOptions).
  bool LoopClosureActive() const;
  void AddToPlaceIndex(int k);
  bool DetectAndCloseLoop(int kf);  // Adds kf to the place index; closes a loop when it finds one.
  // `owner`: the map that has c (this one, or a merge candidate).
  bool VerifyLoop(int kf, PlaceMap& owner, int c, LoopMatch* match);
  // Keyframe kf (bag of words `bow`, score floor `floor`) against the merge sources' keyframes; a
  // verified match waits in loop_.pending_merge for TakeMerge.
  void DetectMerge(int kf, const BowVector& bow, double floor);
  // The bundle adjustment that joins the last merged map to this one, once keyframe `newest`'s
  // window re-observes its points (a merged keyframe among the covisible ones); true when it ran.
  bool AdjustMerge(int newest);
  // The pose and brightness graphs with the loop edge; every keyframe and its points moved.
  // `shared`: the observations each pair of live keyframes (i < j) shares.
  void CorrectLoop(int kf, const LoopMatch& match, const std::map<std::pair<int, int>, int>& shared);
  void SelectCandidates(int kf);
  // Covisible keyframes and their points' re-observations in `newest`, except hidden ones.
  void SelectCovisible(int newest, OcclusionGrid* occlusion);
  void AddToOcclusionGrid(const std::vector<int>& keyframes, int target, OcclusionGrid* grid) const;

  PinholeCamera camera_;
  SystemOptions options_;
  SystemSetup setup_;
  MappingStats* stats_;
  MappingThread* thread_ = nullptr;
  Map map_;
  std::vector<int> window_;     // Temporal window, oldest first.
  std::vector<int> covisible_;  // Covisible part of the window (DSM mode).
  int last_loop_ba_ = -1;       // Keyframe after which the last loop bundle adjustment ran.
  int relocalisations_mapped_ = 0;  // The tracking side's count as the last job brought it.
  int seam_first_ = -1;             // The first keyframe mapped after the last relocalisation (-1: none).
  int rejoin_first_ = -1;           // The same, until that part was rejoined (-1: none).
  bool loop_ba_pending_ = false;    // A relocalisation since the last loop bundle adjustment.
  std::vector<Eigen::Vector2f> old_pixels_;  // Newest-keyframe pixels of old, unselected map points.
  std::map<int, std::vector<Candidate>> candidates_;
  float min_activation_distance_px_;
  double keyframe_ms_ = 0.0;  // The last keyframe's mapping time up to its publication.
  mutable std::mutex published_mutex_;  // The reference handed to the tracking side ...
  std::shared_ptr<const TrackingReference> published_;
  struct InitBetween {
    std::vector<InitFrame> frames;  // Between keyframes 0 and 1, in order.
    SE3d kf1_from_kf0;              // From the two-view start.
    int steps = 1;                  // Frame steps from keyframe 0 to keyframe 1.
  };
  InitBetween init_between_;  // Set by StartMap, tracked by TrackInitFrames ...
  std::vector<FramePose> init_tracked_;  // ... into these records.
  // ORB features of keyframes: computed on first use by loop closure or relocalisation (IdleMap),
  // or for every keyframe (SystemSetup::keyframe_features).
  std::map<int, OrbFeatures> keyframe_features_;
  std::vector<Adjustment> parked_;  // Adjustments stopped for a relocalisation.
  // RestoreMap: the keyframes and live points loaded, the covisible keyframes each was mapped
  // with, and the camera's speed per frame as the map has it.
  int loaded_keyframes_ = 0, loaded_points_ = 0;
  std::vector<std::vector<int>> loaded_covisibility_;
  double loaded_speed_ = 0.0;
  // Localisation: the map is a frozen reference; `loaded_as_` is the stored map's window,
  // covisibility and levels (its map empty) that TakeStoredMap gives back, and loaded_point_ids_
  // the points it had (ids below that are its own).
  bool localizing_ = false;
  StoredMap loaded_as_;
  int loaded_point_ids_ = 0;
  int retired_keyframes_ = 0;  // Localisation's temporary keyframes retired (culled ones: stats_).
  std::vector<int> cull_pending_;  // Left the temporal window, not judged yet (CullUnusedKeyframes).
  LoopState loop_;  // Loop closure and map merging.
  AtlasPlaces own_places_;  // Without an Atlas ...
  AtlasPlaces* places_;     // ... the index this map's places are in.
  // Per keyframe id: the product of the scales loop closures gave it; missing entries are 1.
  std::vector<double> keyframe_scale_;
};

}  // namespace dsm
