// SPDX-License-Identifier: MIT
#include "dsm/eval/ground_truth_check.h"

#include <algorithm>
#include <map>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "dsm/io/mat_gray.h"
#include "dsm/util/check.h"

namespace dsm {

void GtCheckOptions::Validate() const {
  if (gap < 1) throw InputError("gap must be >= 1, got " + std::to_string(gap));
  if (stride < 1) throw InputError("stride must be >= 1, got " + std::to_string(stride));
  if (max_pairs < 1) throw InputError("pairs must be >= 1, got " + std::to_string(max_pairs));
  if (corners < 8) throw InputError("corners must be >= 8, got " + std::to_string(corners));
  if (!(min_baseline_m >= 0.0)) throw InputError("min baseline must be >= 0");
}

namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace

std::vector<PairTracks> TrackPairs(const Dataset& dataset, const GtCheckOptions& options) {
  options.Validate();
  std::vector<PairTracks> out;
  const size_t gap = options.gap;
  if (dataset.size() <= gap) return out;
  const size_t candidates = (dataset.size() - gap - 1) / options.stride + 1;
  // Every k-th candidate so that at most max_pairs are spread over the whole sequence.
  const size_t every = std::max<size_t>(1, (candidates + options.max_pairs - 1) / options.max_pairs);
  for (size_t c = 0; c < candidates; c += every) {
    const size_t i = c * options.stride, j = i + gap;
    const Image<uint8_t> image_a = dataset.LoadImage(i), image_b = dataset.LoadImage(j);
    const cv::Mat a = Gray8View(image_a), b = Gray8View(image_b);
    std::vector<cv::Point2f> pa, pb, back;
    cv::goodFeaturesToTrack(a, pa, options.corners, 0.01, 10);
    if (pa.empty()) continue;
    std::vector<uint8_t> ok_ab, ok_ba;
    std::vector<float> err;
    const cv::Size window(21, 21);
    cv::calcOpticalFlowPyrLK(a, b, pa, pb, ok_ab, err, window, 4);
    cv::calcOpticalFlowPyrLK(b, a, pb, back, ok_ba, err, window, 4);
    PairTracks pair{i, j, {}, {}};
    for (size_t k = 0; k < pa.size(); ++k) {
      if (!ok_ab[k] || !ok_ba[k] || cv::norm(pa[k] - back[k]) > 0.5) continue;  // Forward-backward check.
      Eigen::Vector2d na, nb;
      if (!dataset.camera.Unproject({pa[k].x, pa[k].y}, &na) || !dataset.camera.Unproject({pb[k].x, pb[k].y}, &nb)) {
        continue;
      }
      pair.a.push_back(na);
      pair.b.push_back(nb);
    }
    if (pair.a.size() >= 8) out.push_back(std::move(pair));
  }
  return out;
}

EpipolarStats EpipolarError(const std::vector<PairTracks>& tracks, const Dataset& dataset,
                            const Trajectory& ground_truth, const GtCheckOptions& options, double focal_px) {
  std::map<int64_t, size_t> by_stamp;
  for (size_t k = 0; k < ground_truth.size(); ++k) by_stamp[ground_truth.stamps_ns[k]] = k;
  // The ground-truth pose whose stamp is within 1 ms of frame i, or -1.
  const auto pose_of = [&](size_t i) -> long {
    const int64_t t = dataset.frames[i].t_ns;
    auto it = by_stamp.lower_bound(t - 1000000);
    return it != by_stamp.end() && it->first <= t + 1000000 ? static_cast<long>(it->second) : -1;
  };
  EpipolarStats stats;
  std::vector<double> distances;
  for (const PairTracks& p : tracks) {
    const long ka = pose_of(p.frame_a), kb = pose_of(p.frame_b);
    if (ka < 0 || kb < 0) continue;
    const SE3d b_from_a = ground_truth.poses[kb].Inverse() * ground_truth.poses[ka];
    if (b_from_a.Translation().norm() < options.min_baseline_m) continue;
    const Eigen::Matrix3d E = Skew(b_from_a.Translation()) * b_from_a.Rotation();
    for (size_t k = 0; k < p.a.size(); ++k) {
      const Eigen::Vector3d xa = p.a[k].homogeneous(), xb = p.b[k].homogeneous();
      const Eigen::Vector3d ea = E * xa, eb = E.transpose() * xb;
      const double r = xb.dot(ea), denominator = ea.head<2>().squaredNorm() + eb.head<2>().squaredNorm();
      if (denominator <= 0.0) continue;
      distances.push_back(focal_px * std::sqrt(r * r / denominator));
    }
    ++stats.pairs;
  }
  stats.tracks = distances.size();
  if (distances.empty()) return stats;
  std::sort(distances.begin(), distances.end());
  stats.median_px = distances[distances.size() / 2];
  stats.p90_px = distances[distances.size() * 9 / 10];
  return stats;
}

}  // namespace dsm
