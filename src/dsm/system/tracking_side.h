// SPDX-License-Identifier: MIT
// The tracking side of a System (the paper's tracking thread, section III), on the caller's
// thread: it initialises the map, builds each frame's pyramid, tracks it against the newest
// keyframe the mapping side published and judges it by the quality test (tracking_quality.h),
// relocalises a lost camera, keeps the frame clock and each frame's pose, and decides which
// frames become keyframes. It owns its state machine (tracking_state.h), the reference it tracks
// against and the frame records; it reaches the mapping side only through MappingInbox
// (handover.h): jobs handed over, references taken, and the map lent while the mapping side is
// idle (relocalisation).
#pragma once

#include <array>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/image/image.h"
#include "dsm/image/signature.h"
#include "dsm/system/handover.h"
#include "dsm/system/options.h"
#include "dsm/system/system_stats.h"
#include "dsm/system/tracking_state.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/tracking_quality.h"

namespace dsm {

class Initializer;

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
  double tracking_rmse = 0.0;  // Of its alignment's gradient-weighted residuals at level 0 (kOk).
  double wait_ms = 0.0;      // Waiting for a keyframe to be mapped first (threaded).
  double mapping_ms = 0.0;   // Sequential: its candidate tracing, and its mapping when it became a keyframe.
  // Its pose was told before it waited for a keyframe being mapped (System::SetPoseListener).
  bool posed_before_wait = false;
  // Where its wait for a keyframe being mapped ended, or would have (none before the map starts):
  // what comes after is the work a realtime wait has to leave time for (run/realtime_wait.h).
  std::optional<std::chrono::steady_clock::time_point> wait_end;
};

class TrackingSide {
 public:
  using PoseListener = std::function<void(int index, const SE3d& world_from_cam)>;
  TrackingSide(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup,
               TrackingStats* stats, MappingInbox* mapping);
  ~TrackingSide();

  // System::Process (which checks the image's size), System::Preview, System::SetPoseListener.
  FrameReport Process(int index, int64_t t_ns, const Image<float>& image, double exposure,
                      std::optional<std::chrono::steady_clock::time_point> wait_until);
  void Preview(int index, const Image<float>& image, double exposure_ms) const;
  void SetPoseListener(PoseListener listener) { pose_listener_ = std::move(listener); }

  const PinholeCamera& camera() const { return camera_; }
  TrackingState state() const { return state_; }
  bool NeedsNewMap(bool young) const;  // System::NeedsNewMap.
  void Suspend() { suspended_ = true; }
  void WithdrawTentative() {
    if (state_ == TrackingState::kConfirming) WithdrawRelocalisation();
  }
  std::optional<SE3d> LastFramePose() const;
  const TrackingReference* reference() const { return reference_.get(); }
  // Its quality levels (TrackingQuality), kept with a map file.
  double ResidualLevel() const { return track_.quality.ResidualLevel(); }
  double TextureLevel() const { return track_.quality.TextureLevel(); }

  // Every frame's record, in time order (System::FrameTrajectory).
  const std::vector<FramePose>& frames() const { return frames_; }
  // The records of the frames between the two initial keyframes, tracked by the mapping side.
  void MergeInitTracked(std::vector<FramePose> tracked);
  // A merged map's tracked frames (`other`, its keyframes' ids here shifted by `offset`, its initial
  // keyframes `other_baseline` apart), into this map's in time order; the keyframes made from here
  // on follow the map's `num_keyframes`.
  void MergeFrames(const std::vector<FramePose>& other, int offset, double other_baseline, int num_keyframes);
  std::vector<FramePose> TakeFrames() { return std::exchange(frames_, {}); }
  int next_keyframe() const { return next_keyframe_; }

  // A loaded map taken up (System::RestoreMap): lost in it, against the reference the mapping
  // side published, with the map's speed per frame and the quality levels the file kept.
  void TakeUpLoadedMap(int num_keyframes, double speed, double residual_level, double texture_level);

 private:
  struct PendingWaits {
    bool for_pending_keyframe = false;
    bool for_confirming_keyframe = false;
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
  // Process's steps (tracking_side.cc), in order: the waits the frame before asked for, the
  // pyramid and the image's test; the alignment with the reference and its test (TrackAndJudge),
  // again after the keyframe in flight when it failed, withdrawing an unconfirmed
  // relocalisation; the relocalisation of a lost frame; the pose taken; the frame handed to the
  // mapping side, as a keyframe when the keyframe decision says so.
  FrameWork BeginFrame(int index, int64_t t_ns, const Image<float>& image, double exposure);
  void TrackAndJudge(FrameWork* f);
  void TrackAgainstReference(FrameWork* f);
  void TryRelocalise(FrameWork* f);
  void AcceptPose(FrameWork* f);
  void HandToMappingSide(FrameWork* f);
  void Transition(TrackingEvent event);  // The one place the state changes (NextTrackingState).
  // The realtime pace's wait (tracking_pace.cc): while a keyframe is still being mapped, the frame
  // waits for it until `until` and is tracked against it (a pose told first).
  void WaitForNewerKeyframe(FrameWork* f, std::chrono::steady_clock::time_point until);
  // Waits for the keyframes being mapped (until `until`, or for good), then takes the newest
  // reference; the wait is left out of f's tracking time. True when the reference changed.
  bool WaitForMapping(FrameWork* f, std::optional<std::chrono::steady_clock::time_point> until);
  // Takes the newest published reference (waiting for the pending keyframe first when `wait`),
  // and moves the last frame's pose and brightness onto it.
  void UpdateReference(bool wait);
  // While the mapping side is idle: `ref` becomes the reference of both sides.
  void AdoptReference(std::shared_ptr<const TrackingReference> ref, IdleMap& map);
  bool ReferenceIsStale() const;  // Threaded: a newer reference was published than the one held.

  // The map's start (tracking_start.cc): frames go to the initialiser until two views start it.
  FrameReport Initialize(int index, int64_t t_ns, const Image<float>& image, double exposure);
  void StartMap(const struct InitResult& init);
  // Seeds the quality test's levels of a new map (TrackingQuality::Seed): the textures of the
  // initialiser's frames, and the residual of `neighbour` tracked from `guess`.
  void SeedQuality(const InitFrame& neighbour, const SE3d& guess, const std::vector<double>& textures);

  SE3d WorldFromCam(const SE3d& frame_from_reference) const;  // Of a frame posed against the reference.
  // The best alignment of the frame against the reference from the motion guesses; commits nothing.
  TrackResult TrackFrame(int index, const ImagePyramid& pyramid, double exposure) const;
  // The camera's turn through a rolling shutter's readout, as over the last frame step (none with
  // a global shutter or before a frame is trusted).
  ReadoutTurn Readout() const;
  // The frame's pose and brightness relative to the reference become the last trusted ones; the
  // velocity is the step from the last trusted frame per frame, or `velocity` when given.
  void CommitPose(int index, const TrackResult& result, double exposure, std::optional<SE3d> velocity);
  // Whether a frame was trusted in this run: not so in a loaded map before the camera is found in
  // it, where there is nothing to predict from.
  bool HasTrustedFrame() const { return track_.last_trusted_index >= 0; }
  // Frames from the last trusted frame to `index` (at least 1): index steps, or the frame
  // intervals between their timestamps when more (a gap in the recording).
  int FramesSinceTrusted(int index) const;
  // Frame `index` at t_ns is the current one; the frame interval follows the recording. Throws
  // InputError, changing nothing, when index or t_ns does not come after the last frame's.
  void NoteTimestamp(int index, int64_t t_ns);
  FrameReport LostFrame(FrameReport report, int64_t t_ns, std::string reason);  // Counted; its episode.

  // Relocalisation (tracking_relocalisation.cc), while lost: aligns the frame with the reference
  // and the keyframes most like it, from the last trusted pose; on success the keyframe it passed
  // the quality test against becomes the reference and `result` holds the frame's pose relative
  // to it, `velocity` the camera's motion per frame through the loss. `reason`: why not. `plain`:
  // empty when the frame has the usual texture, else why not (such a frame is accepted only by
  // three sightings that move as one camera). `evidence`: what the accepted pose rests on.
  bool Relocalise(int index, const ImagePyramid& pyramid, const FrameSignature& signature, double exposure,
                  const std::string& plain, TrackResult* result, SE3d* velocity, std::string* reason,
                  TrackingStats::Relocalisation* evidence);
  // Relocalise's keyframes to align with: the reference first, then up to
  // relocalisation.candidates keyframes; `frame_features`: the frame's ORB features; `matches`:
  // theirs with each candidate but the reference.
  std::vector<int> RelocalisationCandidates(IdleMap& idle, const ImagePyramid& pyramid, const FrameSignature& signature,
                                            int ref, OrbFeatures* frame_features,
                                            std::map<int, std::vector<cv::DMatch>>* matches);
  // Relocalise's starting poses of frame `index` relative to keyframe k (of `map`): the features'
  // pose, `still` (the last trusted pose relative to k) and it moved by each of `motions`, each
  // also turned about x and y, k's own pose (k not the reference), and from `first_sighted` on
  // the sightings'.
  std::vector<SE3d> RelocalisationGuesses(const Map& map, int index, int k, const SE3d& still,
                                          const std::array<SE3d, 2>& motions, const FeaturePose& feature_pose,
                                          size_t* first_sighted) const;
  // A lost frame as Relocalise searches the map with it: the frame, the frames since the last trusted one, that
  // frame's pose and absolute brightness, the camera's motion since (over half and all the
  // frames) and the tracker's options over the whole pyramid (the frame may be far from every
  // keyframe).
  struct SearchFrame {
    int index = -1;
    const ImagePyramid* pyramid = nullptr;
    const FrameSignature* signature = nullptr;
    double exposure = 1.0;
    int since = 1;
    SE3d last_from_world;
    AffineBrightness last_brightness;
    std::array<SE3d, 2> motions;
    TrackerOptions tracker;
  };
  // One keyframe's alignments with a lost frame: its points, pyramid and mean inverse depth, the
  // results, and the alignment with the guesses it did not refine (in the order of their coarse
  // energy) and the brightness guessed, which a second round may take up.
  struct Aligned {
    std::vector<ReferencePoint> points;
    std::shared_ptr<const ImagePyramid> pyramid;
    double mean_idepth = 0.0;
    std::vector<TrackResult> results;
    std::unique_ptr<FrameTracker> tracker;
    std::vector<SE3d> rest;
    double alpha = 0.0, beta = 0.0;
  };
  // The lost frame aligned with keyframe k (`matches`: of their ORB features, when made).
  Aligned AlignWithKeyframe(const SearchFrame& f, IdleMap& idle, int k, const OrbFeatures& frame_features,
                            const std::vector<cv::DMatch>* matches) const;
  // A lost frame's best alignment with the map that passed the quality test (camera in the world).
  struct Sighting {
    int index = -1;
    SE3d cam_from_world;
  };
  // True when the sightings of the two lost frames before and this one move as one camera does.
  bool MovesAsOneCamera(const Sighting& now, double mean_idepth) const;
  // The state that each frame moves on (CommitPose, LostFrame), kept whole by a tentative
  // relocalisation and put back when it is withdrawn.
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
  // The state before a relocalisation of frame `index`, restored when the next frame does not
  // confirm it.
  struct Tentative {
    int index = -1;
    size_t record = 0;  // The relocalised frame's entry in frames_.
    std::shared_ptr<const TrackingReference> reference;
    TrackingHistory state;
    TrackingStats::Relocalisation evidence;  // Of the relocalisation, counted once confirmed.
  };
  Tentative SaveTentative(int index) const;
  void WithdrawRelocalisation();

  PinholeCamera camera_;
  SystemOptions options_;
  SystemSetup setup_;
  TrackingStats* stats_;
  MappingInbox* mapping_;
  std::unique_ptr<Initializer> initializer_;
  std::vector<InitFrame> pending_;  // The initialiser's frames.
  std::unique_ptr<FrameTracker> tracker_;
  std::shared_ptr<const TrackingReference> reference_;  // The tracker's.
  PoseListener pose_listener_;
  int next_keyframe_ = 0;         // Id of the next keyframe the tracking side makes.
  int last_frame_keyframe_ = -1;  // The keyframe made from the last tracked frame, if any.
  // What the next frame waits for before it is tracked (threaded): the keyframe in flight, when
  // this frame wanted to become a keyframe meanwhile (SystemSetup::wait_for_mapping), and the
  // keyframe made from the frame that confirmed a relocalisation (always).
  PendingWaits waits_;
  std::vector<FramePose> frames_;
  TrackingHistory track_;
  // The frame being processed, the last one seen before it, the recording's frame interval (0:
  // not known yet) and the steps it is the median of (NoteTimestamp).
  int64_t current_t_ns_ = 0, seen_t_ns_ = 0;
  int seen_index_ = -1;
  double frame_interval_ns_ = 0.0;
  std::deque<double> interval_steps_;
  double previous_texture_ = 0.0;  // FrameSignature::texture of the frame before, whatever became of it.
  TrackingState state_ = TrackingState::kInitializing;  // Changed by Transition alone.
  bool suspended_ = false;              // The map is set aside; its frames count once it is back.
  std::optional<Tentative> tentative_;  // Set in TrackingState::kConfirming.
  std::deque<Sighting> sightings_;      // Of the last lost frames (at most two), oldest first.
  double loaded_speed_ = 0.0;  // A loaded map's speed per frame (MovesAsOneCamera before a trusted frame).
};

}  // namespace dsm
