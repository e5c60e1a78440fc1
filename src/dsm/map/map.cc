// SPDX-License-Identifier: MIT
#include "dsm/map/map.h"

#include "dsm/util/check.h"

namespace dsm {

Keyframe& Map::AddKeyframe(std::unique_ptr<Keyframe> keyframe) {
  keyframe->id = NumKeyframes();
  keyframes_.push_back(std::move(keyframe));
  return *keyframes_.back();
}

int Map::AddPoint(Point point) {
  DSM_CHECK(point.host >= 0 && point.host < NumKeyframes(), "point host out of range");
  point.id = NumPoints();
  keyframes_[point.host]->points.push_back(point.id);
  points_.push_back(std::move(point));
  return points_.back().id;
}

int Map::NumLivePoints() const {
  int n = 0;
  for (const Point& p : points_) n += !p.removed;
  return n;
}

}  // namespace dsm
