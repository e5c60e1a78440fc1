// SPDX-License-Identifier: MIT
// The system facade: feed undistorted frames in order, get poses.
//
// Two sides, as the paper's two threads (section III): the tracking side (tracking_side.h, on the
// caller's thread in Process) and the mapping side (mapping_side.h), which exchange only what
// handover.h declares. The System owns both, and the mapping thread when threaded.
//
// With SystemSetup::threaded false (the default) the mapping work runs inside Process: every
// keyframe is mapped before the next frame, and the output is deterministic. With it true the
// mapping side runs on its own thread (mapping_thread.h). While a keyframe is still being mapped
// the tracking side goes on against the older reference; when it wants another keyframe
// meanwhile, it waits for the pending one first (SystemSetup::wait_for_mapping) or makes it once
// the pending one is mapped: at most one keyframe is in flight.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/image/image.h"
#include "dsm/map/map.h"
#include "dsm/map/stored_map.h"
#include "dsm/system/handover.h"
#include "dsm/system/mapping_side.h"
#include "dsm/system/options.h"
#include "dsm/system/system_stats.h"
#include "dsm/system/tracking_side.h"
#include "dsm/system/tracking_state.h"

namespace dsm {

class System {
 public:
  System(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup = {});
  ~System();

  // `image`: undistorted (and photometrically corrected) frame of the camera's size.
  // `exposure_ms`: 0 when unknown. Returns once the frame is tracked (and, sequential, mapped).
  // `index` and `t_ns` increase from frame to frame (InputError otherwise, nothing changed).
  // `wait_until` (threaded, SystemSetup::wait_for_mapping false): while a keyframe is still being
  // mapped, the frame waits for it until then, so that it is tracked against the newest keyframe
  // as in the sequential run, but no later (the realtime pace's bound, run/realtime_wait.h).
  FrameReport Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                      std::optional<std::chrono::steady_clock::time_point> wait_until = std::nullopt);
  // Called on the caller's thread, from within Process, once per tracked frame as soon as it has a
  // pose (world_from_cam): before the frame waits for a keyframe being mapped (`wait_until`),
  // with its pose against the newest keyframe published then; the pose the run keeps
  // (FrameTrajectory) is the one tracked after the wait (which may also fail the quality test: the
  // frame is then lost although a pose was told). Preview tells it too, and Process once more when
  // it takes that frame later, so a frame's kept pose may come after newer frames' first poses
  // (the index tells them apart). A live application takes its poses here.
  using PoseListener = TrackingSide::PoseListener;
  void SetPoseListener(PoseListener listener) { tracking_.SetPoseListener(std::move(listener)); }
  // Threaded: waits until the mapping side has settled every keyframe handed to it (mapped, and
  // the young map's or loop adjustment after its publication done), but no later than `until`;
  // true when none is left (sequential: always). The realtime pace takes a frame only then, so that
  // it is tracked as in the sequential run (run/frame_backlog.h).
  bool WaitSettled(std::chrono::steady_clock::time_point until) const;
  // Tells the pose listener a provisional pose of frame `index`, tracked against the keyframe the
  // tracking side holds from the last frame Process kept, and changes nothing: for a frame that
  // Process takes later (the realtime pace's frames that wait while the mapping side is busy).
  // Nothing is told before the map starts, while lost, or when the alignment fails.
  void Preview(int index, const Image<float>& image, double exposure_ms) const;
  // Waits until the mapping side has done all the work handed to it (nothing to wait for when
  // sequential). The accessors below read the map: call this first when threaded.
  void Finish();

  // world_from_cam of every keyframe this run made (a loaded map's are left out: RestoreMap) /
  // every tracked frame, with the latest keyframe poses.
  Trajectory KeyframeTrajectory() const;
  Trajectory FrameTrajectory() const;
  const SystemStats& stats() const { return stats_; }
  int NumMapPoints() const;
  const Map& map() const { return mapping_.map(); }
  // Finishes (Finish), adjusts the whole map once (RunGlobalBundleAdjustment, unless it ran
  // already; a loaded map's keyframes held), then hands over the map with the window it ended
  // with, each keyframe's covisible keyframes, its noise handling and tracking levels, for a map
  // file: the System is left with an empty map and is not used again. Localising
  // (LoadedMapUse::kLocalize), it hands back the loaded map as it was taken up.
  StoredMap TakeStoredMap();
  // A new System (no frame given yet) takes up a map of a map file, as a map the camera left
  // (Suspend): lost, each frame is tried against it by relocalisation with nothing to predict
  // from (the camera may start anywhere in it), so three frames in a row must relocalise to poses
  // that move as one camera, and the next frame confirm it (FrameReport::resumed). From there it
  // tracks and maps in the loaded map's frame and scale, extending it. The map keeps its noise
  // handling; its tracking levels judge the first frames. The stats, trajectories and keyframe
  // logs are this run's: KeyframeTrajectory holds the keyframes it adds, not the loaded ones.
  // With LoadedMapUse::kLocalize the map is a reference the run does not change (localisation):
  // its keyframes and points are frozen (Keyframe::frozen) in every adjustment and never culled.
  // The keyframes the run makes are temporary: they track the camera where it leaves the mapped
  // area, and once a new keyframe sees the loaded map again (it has a loaded keyframe among its
  // covisible ones) every temporary keyframe outside the window is retired (Map::Retire), so the
  // map stays the loaded one plus the window. TakeStoredMap then gives back the loaded map as
  // it was taken up.
  enum class LoadedMapUse { kExtend, kLocalize };
  void RestoreMap(StoredMap stored, LoadedMapUse use = LoadedMapUse::kExtend);
  bool localizing() const { return mapping_.localizing(); }
  int retired_keyframes() const { return mapping_.retired_keyframes(); }  // Temporary keyframes retired so far.
  int loaded_keyframes() const { return mapping_.loaded_keyframes(); }  // Taken up by RestoreMap (0: none) ...
  int loaded_points() const { return mapping_.loaded_points(); }        // ... and their points (live ones).
  // The map's size as the tracking side last took it over (its tracking reference): keyframes
  // mapped and live points. For progress displays; safe between Process calls in every pace.
  struct MapSize {
    int keyframes = 0, points = 0;
  };
  MapSize TrackedMapSize() const;
  // Its MapSnapshot (null without SystemSetup::map_snapshots or before the map starts), and the
  // world_from_cam pose of the last tracked frame (none before the map starts); tracking side, as
  // TrackedMapSize.
  std::shared_ptr<const MapSnapshot> TrackedMapSnapshot() const;
  std::optional<SE3d> LastFramePose() const;
  // True once relocalisation failed options.relocalisation.max_lost_frames times in a row
  // (max_predicted_frames in a map that tracked at most young_map_frames frames): the camera is
  // somewhere the map does not cover, and the caller starts a new map (a new System).
  bool NeedsNewMap() const;
  // A map that has tracked at most relocalisation.young_map_frames frames: one the run gives up
  // for a loaded map the camera turns out to be in (system/atlas.h).
  bool Young() const { return stats_.frames_tracked <= young_map_frames_; }
  // The caller started a new map (NeedsNewMap) and keeps this one: frames are still tried against
  // it (Process, relocalisation only) but count in it from the relocalisation the next frame
  // confirms (FrameReport::resumed); until then lost frames leave no trace in its stats and
  // trajectory. The mapping side is idle meanwhile (nothing is handed to it while lost).
  void Suspend() { tracking_.Suspend(); }
  // Withdraws a relocalisation still waiting for the next frame's confirmation, as if that frame
  // had not confirmed it (the run ended first).
  void WithdrawTentative() { tracking_.WithdrawTentative(); }
  // Places (atlas_places.h): the run's place index this map's keyframes go into, given before the
  // first frame or RestoreMap (else the System's own), and what that index knows the map by.
  void JoinPlaces(AtlasPlaces* places) { mapping_.UsePlaces(places); }
  PlaceMap* place_map() { return mapping_.place_map(); }
  // Map merging (mapping_merge.cc; LoopClosureOptions): this map's new keyframes are compared
  // with the index's merge candidates (AtlasPlaces::SetMergeCandidates: place recognition and
  // the loop's verification against their keyframes, on this map's mapping side). The mapping
  // side reads them while this map tracks: the caller leaves them untouched meanwhile and
  // finishes this map's mapping side (Finish) before it uses one of them itself (system/atlas.h).
  // The Atlas's id of the candidate a keyframe recognised and verified, waiting to be merged (-1:
  // none); read without waiting for the mapping side.
  int MergeReady() const { return mapping_.MergeReady(); }
  // Takes the map MergeReady names, `other`, into this one, on the caller's thread once the mapping side is
  // finished (Finish): its keyframes and points follow this map's (ids shifted by this map's
  // keyframe and point counts), moved into this map's frame and scale by the verified Sim(3)
  //   S = K^-1 k_from_c C   (this world from the other's; K, C: the keyframe's and the
  //                           candidate's cam_from_world),
  // each keyframe's pose C_j S^-1 (its points' inverse depths over s, as a loop closure scales
  // them), and its tracked frames join this map's trajectory (FrameTrajectory, KeyframeTrajectory:
  // in time order). The other System is left with an empty map and no frames (its stats stay).
  // The next keyframes select the merged keyframes as covisible and re-observe their points, and
  // the merge's bundle adjustment follows (AdjustMerge). False, nothing changed, while a
  // relocalisation waits to be confirmed (the caller tries again with a later frame). `taken_id`:
  // the caller's name of the map taken in from here on (stats: SystemStats::MapMerge::map).
  bool MergeVerified(System& other, int taken_id);

  // What the tracking side does with the next frame (tracking_state.h).
  TrackingState state() const { return tracking_.state(); }

  // Bundle adjustment of every keyframe and point of the map (keyframe 0 fixed), once, at the end.
  void RunGlobalBundleAdjustment() { mapping_.RunGlobalBundleAdjustment(); }
  // Diagnostic (dsm run --truth-ba): each keyframe whose stamp `world_from_cam` has is set to its
  // pose there (its points move with it: their inverse depths are host-relative), then the whole
  // map is bundle-adjusted (keyframe 0 fixed) until an adjustment lowers the energy by less than
  // 0.1%, at most four times. Started from the true poses (in the map's frame and scale), the
  // keyframes end where the map's own energy has its minimum: how far that lies from the truth
  // is the bias of what the map holds (its points, observations and error models), apart from any
  // drift on the way.
  void AdjustWholeMapFrom(const Trajectory& world_from_cam);

  // The keyframes of the current window: temporal (oldest first) then covisible.
  std::vector<int> ActiveKeyframes() const { return mapping_.ActiveKeyframes(); }
  // Live points hosted by the window's keyframes.
  std::vector<int> ActivePointIds() const { return mapping_.ActivePointIds(); }

 private:
  SystemStats stats_;  // The tracking side writes its TrackingStats, the mapping side its MappingStats.
  int young_map_frames_;
  MappingSide mapping_;
  TrackingSide tracking_;
  std::unique_ptr<class MappingThread> mapping_thread_;  // Threaded only; joined first.
};

}  // namespace dsm
