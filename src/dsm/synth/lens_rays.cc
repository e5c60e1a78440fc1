// SPDX-License-Identifier: MIT
#include "dsm/synth/lens_rays.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

namespace dsm::synth {

std::vector<double> TypicalDistortion(CameraModel model) {
  switch (model) {
    case CameraModel::kRadTan: return {-0.28, 0.08, 0.0006, -0.0004};
    case CameraModel::kEquidistant: return {0.02, -0.015, 0.004, -0.001};
    case CameraModel::kFov: return {0.9};
    case CameraModel::kPinhole: break;
  }
  return {};
}

LensRays::LensRays(const CameraCalibration& camera) : camera_(camera) {
  const int w = camera.width, h = camera.height;
  corners_.resize(static_cast<size_t>(w + 1) * (h + 1));
  tbb::parallel_for(0, h + 1, [&](int j) {
    for (int i = 0; i <= w; ++i) {
      Eigen::Vector2d n;
      corners_[static_cast<size_t>(j) * (w + 1) + i] =
          camera.Unproject({i - 0.5, j - 0.5}, &n) ? n.cast<float>() : Eigen::Vector2f(NAN, NAN);
    }
  });
  pixels_.resize(static_cast<size_t>(w) * h);
  const auto unit = [](const Eigen::Vector2f& n) { return Eigen::Vector3f(n.x(), n.y(), 1.f).normalized(); };
  tbb::parallel_for(0, h, [&](int v) {
    for (int u = 0; u < w; ++u) {
      Eigen::Vector2d n;
      const Eigen::Vector2f c00 = Corner(u, v), c11 = Corner(u + 1, v + 1), c10 = Corner(u + 1, v),
                            c01 = Corner(u, v + 1);
      if (!camera.Unproject({double(u), double(v)}, &n) || !c00.allFinite() || !c11.allFinite() ||
          !c10.allFinite() || !c01.allFinite())
        continue;
      Pixel& p = pixels_[static_cast<size_t>(v) * w + u];
      p.unit = Eigen::Vector3d(n.x(), n.y(), 1.0).normalized().cast<float>();
      // The pixel's solid angle: half the cross product of its diagonals on the unit sphere.
      const float solid = 0.5f * (unit(c11) - unit(c00)).cross(unit(c01) - unit(c10)).norm();
      p.angle = std::sqrt(solid);
    }
  });
}

bool LensRays::Cone(int u0, int v0, int u1, int v1, std::array<Eigen::Vector3f, 4>* corners) const {
  Eigen::Vector2f lo = Eigen::Vector2f::Constant(INFINITY), hi = Eigen::Vector2f::Constant(-INFINITY);
  bool finite = true;
  const auto take = [&](int i, int j) {
    const Eigen::Vector2f& c = Corner(i, j);
    finite = finite && c.allFinite();
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  };
  for (int i = u0; i <= u1; ++i) take(i, v0), take(i, v1);
  for (int j = v0 + 1; j < v1; ++j) take(u0, j), take(u1, j);
  if (!finite) return false;
  const Eigen::Vector2f margin = 0.01f * (hi - lo);
  lo -= margin;
  hi += margin;
  *corners = {Eigen::Vector3f(lo.x(), lo.y(), 1.f), Eigen::Vector3f(hi.x(), lo.y(), 1.f),
              Eigen::Vector3f(hi.x(), hi.y(), 1.f), Eigen::Vector3f(lo.x(), hi.y(), 1.f)};
  return true;
}

}  // namespace dsm::synth
