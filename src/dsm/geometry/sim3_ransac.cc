// SPDX-License-Identifier: MIT
#include "dsm/geometry/sim3_ransac.h"

#include <random>

#include "dsm/geometry/umeyama.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

std::vector<int> Inliers(const Sim3d& b_from_a, const std::vector<Eigen::Vector3d>& in_a,
                         const std::vector<Eigen::Vector3d>& in_b, const PinholeCamera& camera, double max_px) {
  const Sim3d a_from_b = b_from_a.Inverse();
  const double max2 = max_px * max_px;
  std::vector<int> inliers;
  for (size_t i = 0; i < in_a.size(); ++i) {
    const Eigen::Vector3d b = b_from_a * in_a[i], a = a_from_b * in_b[i];
    if (b.z() <= 0.0 || a.z() <= 0.0) continue;
    if ((camera.Project(b) - camera.Project(in_b[i])).squaredNorm() < max2 &&
        (camera.Project(a) - camera.Project(in_a[i])).squaredNorm() < max2)
      inliers.push_back(static_cast<int>(i));
  }
  return inliers;
}

}  // namespace

Sim3RansacResult EstimateSim3Ransac(const std::vector<Eigen::Vector3d>& in_a, const std::vector<Eigen::Vector3d>& in_b,
                                    const PinholeCamera& camera, const Sim3RansacOptions& options) {
  DSM_CHECK(in_a.size() == in_b.size(), "3D-3D matches come in pairs");
  Sim3RansacResult best;
  const int n = static_cast<int>(in_a.size());
  if (n < std::max(3, options.min_inliers)) return best;
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int it = 0; it < options.iterations; ++it) {
    const int i = pick(rng);
    int j = pick(rng), k = pick(rng);
    if (i == j || i == k || j == k) continue;
    Sim3d s;
    try {
      s = UmeyamaAlignment({in_a[i], in_a[j], in_a[k]}, {in_b[i], in_b[j], in_b[k]}, true);
    } catch (const InputError&) {
      continue;  // Collinear.
    }
    std::vector<int> inliers = Inliers(s, in_a, in_b, camera, options.max_px);
    if (inliers.size() > best.inliers.size()) best.b_from_a = s, best.inliers = std::move(inliers);
  }
  if (static_cast<int>(best.inliers.size()) < options.min_inliers) return best;
  // Refined on the inliers, twice (the inliers of the refined similarity may grow).
  for (int round = 0; round < 2; ++round) {
    std::vector<Eigen::Vector3d> a, b;
    for (int i : best.inliers) a.push_back(in_a[i]), b.push_back(in_b[i]);
    Sim3d refined;
    try {
      refined = UmeyamaAlignment(a, b, true);
    } catch (const InputError&) {
      break;
    }
    std::vector<int> inliers = Inliers(refined, in_a, in_b, camera, options.max_px);
    if (inliers.size() < best.inliers.size()) break;
    best.b_from_a = refined, best.inliers = std::move(inliers);
  }
  best.ok = static_cast<int>(best.inliers.size()) >= options.min_inliers;
  return best;
}

}  // namespace dsm
