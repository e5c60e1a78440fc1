// SPDX-License-Identifier: MIT
// The mapping side's adjustments beyond the window's own: the young map's, the loop's after a
// return, the seam's after a relocalisation (each after a keyframe is published, stopping for a
// keyframe that waits: Adjust), and the whole map's (at the end, or from the true poses).
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "dsm/optimization/pba.h"
#include "dsm/system/mapping_side.h"
#include "dsm/system/mapping_thread.h"
#include "dsm/system/system_internal.h"

namespace dsm {

bool MappingSide::AdjustYoungMap() {
  if (!options_.YoungMapBaDue(map_.NumKeyframes())) return false;
  Adjustment a;
  a.young = true;
  a.options = options_.pba;
  a.log = stats_->per_keyframe.size() - 1;
  a.stat = stats_->young_map_ba_ms.size();
  stats_->per_keyframe.back().young_map_ba_keyframes = map_.NumKeyframes();
  stats_->young_map_ba_ms.push_back(0.0);
  Adjust(std::move(a));
  return true;
}

bool MappingSide::RunParked() {
  std::vector<Adjustment> parked;
  parked.swap(parked_);
  for (Adjustment& a : parked) Adjust(std::move(a));
  return !parked.empty();
}

void MappingSide::Adjust(Adjustment a) {
  PbaYield yield;
  if (thread_ && setup_.yield_adjustments) {
    yield.now = [this] { return thread_->KeyframesPending() > 0 || thread_->Urgent(); };
  }
  yield.level = a.level;
  yield.iterations = a.iterations;
  // Keyframes retired meanwhile (culled, or a localisation's temporary ones) have left the map.
  const auto retired = [this](int k) { return map_.keyframe(k).retired; };
  std::erase_if(a.keyframes, retired);
  std::erase_if(a.held, retired);
  const PbaSummary s =
      RunPba(&map_, camera_, a.young ? AllKeyframes() : a.keyframes, a.options, HeldWithLoaded(a.held), yield);
  MappingStats::KeyframeLog& log = stats_->per_keyframe[a.log];
  if (a.young) {
    log.young_map_ba_ms += s.time_ms;
    log.young_map_ba_iterations += s.iterations;
    log.young_map_ba_observations = s.observations;
    stats_->young_map_ba_ms[a.stat] += s.time_ms;
  } else {
    log.loop_ba_ms += s.time_ms;
    stats_->loop_ba_ms[a.stat] += s.time_ms;
  }
  if (!s.yielded) return;
  ++stats_->adjustments_yielded;
  a.level = s.level;
  a.iterations = s.level_iterations;
  if (thread_->KeyframesPending() == 0) {
    // A relocalisation waits for the mapping side to be idle (nothing is handed to it while lost):
    // the rest runs after the next keyframe (FinishKeyframe), or at the end (Finish).
    parked_.push_back(std::move(a));
    return;
  }
  // Behind the waiting keyframe's jobs (MappingSide::Submit queues both at once), then published again.
  thread_->Submit(
      [this, a = std::move(a)] {
        Adjust(a);
        PublishTrackingReference();
      },
      false);
}

namespace {

// How far the camera went from keyframe `from` over the keyframes after it up to `to`, in scene
// depths: the largest distance of their centres from `from`'s times the mean inverse depth of the
// points hosted by the keyframes `window` (0 when they host none).
double ReachInDepths(const Map& map, int from, int to, const std::vector<int>& window) {
  double idepth = 0.0;
  int n = 0;
  for (int k : window)
    for (int pid : map.keyframe(k).points) {
      const Point& p = map.point(pid);
      if (!p.removed) idepth += p.idepth, ++n;
    }
  if (n == 0) return 0.0;
  const Eigen::Vector3d origin = map.keyframe(from).Centre();
  double reach = 0.0;
  for (int k = from + 1; k <= to; ++k)
    if (!map.keyframe(k).retired) reach = std::max(reach, (map.keyframe(k).Centre() - origin).norm());
  return reach * idepth / n;
}

}  // namespace

bool MappingSide::AdjustLoop(int newest) {
  if (options_.mode != MapMode::kFull || covisible_.empty()) return false;
  const int oldest = *std::min_element(covisible_.begin(), covisible_.end());
  const int after_loss = options_.loop_ba_after_relocalisation;
  // Once tracking was lost and regained, the map holds parts joined by a relocalised pose alone,
  // and only the loops that close later make them agree: the window holds its old keyframes.
  // After a relocalisation with few points in view the part after it can run off in scale, and a
  // single adjustment as the lap closes does not bring it back. So such a map is adjusted
  // periodically, every loop_ba_after_relocalisation keyframes.
  const int gap = options_.loop_ba_min_gap > 0 ? options_.loop_ba_min_gap : relocalisations_mapped_ > 0 ? after_loss : 0;
  // A map without relocalisations is adjusted only where the camera went away and came back.
  const bool periodic = gap > 0 && newest - oldest >= gap && (last_loop_ba_ < 0 || newest - last_loop_ba_ >= gap) &&
                        (relocalisations_mapped_ > 0 || ReachInDepths(map_, oldest, newest, window_) >= options_.loop_ba_min_reach);
  const bool relocalised = loop_ba_pending_ && after_loss > 0 && newest - oldest >= after_loss;
  if (!periodic && !relocalised) return false;
  loop_ba_pending_ = false;
  // Free: the keyframes after the oldest covisible one (at most loop_ba_max_keyframes, the
  // newest), but the covisible ones; held: those and the oldest.
  const int first = std::max(oldest + 1, newest + 1 - options_.loop_ba_max_keyframes);
  std::vector<int> keyframes = covisible_, held = covisible_;
  for (int k = first; k <= newest; ++k)
    if (std::find(covisible_.begin(), covisible_.end(), k) == covisible_.end()) keyframes.push_back(k);
  last_loop_ba_ = newest;
  AdjustAfterNewest(std::move(keyframes), std::move(held), LoopBaOptions(), /*seam=*/false);
  return true;
}

PbaOptions MappingSide::LoopBaOptions() const {
  PbaOptions pba = options_.pba;
  if (options_.loop_ba_max_iterations > 0) pba.max_iterations = options_.loop_ba_max_iterations;
  return pba;
}

void MappingSide::AdjustAfterNewest(std::vector<int> keyframes, std::vector<int> held, const PbaOptions& pba, bool seam) {
  Adjustment a;
  a.options = pba;
  a.log = stats_->per_keyframe.size() - 1;
  a.stat = stats_->loop_ba_ms.size();
  MappingStats::KeyframeLog& log = stats_->per_keyframe.back();
  log.loop_ba_keyframes = static_cast<int>(keyframes.size() - held.size());
  log.loop_ba_seam = seam;  // When both ran: the last one's.
  stats_->loop_ba_ms.push_back(0.0);
  a.keyframes = std::move(keyframes);
  a.held = std::move(held);
  Adjust(std::move(a));
}

bool MappingSide::AdjustSeam(int newest) {
  if (options_.mode != MapMode::kFull || seam_first_ < 0 || newest < seam_first_) return false;
  const int after = newest - seam_first_ + 1;  // Keyframes mapped since the relocalisation.
  if (after > options_.seam_ba_step * options_.seam_ba_count) {
    seam_first_ = -1;
    return false;
  }
  if (after % options_.seam_ba_step != 0) return false;
  // Free: the keyframes from seam_ba_before before the relocalisation on; held: the older ones
  // whose points they observe, so that those points tie them to the old map (the keyframes that
  // observe the free keyframes' points enter fixed, as in every adjustment).
  // A map of fewer than twice that many keyframes at the loss has too little before them to hold:
  // freeing it nearly whole bends it; the young map's adjustments cover it.
  const int first = seam_first_ - options_.seam_ba_before;
  if (first < options_.seam_ba_before) return false;
  std::vector<int> held;
  for (int h = 0; h < first; ++h) {
    const std::vector<int>& hosted = map_.keyframe(h).points;
    const bool ties = std::any_of(hosted.begin(), hosted.end(), [&](int pid) {
      const Point& p = map_.point(pid);
      if (p.removed) return false;
      for (const Observation& o : p.observations)
        if (!o.outlier && o.target >= first) return true;
      return false;
    });
    if (ties) held.push_back(h);
  }
  std::vector<int> keyframes = held;
  for (int k = first; k <= newest; ++k) keyframes.push_back(k);
  AdjustAfterNewest(std::move(keyframes), std::move(held), options_.pba, /*seam=*/true);
  return true;
}

std::vector<int> MappingSide::AllKeyframes() const {
  std::vector<int> all;
  for (int k = 0; k < map_.NumKeyframes(); ++k)
    if (!map_.keyframe(k).retired) all.push_back(k);
  return all;
}

PbaSummary MappingSide::AdjustWholeMap() { return RunPba(&map_, camera_, AllKeyframes(), options_.pba, HeldWithLoaded({})); }

std::vector<int> MappingSide::HeldWithLoaded(std::vector<int> held) const {
  for (int k = 0; k < loaded_keyframes_; ++k) held.push_back(k);
  return held;
}

void MappingSide::RunGlobalBundleAdjustment() {
  if (map_.NumKeyframes() < 2) return;
  stats_->global_ba_ms = AdjustWholeMap().time_ms;
}

void MappingSide::AdjustWholeMapFrom(const Trajectory& world_from_cam) {
  for (size_t i = 0; i < world_from_cam.size(); ++i) {
    for (int k = 0; k < map_.NumKeyframes(); ++k) {
      Keyframe& keyframe = map_.keyframe(k);
      if (std::llabs(keyframe.t_ns - world_from_cam.stamps_ns[i]) > 1000000) continue;  // 1 ms
      keyframe.cam_from_world = world_from_cam.poses[i].Inverse();
    }
  }
  if (map_.NumKeyframes() < 2) return;
  for (int round = 0; round < 4; ++round) {
    const PbaSummary s = AdjustWholeMap();
    if (!(s.final_energy < 0.999 * s.initial_energy)) break;  // Converged: the energy moved < 0.1%.
  }
}

}  // namespace dsm
