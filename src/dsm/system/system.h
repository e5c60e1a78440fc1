// SPDX-License-Identifier: MIT
// The system facade: feed undistorted frames in order, get poses.
//
// Two sides, as the paper's two threads (section III). The tracking side (Process, on the caller's
// thread) initialises, builds the frame's pyramid, tracks it against the newest keyframe the
// mapping side has finished, and decides whether it becomes a keyframe. The mapping side refines
// the candidates of the temporal keyframes along their epipolar lines with every tracked frame, and
// maps a new keyframe: observations of the window's points in it, it enters the temporal window
// (one keyframe leaves), old keyframes covisible with it join the window (DSM mode) with their
// points' re-observations, candidates are activated where the view is still depleted, the
// photometric bundle adjustment runs over the window, points are culled, and the tracking side
// gets the keyframe as its new reference; then the keyframe's own candidates are selected (the
// tracking side goes on meanwhile: nothing it reads depends on them).
//
// With SystemSetup::threaded false (the default) the mapping work runs inside Process: every
// keyframe is mapped before the next frame, and the output is deterministic. With it true the
// mapping side runs on its own thread (mapping_thread.h); the two share nothing but the jobs
// handed over (frame pyramid, pose relative to its reference keyframe, brightness) and the
// published tracking reference (TrackingReference, an immutable snapshot). While a keyframe is
// still being mapped the tracking side goes on against the older reference; when it wants another
// keyframe meanwhile, it waits for the pending one first (SystemSetup::wait_for_mapping) or makes
// it once the pending one is mapped: at most one keyframe is in flight.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/image/image.h"
#include "dsm/image/signature.h"
#include "dsm/map/map.h"
#include "dsm/lie/sim3.h"
#include "dsm/map/stored_map.h"
#include "dsm/mapping/map_points.h"
#include "dsm/system/handover.h"
#include "dsm/system/loop_state.h"
#include "dsm/system/options.h"
#include "dsm/system/system_stats.h"
#include "dsm/system/tracking_state.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/tracking_quality.h"

namespace dsm {

enum class TrackingStatus { kInitializing, kOk, kLost };
std::string TrackingStatusName(TrackingStatus status);

struct FrameReport {
  int index = -1;
  TrackingStatus status = TrackingStatus::kInitializing;
  std::string reason;       // For kInitializing / kLost.
  bool keyframe = false;
  bool relocalised = false;  // Tracking regained after lost frames (kOk).
  // A suspended System's relocalisation confirmed by this frame: the camera is back in its map,
  // which counts frames again (System::Suspend).
  bool resumed = false;
  double tracking_ms = 0.0;  // Pyramid and alignment.
  double wait_ms = 0.0;      // Waiting for a keyframe to be mapped first (threaded).
  double mapping_ms = 0.0;   // Sequential: its candidate tracing, and its mapping when it became a keyframe.
  // Its pose was told before it waited for a keyframe being mapped (System::SetPoseListener).
  bool posed_before_wait = false;
  // Where its wait for a keyframe being mapped ended, or would have (none before the map starts):
  // what comes after is the work a realtime wait has to leave time for (run/realtime_wait.h).
  std::optional<std::chrono::steady_clock::time_point> wait_end;
};

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
  using PoseListener = std::function<void(int index, const SE3d& world_from_cam)>;
  void SetPoseListener(PoseListener listener) { pose_listener_ = std::move(listener); }
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
  const Map& map() const { return map_; }
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
  bool localizing() const { return localizing_; }
  int retired_keyframes() const { return retired_keyframes_; }  // Temporary keyframes retired so far.
  int loaded_keyframes() const { return loaded_keyframes_; }  // Taken up by RestoreMap (0: none) ...
  int loaded_points() const { return loaded_points_; }        // ... and their points (live ones).
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
  bool Young() const { return stats_.frames_tracked <= options_.relocalisation.young_map_frames; }
  // The caller started a new map (NeedsNewMap) and keeps this one: frames are still tried against
  // it (Process, relocalisation only) but count in it from the relocalisation the next frame
  // confirms (FrameReport::resumed); until then lost frames leave no trace in its stats and
  // trajectory. The mapping side is idle meanwhile (nothing is handed to it while lost).
  void Suspend() { suspended_ = true; }
  // Withdraws a relocalisation still waiting for the next frame's confirmation, as if that frame
  // had not confirmed it (the run ended first).
  void WithdrawTentative() {
    if (state_ == TrackingState::kConfirming) WithdrawRelocalisation();
  }
  // Map merging (system_merge.cc; LoopClosureOptions). The other maps of the run that this map's
  // new keyframes are compared with: place recognition and the loop's
  // verification (system_loop.cc) against their keyframes, on this map's mapping side. `id`: the
  // caller's name of each. The mapping side reads them while this map tracks: the caller leaves
  // them untouched meanwhile and finishes this map's mapping side (Finish) before it uses one of
  // them itself (system/atlas.h). Set while the mapping side is idle.
  void SetMergeSources(const std::vector<std::pair<int, System*>>& sources);
  // The id of the source a keyframe recognised and verified, waiting to be merged (-1: none); read
  // without waiting for the mapping side.
  int MergeReady() const { return loop_.merge_ready.load(); }
  // Takes the map MergeReady names into this one, on the caller's thread once the mapping side is
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
  bool MergeVerified(int taken_id);

  // What the tracking side does with the next frame (tracking_state.h).
  TrackingState state() const { return state_; }

  // Bundle adjustment of every keyframe and point of the map (keyframe 0 fixed), once, at the end.
  void RunGlobalBundleAdjustment();
  // Diagnostic (dsm run --truth-ba): each keyframe whose stamp `world_from_cam` has is set to its
  // pose there (its points move with it: their inverse depths are host-relative), then the whole
  // map is bundle-adjusted (keyframe 0 fixed) until an adjustment lowers the energy by less than
  // 0.1%, at most four times. Started from the true poses (in the map's frame and scale), the
  // keyframes end where the map's own energy has its minimum: how far that lies from the truth
  // is the bias of what the map holds (its points, observations and error models), apart from any
  // drift on the way.
  void AdjustWholeMapFrom(const Trajectory& world_from_cam);

  // The keyframes of the current window: temporal (oldest first) then covisible.
  std::vector<int> ActiveKeyframes() const;
  // Live points hosted by the window's keyframes.
  std::vector<int> ActivePointIds() const;

 private:
  struct FrameRecordInternal {
    int64_t t_ns = 0;
    int reference = -1;          // Keyframe id the pose is relative to.
    SE3d frame_from_reference;
    // > 0 for the frames between the two initial keyframes: the distance between the two when the
    // frame was tracked. The first bundle adjustments still rescale the young map about keyframe 0
    // (held fixed), by ~5% on a hand-held start, so the frame's offset from its keyframe (0 or 1)
    // is scaled by that distance's change.
    double init_baseline = 0.0;
    // The reference keyframe's scale (keyframe_scale_) when the frame was tracked: a loop closure
    // that rescales the keyframe later scales the frame's offset from it alike.
    double reference_scale = 1.0;
  };
  struct PendingFrame {
    int index;
    int64_t t_ns;
    double exposure;
    std::shared_ptr<const ImagePyramid> pyramid;
  };
  // The frame Process works on: what it was given, what the quality test found, what it reports.
  struct FrameWork {
    int index = -1;
    int64_t t_ns = 0;
    double exposure = 1.0;
    std::shared_ptr<const ImagePyramid> pyramid;
    FrameSignature signature;
    double previous_texture = 0.0;  // FrameSignature::texture of the frame before.
    FrameReport report;
    std::string reason;  // Why it fails the quality test; empty while it passes.
    TrackResult result;  // Its alignment, against reference_ when `tracked`.
    bool tracked = false;
    bool waited = false;     // It waited for the keyframe in flight before it was tracked.
    bool confirmed = false;  // It confirmed a relocalisation.
    SE3d relocalised_velocity;  // Relocalised: the camera's motion per frame through the loss.
    std::chrono::steady_clock::time_point t0;  // Start of its tracking time (waits left out).
  };
  // Process's steps (system.cc), in order: the waits the frame before asked for, the pyramid and
  // the image's test; the alignment with the reference and its test (TrackAndJudge), again after
  // the keyframe in flight when it failed, withdrawing an unconfirmed relocalisation; the
  // relocalisation of a lost frame; the pose taken; the frame handed to the mapping side, as a
  // keyframe when the keyframe decision says so.
  FrameWork BeginFrame(int index, int64_t t_ns, const Image<float>& image, double exposure);
  void TrackAndJudge(FrameWork* f);
  void TrackAgainstReference(FrameWork* f);
  void TryRelocalise(FrameWork* f);
  void AcceptPose(FrameWork* f);
  void HandToMappingSide(FrameWork* f);
  // The one place the tracking state changes: NextTrackingState, which must know the event.
  void Transition(TrackingEvent event);
  // The realtime pace's wait (system_pace.cc): while a keyframe is still being mapped, the frame
  // waits for it until `until` and is tracked against it (a pose told first, SetPoseListener).
  void WaitForNewerKeyframe(FrameWork* f, std::chrono::steady_clock::time_point until);
  // Waits for the keyframes being mapped (until `until`, or for good), then takes the newest
  // reference; the wait is left out of f's tracking time. True when the reference changed.
  bool WaitForMapping(FrameWork* f, std::optional<std::chrono::steady_clock::time_point> until);

  // On the first frame (or a loaded map's): its noise level, and from it whether the candidates' contrast floor applies
  // (candidate_selector.h: from candidates.contrast_min_noise on), how residuals sample images and
  // whether the texture-loss test is on.
  void ChooseNoiseHandling(double noise_sigma);
  FrameReport Initialize(int index, int64_t t_ns, const Image<float>& image, double exposure);
  void StartMap(const struct InitResult& init);
  // The best alignment of the frame against the reference from the motion guesses; commits nothing.
  // world_from_cam of a frame at `frame_from_reference` from the tracking reference.
  SE3d WorldFromCam(const SE3d& frame_from_reference) const;
  TrackResult TrackFrame(int index, const ImagePyramid& pyramid, double exposure) const;
  // The camera's turn through a rolling shutter's readout, as over the last frame step (none with
  // a global shutter or before a frame is trusted).
  ReadoutTurn Readout() const;
  // A frame's pyramid as a global shutter at its timestamp would have seen it, the camera turning
  // by `turn` through the readout (tracking/rolling_shutter.h); without gradients.
  std::shared_ptr<const ImagePyramid> GlobalShutterPyramid(const ImagePyramid& pyramid, const ReadoutTurn& turn) const;
  // The frame's pose and brightness relative to the reference become the last trusted ones; the
  // velocity is the step from the last trusted frame per frame, or `velocity` when given.
  void CommitPose(int index, const TrackResult& result, double exposure, std::optional<SE3d> velocity);
  // Whether a frame was trusted in this run: not so in a loaded map before the camera is found in
  // it (RestoreMap), where there is nothing to predict from.
  bool HasTrustedFrame() const { return track_.last_trusted_index >= 0; }
  // Frames from the last trusted frame to `index` (at least 1): index steps, or the frame
  // intervals between their timestamps when more (a gap in the recording).
  int FramesSinceTrusted(int index) const;
  // Process: frame `index` at t_ns is the current one; the frame interval follows the recording.
  // Throws InputError, changing nothing, when index or t_ns does not come after the last frame's.
  void NoteTimestamp(int index, int64_t t_ns);
  // A lost frame: counted, its episode opened or extended.
  FrameReport LostFrame(FrameReport report, int64_t t_ns, std::string reason);
  // While lost (system_relocalisation.cc): aligns the frame with the reference and the keyframes most
  // like it, from the last trusted pose; on success the keyframe it passed the quality test against
  // becomes the reference and `result` holds the frame's pose relative to it, `velocity` the
  // camera's motion per frame through the loss (cam_now_from_cam_before). `reason`: why not.
  // `plain`: empty when the frame has the usual texture, else why not
  // (TrackingQuality::CheckRelocalisationImage); such a frame is accepted only by three sightings
  // that move as one camera, never by the prediction.
  // `evidence`: what the accepted pose rests on (SystemStats::Relocalisation).
  bool Relocalise(int index, const ImagePyramid& pyramid, const FrameSignature& signature, double exposure,
                  const std::string& plain, TrackResult* result, SE3d* velocity, std::string* reason,
                  SystemStats::Relocalisation* evidence);
  // Relocalise's keyframes to align with: the reference first, then up to
  // relocalisation.candidates keyframes; `frame_features`: the frame's ORB features; `matches`:
  // theirs with each candidate but the reference (MatchFeatures).
  std::vector<int> RelocalisationCandidates(const ImagePyramid& pyramid, const FrameSignature& signature, int ref,
                                            OrbFeatures* frame_features,
                                            std::map<int, std::vector<cv::DMatch>>* matches);
  // Relocalise's starting poses of frame `index` relative to keyframe k: the features' pose, `still`
  // (the last trusted pose relative to k) and it moved by each of `motions`, each also turned
  // about x and y, k's own pose (k not the reference), and from `first_sighted` on the sightings'.
  std::vector<SE3d> RelocalisationGuesses(int index, int k, const SE3d& still, const std::array<SE3d, 2>& motions,
                                          const FeaturePose& feature_pose, size_t* first_sighted) const;
  // A lost frame's best alignment with the map that passed the quality test (camera in the world).
  struct Sighting {
    int index = -1;
    SE3d cam_from_world;
  };
  // True when the sightings of the two lost frames before and this one move as one camera does.
  bool MovesAsOneCamera(const Sighting& now, double mean_idepth) const;
  // The tracking side's state that each frame moves on (CommitPose, LostFrame), kept whole by a
  // tentative relocalisation and put back when it is withdrawn.
  struct TrackingHistory {
    // velocity: the camera's motion per frame index (frame_from_previous over one index step;
    // frames dropped or skipped between two trusted ones divide their step).
    SE3d last_frame_from_reference, velocity;
    int last_trusted_index = -1;  // Frame index of the last trusted frame ...
    int64_t last_trusted_t_ns = 0;  // ... and its timestamp.
    double alpha = 0.0, beta = 0.0;  // Brightness of the last frame relative to the reference.
    double exposure = 1.0;           // The last frame's exposure.
    double first_rmse_after_keyframe = 0.0;
    TrackingQuality quality{QualityOptions{}};
    int lost_in_a_row = 0;           // Lost frames since the last trusted one.
    int failed_relocalisations = 0;  // Frames relocalisation tried and failed since the last trusted one.
  };
  // The tracking side's state before a relocalisation of frame `index`, restored when the next
  // frame does not confirm it.
  struct Tentative {
    int index = -1;
    size_t record = 0;  // The relocalised frame's entry in frames_.
    std::shared_ptr<const TrackingReference> reference;
    TrackingHistory state;
    SystemStats::Relocalisation evidence;  // Of the relocalisation, counted once confirmed.
  };
  Tentative SaveTentative(int index) const;
  void WithdrawRelocalisation();
  // Points observed in keyframe kf (hosted, or an inlier observation), for tracking against it.
  std::vector<ReferencePoint> PointsSeenIn(int kf);
  // Tracking side: takes the newest published reference (waiting for the pending keyframe first
  // when `wait`), and moves the last frame's pose and brightness onto it.
  void UpdateReference(bool wait);
  void Submit(MappingJob job);
  // A job of the mapping side, after the ones handed over before (inline when sequential);
  // `keyframe`: counted as a keyframe being mapped (UpdateReference waits for it).
  void RunOnMappingSide(std::function<void()> job, bool keyframe = false);
  // The initialisation frames the mapping side tracked, into the frame records (at Finish, once
  // the mapping side is idle).
  void MergeInitTracked();
  double InitBaseline() const;  // Distance between keyframes 0 and 1 (their camera centres).
  // On the mapping side, once keyframe kInitTrackingKeyframe is mapped (or at Finish): tracks
  // init_between_ into init_tracked_.
  void TrackInitFrames();
  // Seeds the quality test's levels of a new map (TrackingQuality::Seed): the textures of the
  // initialiser's frames, and the residual of `neighbour` tracked from `guess` (frame_from_reference).
  void SeedQuality(const PendingFrame& neighbour, const SE3d& guess, const std::vector<double>& textures);
  static constexpr int kInitTrackingKeyframe = 4;
  // The points among `ids` the bundle adjustment saw in keyframe `kf`, projected into it
  // (`adjusted` false: before kf's first bundle adjustment, every point that projects into it).
  std::vector<ReferencePoint> ReferencePointsIn(int kf, const std::vector<int>& ids, bool adjusted = true);
  // Mapping side.
  void RunJob(const MappingJob& job);  // Traces candidates; maps the frame when it is a keyframe.
  void RunFinishJob(int kf);           // FinishKeyframe, timed.
  void TraceCandidates(const ImagePyramid& pyramid, int reference, const SE3d& frame_from_reference, double alpha,
                       double beta, double exposure);
  void CreateKeyframe(int index, int64_t t_ns, std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                      const SE3d& cam_from_world, const AffineBrightness& affine);
  // Hands keyframe kf with `points` to the tracking side (it takes them in UpdateReference).
  void PublishReference(int kf, std::vector<ReferencePoint> points);
  // The snapshot of keyframe kf with `points`; `pyramid`: kf's, when the map holds none (released).
  std::shared_ptr<const TrackingReference> MakeReference(int kf, std::vector<ReferencePoint> points,
                                                         std::shared_ptr<const ImagePyramid> pyramid = nullptr) const;
  // Tracking side, while the mapping side is idle (lost): `ref` becomes the reference of both sides.
  void AdoptReference(std::shared_ptr<const TrackingReference> ref);
  // Maps keyframe kf and publishes it as the tracking reference.
  void MapNewKeyframe(int kf);
  // One bundle adjustment of every keyframe (keyframe 0 fixed) and point.
  PbaSummary AdjustWholeMap();
  // `held` and the keyframes of a loaded map (RestoreMap): the map a later session extends is its
  // reference, so their poses stay where the file has them in every adjustment and the session's
  // poses are in its frame and scale (their points' depths are still refined).
  std::vector<int> HeldWithLoaded(std::vector<int> held) const;
  std::vector<int> AllKeyframes() const;  // 0 .. NumKeyframes() - 1 but the retired ones.
  // A young map's or loop bundle adjustment (AdjustYoungMap, AdjustLoop). Threaded
  // (SystemSetup::yield_adjustments), it stops for a keyframe waiting to be mapped and is taken
  // up after it, as another mapping job, and for a relocalisation waiting for the mapping side to
  // be idle, taken up after the next keyframe (parked_): a whole-map adjustment of the young map
  // takes about a second, which the next keyframe, and the frames tracked against the one before
  // it, would otherwise wait through (in the realtime pace, frames dropped while a frame that
  // failed against the old keyframe waited for the new one).
  struct Adjustment {
    bool young = false;                // All keyframes at the time each part runs.
    std::vector<int> keyframes, held;  // Else these (RunPba's active and held).
    PbaOptions options;
    size_t log = 0;   // The stats_.per_keyframe entry of the keyframe it follows.
    size_t stat = 0;  // Its entry in stats_.young_map_ba_ms or stats_.loop_ba_ms.
    int level = -1, iterations = 0;  // Where to take it up (PbaYield).
  };
  void Adjust(Adjustment a);
  // Runs the rest of the adjustments that stopped for a relocalisation; true when there were any.
  bool RunParked();
  // The loop bundle adjustment (SystemOptions::loop_ba_min_gap, loop_ba_after_relocalisation)
  // after keyframe `newest` is published (FinishKeyframe), when due; true when it ran.
  bool AdjustLoop(int newest);
  // The seam adjustment after a relocalisation (SystemOptions::seam_ba_count) after keyframe
  // `newest` is published, when due; true when it ran.
  bool AdjustSeam(int newest);
  // The part mapped since the last relocalisation moved onto the older map when keyframe `newest`
  // sees that map's points as outliers (SystemOptions::rejoin_min_outliers); true when it moved.
  bool RejoinAfterRelocalisation(int newest);
  // A loop or seam adjustment of `keyframes` (`held` among them stay fixed), logged with the newest
  // keyframe's entry and in stats_.loop_ba_ms.
  // The PBA options of a loop or merge adjustment (SystemOptions::loop_ba_max_iterations).
  PbaOptions LoopBaOptions() const;
  void AdjustAfterNewest(std::vector<int> keyframes, std::vector<int> held, const PbaOptions& pba, bool seam);
  // The young map's bundle adjustment (SystemOptions::young_map_ba_first) after the newest
  // keyframe is published, when due; true when it ran.
  bool AdjustYoungMap();
  // What the tracking reference does not need, done after it is published: kf's candidates (traced
  // in the frames that follow), the young map's and the loop adjustments when due, and the release
  // of pyramids no longer used.
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
  // adjustment no longer has them among its cameras (`in_use`): until then their observations
  // still tie the window to the map as it was just before.
  void CullUnusedKeyframes(const std::vector<int>& in_use);
  // Localisation (LoadedMapUse::kLocalize): once keyframe `newest` sees the loaded map again, the
  // temporary keyframes outside the window leave the map (Map::Retire).
  void RetireTemporaries(int newest);
  // Loop closure (system_loop.cc; LoopClosureOptions), mapping side. Keyframe k's ORB features,
  // detected on first use (keyframe_features_).
  const OrbFeatures& KeyframeFeatures(int k);
  bool LoopClosureActive() const;
  void AddToPlaceIndex(int k);
  // Adds keyframe kf to the place index, and closes a loop when it finds one; true when it did.
  bool DetectAndCloseLoop(int kf);
  // `owner`: the System whose map has c (this one, or a merge source).
  bool VerifyLoop(int kf, System& owner, int c, LoopMatch* match);
  // Keyframe kf (bag of words `bow`, score floor `floor`) against the merge sources' keyframes; a
  // verified match waits in loop_.pending_merge for MergeVerified.
  void DetectMerge(int kf, const BowVector& bow, double floor);
  // The bundle adjustment that joins the last merged map to this one, once keyframe `newest`'s
  // window re-observes its points (a merged keyframe among the covisible ones); true when it ran.
  bool AdjustMerge(int newest);
  // The pose and brightness graphs with the loop edge; every keyframe and its points moved
  // (stats_.loops_closed). `shared`: the observations each pair of live keyframes (i < j) shares.
  void CorrectLoop(int kf, const LoopMatch& match, const std::map<std::pair<int, int>, int>& shared);
  void SelectCandidates(int kf);
  void PublishTrackingReference();
  // Threaded: a newer reference was published than the one the tracking side holds.
  bool ReferenceIsStale() const;
  // Covisible keyframes and their points' re-observations in `newest`, except hidden ones.
  void SelectCovisible(int newest, OcclusionGrid* occlusion);
  void AddToOcclusionGrid(const std::vector<int>& keyframes, int target, OcclusionGrid* grid) const;

  PinholeCamera camera_;
  SystemOptions options_;
  SystemSetup setup_;
  // Mapping side (or the caller's thread before the map starts).
  Map map_;
  std::vector<int> window_;     // Temporal window, oldest first.
  std::vector<int> covisible_; // Covisible part of the window (DSM mode).
  int last_loop_ba_ = -1;       // Keyframe after which the last loop bundle adjustment ran.
  int relocalisations_mapped_ = 0;  // The tracking side's count as the last job brought it.
  int seam_first_ = -1;             // The first keyframe mapped after the last relocalisation (-1: none).
  int rejoin_first_ = -1;           // The same, until that part was rejoined (-1: none).
  bool loop_ba_pending_ = false;    // A relocalisation since the last loop bundle adjustment.
  std::vector<Eigen::Vector2f> old_pixels_;  // Newest-keyframe pixels of old, unselected map points.
  std::map<int, std::vector<Candidate>> candidates_;
  float min_activation_distance_px_;
  double keyframe_ms_ = 0.0;  // The last keyframe's mapping time up to its publication.
  // Handed from the mapping side to the tracking side.
  mutable std::mutex reference_mutex_;
  std::shared_ptr<const TrackingReference> published_;
  std::unique_ptr<class MappingThread> mapping_thread_;  // Threaded only.
  // Tracking side.
  std::unique_ptr<class Initializer> initializer_;
  std::vector<PendingFrame> pending_;
  std::unique_ptr<class FrameTracker> tracker_;
  std::shared_ptr<const TrackingReference> reference_;  // The tracker's.
  PoseListener pose_listener_;
  int next_keyframe_ = 0;         // Id of the next keyframe the tracking side makes.
  int last_frame_keyframe_ = -1;  // The keyframe made from the last tracked frame, if any.
  // What the next frame waits for before it is tracked (threaded): the keyframe in flight, when
  // this frame wanted to become a keyframe meanwhile (SystemSetup::wait_for_mapping), and the
  // keyframe made from the frame that confirmed a relocalisation (always).
  struct PendingWaits {
    bool for_pending_keyframe = false;
    bool for_confirming_keyframe = false;
  };
  PendingWaits waits_;
  std::vector<FrameRecordInternal> frames_;
  // Records of the frames between the two initial keyframes as the mapping side tracked them
  // (TrackInitFrames), merged into frames_ by MergeInitTracked.
  std::vector<FrameRecordInternal> init_tracked_;
  struct InitBetween {
    std::vector<PendingFrame> frames;  // Between keyframes 0 and 1, in order.
    SE3d kf1_from_kf0;                 // From the two-view start.
    int steps = 1;                     // Frame steps from keyframe 0 to keyframe 1.
  };
  InitBetween init_between_;  // Set by StartMap, tracked on the mapping side (TrackInitFrames).
  TrackingHistory track_;
  // The frame being processed, the last one seen before it, the recording's frame interval (0:
  // not known yet) and the steps it is the median of (NoteTimestamp).
  int64_t current_t_ns_ = 0, seen_t_ns_ = 0;
  int seen_index_ = -1;
  double frame_interval_ns_ = 0.0;
  std::deque<double> interval_steps_;
  double previous_texture_ = 0.0;  // FrameSignature::texture of the frame before, whatever became of it.
  TrackingState state_ = TrackingState::kInitializing;  // Changed by Transition alone.
  bool suspended_ = false;              // Suspend: the map is set aside; its frames count once it is back.
  std::optional<Tentative> tentative_;  // Set in TrackingState::kConfirming.
  std::deque<Sighting> sightings_;      // Of the last lost frames (at most two), oldest first.
  // ORB features of the keyframes relocalisation ranked, computed on first use, or by the mapping
  // side for every keyframe (SystemSetup::keyframe_features). Written by the mapping side only
  // in its jobs, read and written by the tracking side only while lost, after the mapping side went
  // idle (Relocalise; nothing is handed to it while lost).
  std::map<int, OrbFeatures> keyframe_features_;
  // Mapping side: adjustments stopped for a relocalisation, taken up after the next keyframe.
  std::vector<Adjustment> parked_;
  // RestoreMap: the keyframes and live points loaded, the covisible keyframes each was mapped
  // with, and the camera's speed per frame as the map has it (between consecutive keyframes),
  // the reach that judges its first sightings (MovesAsOneCamera).
  int loaded_keyframes_ = 0, loaded_points_ = 0;
  // LoadedMapUse::kLocalize: the map is a frozen reference; `loaded_as_` is the stored map's
  // window, covisibility and levels (its map empty) that TakeStoredMap gives back, and
  // loaded_point_ids_ the points it had (ids below that are its own).
  bool localizing_ = false;
  StoredMap loaded_as_;
  int loaded_point_ids_ = 0;
  int retired_keyframes_ = 0;  // Localisation's temporary keyframes retired (culled ones: stats_).
  std::vector<int> cull_pending_;  // Left the temporal window, not judged yet (CullUnusedKeyframes).
  LoopState loop_;  // Loop closure and map merging, mapping side.
  // Per keyframe id: the product of the scales loop closures gave it (its hosted geometry is that
  // much smaller than when it was mapped); missing entries are 1.
  std::vector<double> keyframe_scale_;
  double KeyframeScale(int k) const { return k < static_cast<int>(keyframe_scale_.size()) ? keyframe_scale_[k] : 1.0; }
  std::vector<std::vector<int>> loaded_covisibility_;
  double loaded_speed_ = 0.0;
  SystemStats stats_;  // Counts of frames and tracking times by the tracking side, the rest by the mapping side.
};

}  // namespace dsm
