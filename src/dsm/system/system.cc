// SPDX-License-Identifier: MIT
// The System facade: the two sides, the mapping thread, and what needs both (the trajectories,
// map files, merges).
#include "dsm/system/system.h"

#include <algorithm>
#include <string>

#include "dsm/image/noise.h"
#include "dsm/system/mapping_thread.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

// The options both sides run with: validated, and DSM-SW's window all temporal.
SystemOptions RunOptions(SystemOptions options, const PinholeCamera& camera) {
  options.Validate();
  if (options.mode == MapMode::kSlidingWindow) {
    // DSM-SW: the same window size N_w = N_t + N_c, all of it temporal (a sliding window as DSO's).
    options.window.temporal_keyframes += options.window.covisible_keyframes;
    options.window.covisible_keyframes = 0;
  }
  const int div = 1 << (options.pyramid_levels - 1);
  if (camera.width % div || camera.height % div) {
    throw InputError("the undistorted image size " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                     " must divide by 2^(pyramid_levels - 1) = " + std::to_string(div));
  }
  return options;
}

SystemSetup Validated(SystemSetup setup) {
  setup.Validate();
  return setup;
}

}  // namespace

System::System(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup)
    : young_map_frames_(options.relocalisation.young_map_frames),
      mapping_(camera, RunOptions(options, camera), Validated(setup), &stats_),
      tracking_(camera, RunOptions(options, camera), setup, &stats_, &mapping_) {
  if (setup.threaded) {
    mapping_thread_ = std::make_unique<MappingThread>();
    mapping_.RunOn(mapping_thread_.get());
  }
}

System::~System() = default;

FrameReport System::Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                            std::optional<std::chrono::steady_clock::time_point> wait_until) {
  const PinholeCamera& camera = tracking_.camera();
  DSM_CHECK(image.width() == camera.width && image.height() == camera.height, "frame size differs from the camera");
  // The noise level is the first frame's, or a loaded map's (RestoreMap); the mapping side is
  // idle before the map starts.
  if (!mapping_.NoiseChosen()) mapping_.ChooseNoiseHandling(EstimateNoiseSigma(image));
  return tracking_.Process(index, t_ns, image, exposure_ms, wait_until);
}

bool System::WaitSettled(std::chrono::steady_clock::time_point until) const {
  return !mapping_thread_ || mapping_thread_->WaitForSettledKeyframesUntil(until);
}

void System::Preview(int index, const Image<float>& image, double exposure_ms) const {
  tracking_.Preview(index, image, exposure_ms);
}

void System::Finish() {
  mapping_.Finish();
  tracking_.MergeInitTracked(mapping_.TakeInitTracked());
}

Trajectory System::KeyframeTrajectory() const { return mapping_.KeyframeTrajectory(); }

Trajectory System::FrameTrajectory() const {
  const Map& map = mapping_.map();
  Trajectory t;
  const double baseline = mapping_.InitBaseline();
  for (const FramePose& f : tracking_.frames()) {
    if (f.reference < 0) continue;
    SE3d frame_from_reference = f.AtBaseline(baseline);
    frame_from_reference.SetTranslation(frame_from_reference.Translation() *
                                        (f.reference_scale / mapping_.KeyframeScale(f.reference)));
    t.Add(f.t_ns, (frame_from_reference * map.keyframe(f.reference).cam_from_world).Inverse());
  }
  return t;
}

int System::NumMapPoints() const { return mapping_.map().NumLivePoints(); }

System::MapSize System::TrackedMapSize() const {
  const TrackingReference* ref = tracking_.reference();
  if (!ref) return {};
  return {static_cast<int>(ref->cam_from_world.size()), ref->map_points};
}

std::shared_ptr<const MapSnapshot> System::TrackedMapSnapshot() const {
  const TrackingReference* ref = tracking_.reference();
  return ref ? ref->snapshot : nullptr;
}

std::optional<SE3d> System::LastFramePose() const { return tracking_.LastFramePose(); }

bool System::NeedsNewMap() const { return tracking_.NeedsNewMap(Young()); }

StoredMap System::TakeStoredMap() {
  Finish();
  return mapping_.TakeStoredMap(tracking_.ResidualLevel(), tracking_.TextureLevel());
}

void System::RestoreMap(StoredMap stored, LoadedMapUse use) {
  const double residual_level = stored.residual_level, texture_level = stored.texture_level;
  mapping_.RestoreMap(&stored, use == LoadedMapUse::kLocalize);
  tracking_.TakeUpLoadedMap(mapping_.loaded_keyframes(), mapping_.loaded_speed(), residual_level, texture_level);
}

bool System::MergeVerified(System& other, int taken_id) {
  if (mapping_.MergeReady() < 0) return false;
  Finish();
  if (tracking_.state() == TrackingState::kConfirming) return false;
  DSM_CHECK(tracking_.next_keyframe() == mapping_.map().NumKeyframes(), "a merge waits until every keyframe is mapped");
  DSM_CHECK(mapping_.MergeReadyWith(other.mapping_), "a merge takes the map its keyframe recognised");
  const double baseline = other.mapping_.InitBaseline();  // Before its map is taken.
  const int offset = mapping_.TakeMerge(other.mapping_, taken_id);
  tracking_.MergeFrames(other.tracking_.TakeFrames(), offset, baseline, mapping_.map().NumKeyframes());
  return true;
}

void System::AdjustWholeMapFrom(const Trajectory& world_from_cam) { mapping_.AdjustWholeMapFrom(world_from_cam); }

}  // namespace dsm
