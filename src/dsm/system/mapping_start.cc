// SPDX-License-Identifier: MIT
// The map's start on the mapping side: the two keyframes of the two-view initialisation with the
// initialiser's points (MapStart), keyframe 1's first mapping, and the tracking of the frames the
// initialiser buffered between the two once the young map has settled.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "dsm/mapping/projection.h"
#include "dsm/system/mapping_side.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/util/check.h"

namespace dsm {

using internal::MsSince;
using internal::Scale;

void MappingSide::StartMap(MapStart start) {
  const auto t0 = std::chrono::steady_clock::now();
  const InitFrame& first = start.first;
  const InitFrame& last = start.last;
  CreateKeyframe(first.index, first.t_ns, first.pyramid, first.exposure, SE3d(), AffineBrightness{});
  CreateKeyframe(last.index, last.t_ns, last.pyramid, last.exposure, start.kf1_from_kf0, AffineBrightness{});
  // Points triangulated by the initialiser, hosted by keyframe 0.
  stats_->per_keyframe.push_back({first.index, 0, 0, {}});
  for (const InitPoint& ip : start.points) {
    Point p;
    p.host = 0;
    p.pixel = ip.pixel;
    p.idepth = ip.idepth;
    p.created_at_keyframe = 2;
    HostPatch patch;
    if (!SampleHostPatch(map_.keyframe(0).Pyramid(), 0, p.pixel, map_.interpolation(), &patch)) continue;
    map_.AddPoint(p);
    ++stats_->points_created;
    ++stats_->per_keyframe.back().points_created;
  }
  window_ = {0};
  // Until keyframe 1 is mapped, frames are tracked against it with the initialiser's depths.
  PublishReference(1, ReferencePointsIn(1, map_.keyframe(0).points, /*adjusted=*/false));
  init_between_ = {std::move(start.between), start.kf1_from_kf0, start.steps};
  // Brightness guess: only the exposure changed (alpha = log(tau_1 / tau_0), so a_1 = 0).
  const double alpha = std::log(last.exposure / first.exposure), exposure = last.exposure;
  const double start_ms = MsSince(t0);
  Run([this, pose = start.kf1_from_kf0, alpha, exposure, start_ms] { MapFirstKeyframe(pose, alpha, exposure, start_ms); },
      /*keyframe=*/true);
}

void MappingSide::MapFirstKeyframe(SE3d pose, double alpha, double exposure, double start_ms) {
  const auto t0 = std::chrono::steady_clock::now();
  SelectCandidates(0);
  TraceCandidates(map_.keyframe(1).Pyramid(), 0, pose, alpha, 0.0, exposure);
  MapNewKeyframe(1);
  FinishKeyframe(1);
  stats_->mapping_ms.push_back(start_ms + MsSince(t0));
}

void MappingSide::TrackInitFrames() {
  // Hand-held starts turn back and forth between the two keyframes (on `pan`, 60 deg away from
  // keyframe 1 and back), so an interpolation of their relative motion is no guess for the frames
  // between, and one keyframe may barely overlap the frames near the other (tracking a narrow
  // overlap confuses a tilt with a sideways shift). Each frame is therefore tracked twice, in a
  // chain forwards from keyframe 0 and backwards from keyframe 1, each from its neighbour's pose
  // and the step between them (constant velocity), and keeps the result of the keyframe it is
  // turned less from. A chain stops at its first failure. The references are the map's points as
  // the bundle adjustments of the next keyframes left them: the two-view start is only a guess.
  const std::vector<InitFrame> between = std::move(init_between_.frames);
  init_between_.frames.clear();
  if (between.empty()) return;
  const int n = static_cast<int>(between.size());
  const auto angle = [](const std::optional<TrackResult>& r) { return r->frame_from_keyframe.So3().Log().norm(); };
  // `stop(i, r)`: the chain ends before frame i.
  std::vector<int> live;  // The young map's points, whichever keyframes the window holds by now.
  for (int pid = 0; pid < map_.NumPoints(); ++pid)
    if (!map_.point(pid).removed) live.push_back(pid);
  const auto chain = [&](int keyframe, SE3d step, bool forward, const auto& stop) {
    map_.LoadPyramids({keyframe});
    FrameTracker tracker(options_.tracker);
    tracker.SetReference(map_.keyframe(keyframe).pyramid.get(), camera_, ReferencePointsIn(keyframe, live));
    std::vector<std::optional<TrackResult>> out(n);
    SE3d previous;  // The neighbour's frame_from_keyframe.
    for (int j = 0; j < n; ++j) {
      const int i = forward ? j : n - 1 - j;
      std::optional<TrackResult> r = tracker.Track(*between[i].pyramid, step * previous, 0.0, 0.0, j + 1);
      if (!r->ok || stop(i, r)) break;
      step = r->frame_from_keyframe * previous.Inverse();
      previous = r->frame_from_keyframe;
      out[i] = std::move(r);
    }
    return out;
  };
  // Frame j + 1 from frame j, as the two-view start saw it: the chains' first guess.
  const SE3d per_frame = Scale(init_between_.kf1_from_kf0, 1.0 / init_between_.steps);
  const auto from_kf1 = chain(1, per_frame.Inverse(), false, [](int, const auto&) { return false; });
  // Forwards only while keyframe 0 is the nearer one (the tracking thread may be waiting).
  const auto from_kf0 =
      chain(0, per_frame, true, [&](int i, const auto& r) { return from_kf1[i] && angle(from_kf1[i]) <= angle(r); });
  const double baseline = InitBaseline();
  for (int i = 0; i < n; ++i) {
    const bool use_kf0 = from_kf0[i] && (!from_kf1[i] || angle(from_kf0[i]) < angle(from_kf1[i]));
    const std::optional<TrackResult>& r = use_kf0 ? from_kf0[i] : from_kf1[i];
    if (r) init_tracked_.push_back({between[i].t_ns, use_kf0 ? 0 : 1, r->frame_from_keyframe, baseline});
  }
}

}  // namespace dsm
