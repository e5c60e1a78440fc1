// SPDX-License-Identifier: MIT
#include "dsm/mapping/candidate.h"

#include <cmath>
#include <limits>

namespace dsm {

bool MakeCandidate(const ImagePyramid& host, const Eigen::Vector2f& pixel, Candidate* c) {
  c->pixel = pixel;
  for (int k = 0; k < kPatternSize; ++k) {
    const float x = pixel.x() + kPattern[k][0], y = pixel.y() + kPattern[k][1];
    if (!host.InBounds(0, x, y, 2.f)) return false;
    const PixelGrad g = host.Sample(0, x, y);
    c->value[k] = g[0];
    c->gradient[k] = Eigen::Vector2f(g[1], g[2]);
  }
  return true;
}

namespace {

// Pattern error at frame position u (level 0); +inf when outside.
float PatternError(const Candidate& c, const ImagePyramid& frame, const Eigen::Vector2f& u, const Transfer& tr) {
  float e = 0.f;
  for (int k = 0; k < kPatternSize; ++k) {
    const float x = u.x() + kPattern[k][0], y = u.y() + kPattern[k][1];
    if (!frame.InBounds(0, x, y, 2.f)) return std::numeric_limits<float>::infinity();
    const float r = (c.value[k] - tr.b_host) - tr.s * (frame.SampleValue(0, x, y) - tr.b_frame);
    // Huber-like: quadratic up to 9, linear beyond (robust to a few occluded pattern pixels).
    const float a = std::abs(r);
    e += a < 9.f ? r * r : 18.f * a - 81.f;
  }
  return e;
}

// Inverse depth at which the point projects to pixel U on the line: solve along the better axis.
float IdepthAt(const Eigen::Vector3f& pr, const Eigen::Vector3f& kt, const Eigen::Vector2f& U, const Eigen::Vector2f& dir) {
  if (std::abs(dir.x()) > std::abs(dir.y())) return (pr.z() * U.x() - pr.x()) / (kt.x() - kt.z() * U.x());
  return (pr.z() * U.y() - pr.y()) / (kt.y() - kt.z() * U.y());
}

}  // namespace

TraceStatus TraceCandidate(Candidate* c, const ImagePyramid& frame, const PinholeCamera& cam, const SE3d& T,
                           const Transfer& tr, const EpipolarOptions& options) {
  const Eigen::Matrix3f K = cam.K().cast<float>();
  const Eigen::Matrix3f Kinv = K.inverse();
  const Eigen::Vector3f pr = K * T.Rotation().cast<float>() * Kinv * Eigen::Vector3f(c->pixel.x(), c->pixel.y(), 1.f);
  const Eigen::Vector3f kt = K * T.Translation().cast<float>();
  const auto project = [&](float rho) -> Eigen::Vector2f {
    const Eigen::Vector3f p = pr + rho * kt;
    return Eigen::Vector2f(p.x() / p.z(), p.y() / p.z());
  };
  const float rho_min = std::max(c->idepth_min, 0.f);
  if (!((pr + rho_min * kt).z() > 0.f)) return c->status = TraceStatus::kOutOfBounds;
  const Eigen::Vector2f u_min = project(rho_min);
  if (!frame.InBounds(0, u_min.x(), u_min.y(), 4.f) && c->idepth_max < 0) return c->status = TraceStatus::kOutOfBounds;
  const float max_len = static_cast<float>(options.max_search_fraction * std::hypot(cam.width, cam.height));
  Eigen::Vector2f u_max;
  if (c->idepth_max >= 0.f && (pr + c->idepth_max * kt).z() > 0.f) {
    u_max = project(c->idepth_max);
  } else {
    // Direction of growing inverse depth; length max_len.
    const Eigen::Vector2f towards = project(rho_min + 0.01f) - u_min;
    if (towards.norm() < 1e-9f) return c->status = TraceStatus::kSkipped;
    u_max = u_min + towards.normalized() * max_len;
  }
  Eigen::Vector2f line = u_max - u_min;
  float length = line.norm();
  if (length < options.min_search_px) return c->status = TraceStatus::kSkipped;
  const Eigen::Vector2f dir = line / length;
  if (length > max_len) length = max_len;
  // Pixel uncertainty from the gradient direction relative to the line.
  float a = 0.f, b = 0.f;
  for (const Eigen::Vector2f& g : c->gradient) {
    const float along = g.dot(dir), across = g.x() * dir.y() - g.y() * dir.x();
    a += along * along;
    b += across * across;
  }
  const float err_px = 0.2f + 0.2f * (a + b) / std::max(a, 1e-6f);
  if (err_px > options.max_pixel_error) return c->status = TraceStatus::kBadCondition;

  // Discrete search, 1-px steps.
  const int steps = static_cast<int>(std::ceil(length));
  float best = std::numeric_limits<float>::infinity(), second = std::numeric_limits<float>::infinity();
  int best_step = -1;
  std::vector<float> energies(steps + 1);
  for (int i = 0; i <= steps; ++i) {
    energies[i] = PatternError(*c, frame, u_min + dir * static_cast<float>(i), tr);
    if (energies[i] < best) best = energies[i], best_step = i;
  }
  if (best_step < 0 || !std::isfinite(best)) return c->status = TraceStatus::kOutOfBounds;
  for (int i = 0; i <= steps; ++i)
    if (std::abs(i - best_step) > 2) second = std::min(second, energies[i]);
  // Gauss–Newton along the line on the squared residuals.
  float offset = static_cast<float>(best_step);
  for (int it = 0; it < options.gauss_newton_iterations; ++it) {
    const Eigen::Vector2f u = u_min + dir * offset;
    float H = 0.f, g = 0.f;
    bool ok = true;
    for (int k = 0; k < kPatternSize && ok; ++k) {
      const float x = u.x() + kPattern[k][0], y = u.y() + kPattern[k][1];
      if (!frame.InBounds(0, x, y, 2.f)) {
        ok = false;
        break;
      }
      // The gradient of the interpolated image by central differences (the frame's pyramid has
      // no gradient planes; inside the border it equals the interpolated central differences).
      const float value = frame.SampleValue(0, x, y);
      const float gx = 0.5f * (frame.SampleValue(0, x + 1.f, y) - frame.SampleValue(0, x - 1.f, y));
      const float gy = 0.5f * (frame.SampleValue(0, x, y + 1.f) - frame.SampleValue(0, x, y - 1.f));
      const float r = (c->value[k] - tr.b_host) - tr.s * (value - tr.b_frame);
      const float J = -tr.s * (gx * dir.x() + gy * dir.y());
      const float w = std::abs(r) < 9.f ? 1.f : 9.f / std::abs(r);
      H += w * J * J;
      g += w * J * r;
    }
    if (!ok || H < 1e-6f) break;
    const float step = std::clamp(-g / H, -0.5f, 0.5f);
    offset = std::clamp(offset + step, 0.f, length);
    if (std::abs(step) < 1e-3f) break;
  }
  const float refined = PatternError(*c, frame, u_min + dir * offset, tr);
  if (refined < best) best = refined;
  if (best > options.max_energy) {
    ++c->outlier_count;
    return c->status = TraceStatus::kOutlier;
  }
  c->quality = std::isfinite(second) ? second / std::max(best, 1e-3f) : 1e3f;
  const Eigen::Vector2f lo = u_min + dir * (offset - err_px), hi = u_min + dir * (offset + err_px);
  float r0 = IdepthAt(pr, kt, lo, dir), r1 = IdepthAt(pr, kt, hi, dir);
  if (r0 > r1) std::swap(r0, r1);
  if (!std::isfinite(r0) || !std::isfinite(r1) || r1 <= 0.f) return c->status = TraceStatus::kOutlier;
  c->idepth_min = std::max(r0, 0.f);
  c->idepth_max = r1;
  c->pixel_interval = 2.f * err_px;
  c->outlier_count = 0;
  return c->status = TraceStatus::kGood;
}

}  // namespace dsm
