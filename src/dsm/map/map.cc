// SPDX-License-Identifier: MIT
#include "dsm/map/map.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/util/check.h"

namespace dsm {

Keyframe& Map::AddKeyframe(std::unique_ptr<Keyframe> keyframe) {
  keyframe->id = NumKeyframes();
  keyframe->pyramid_used = epoch_;
  if (keyframe->pyramid != nullptr) {  // Without one: geometry only (tests of window selection).
    DSM_CHECK(keyframe->pyramid->HasGradients(), "a keyframe needs a full pyramid");
    keyframe->pyramid_levels = keyframe->pyramid->levels();
  }
  keyframes_.push_back(std::move(keyframe));
  return *keyframes_.back();
}

int Map::AddPoint(Point point) {
  DSM_CHECK(point.host >= 0 && point.host < NumKeyframes(), "point host out of range");
  point.id = NumPoints();
  const Keyframe& host = *keyframes_[point.host];
  point.patch_ok = host.pyramid != nullptr && SampleHostPatch(*host.pyramid, 0, point.pixel, interpolation_, &point.patch);
  keyframes_[point.host]->points.push_back(point.id);
  points_.push_back(std::move(point));
  return points_.back().id;
}

Keyframe& Map::RestoreKeyframe(std::unique_ptr<Keyframe> keyframe) {
  DSM_CHECK(keyframe->id == NumKeyframes() && keyframe->pyramid == nullptr && keyframe->points.empty(),
            "a restored keyframe comes in id order, with its image and without points");
  keyframe->pyramid_used = epoch_;
  keyframes_.push_back(std::move(keyframe));
  return *keyframes_.back();
}

void Map::RestorePoint(Point point) {
  DSM_CHECK(point.id == NumPoints() && point.host >= 0 && point.host < NumKeyframes(),
            "a restored point comes in id order, with a host in the map");
  keyframes_[point.host]->points.push_back(point.id);
  points_.push_back(std::move(point));
}

void Map::set_interpolation(Interpolation interpolation) {
  DSM_CHECK(points_.empty(), "the interpolation is set before the first point");
  interpolation_ = interpolation;
}

int Map::LoadPyramids(const std::vector<int>& ids) {
  std::vector<Keyframe*> missing;
  for (int id : ids) {
    Keyframe& kf = *keyframes_[id];
    DSM_CHECK(!kf.retired, "a retired keyframe's pyramid is never used");
    if (kf.pyramid == nullptr && std::find(missing.begin(), missing.end(), &kf) == missing.end()) missing.push_back(&kf);
    kf.pyramid_used = epoch_;
  }
  tbb::parallel_for(size_t{0}, missing.size(), [&](size_t i) {
    Keyframe& kf = *missing[i];
    kf.pyramid = std::make_shared<const ImagePyramid>(ImagePyramid::FromFixed(kf.image, kf.pyramid_levels));
    kf.image = Image<uint16_t>();
  });
  pyramids_rebuilt_ += static_cast<int>(missing.size());
  return static_cast<int>(missing.size());
}

int Map::ReleaseUnusedPyramids(int keep_epochs) {
  int released = 0;
  for (auto& kf : keyframes_) {
    if (kf->pyramid != nullptr && kf->pyramid_used <= epoch_ - keep_epochs) {
      kf->image = kf->pyramid->FixedLevel0();
      kf->pyramid.reset();
      ++released;
    }
  }
  ++epoch_;
  return released;
}

void Map::Retire(int id) {
  Keyframe& kf = *keyframes_[id];
  for (int pid : kf.points) points_[pid].removed = true;
  kf.points.clear();
  for (Point& p : points_)
    std::erase_if(p.observations, [id](const Observation& o) { return o.target == id; });
  kf.pyramid.reset();
  kf.image = Image<uint16_t>();
  kf.retired = true;
}

void Map::Rehost(int pid, int host, const Eigen::Vector2f& pixel, float idepth) {
  Point& p = points_[pid];
  Keyframe& to = *keyframes_[host];
  DSM_CHECK(to.pyramid != nullptr, "a point is re-hosted by a keyframe with its pyramid loaded");
  std::erase(keyframes_[p.host]->points, pid);
  std::erase_if(p.observations, [host](const Observation& o) { return o.target == host; });
  p.host = host;
  p.pixel = pixel;
  p.idepth = idepth;
  p.patch_ok = SampleHostPatch(*to.pyramid, 0, pixel, interpolation_, &p.patch);
  to.points.push_back(pid);
}

std::vector<int> Map::DropRetired() {
  std::vector<int> keyframe_id(keyframes_.size(), -1), point_id(points_.size(), -1);
  std::vector<std::unique_ptr<Keyframe>> keyframes;
  for (size_t k = 0; k < keyframes_.size(); ++k) {
    if (keyframes_[k]->retired) continue;
    keyframe_id[k] = static_cast<int>(keyframes.size());
    keyframes.push_back(std::move(keyframes_[k]));
  }
  std::vector<Point> points;
  for (size_t i = 0; i < points_.size(); ++i) {
    if (keyframe_id[points_[i].host] < 0) continue;
    point_id[i] = static_cast<int>(points.size());
    points.push_back(std::move(points_[i]));
  }
  for (Point& p : points) {
    p.id = point_id[p.id];
    p.host = keyframe_id[p.host];
    for (Observation& o : p.observations) o.target = keyframe_id[o.target];  // Retire dropped those in retired ones.
  }
  for (auto& kf : keyframes) {
    kf->id = keyframe_id[kf->id];
    for (int& pid : kf->points) pid = point_id[pid];
  }
  keyframes_ = std::move(keyframes);
  points_ = std::move(points);
  return keyframe_id;
}

void Map::KeepFirst(int keyframes, int points) {
  DSM_CHECK(keyframes <= NumKeyframes() && points <= NumPoints(), "a map keeps what it has");
  keyframes_.resize(keyframes);
  points_.resize(points);
  for (Point& p : points_)
    std::erase_if(p.observations, [keyframes](const Observation& o) { return o.target >= keyframes; });
  for (auto& kf : keyframes_)
    std::erase_if(kf->points, [points](int pid) { return pid >= points; });
}

int Map::NumLoadedPyramids() const {
  int n = 0;
  for (const auto& kf : keyframes_) n += kf->pyramid != nullptr;
  return n;
}

int Map::NumLivePoints() const {
  int n = 0;
  for (const Point& p : points_) n += !p.removed;
  return n;
}

}  // namespace dsm
