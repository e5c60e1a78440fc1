// SPDX-License-Identifier: MIT
#include "dsm/calibration/corner_symmetry.h"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

namespace dsm {

namespace {

constexpr double kSmoothSigmaPx = 1.0;
constexpr double kStepPx = 0.5;
constexpr int kMaxIterations = 20;

// Bilinear value of a float image at (x, y); false when a neighbour lies outside.
bool Sample(const cv::Mat& m, double x, double y, double* value) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= m.cols || y0 + 1 >= m.rows) return false;
  const double fx = x - x0, fy = y - y0;
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y0 + 1);
  *value = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

}  // namespace

void RefineBySymmetry(const cv::Mat& grey, int radius, std::vector<cv::Point2f>* corners) {
  cv::Mat image, smooth, gx, gy;
  grey.convertTo(image, CV_32F);
  cv::GaussianBlur(image, smooth, cv::Size(0, 0), kSmoothSigmaPx);
  cv::Sobel(smooth, gx, CV_32F, 1, 0, 3, 1.0 / 8);  // Per pixel.
  cv::Sobel(smooth, gy, CV_32F, 0, 1, 3, 1.0 / 8);
  // The offsets v of one half-plane (each pair v, -v once) and their weights.
  std::vector<Eigen::Vector3d> offsets;  // (vx, vy, w)
  const double width = 0.5 * radius;
  for (double vy = 0.0; vy <= radius; vy += kStepPx)
    for (double vx = -radius; vx <= radius; vx += kStepPx) {
      if ((vy == 0.0 && vx <= 0.0) || vx * vx + vy * vy > radius * radius) continue;
      offsets.emplace_back(vx, vy, std::exp(-(vx * vx + vy * vy) / (2 * width * width)));
    }
  for (cv::Point2f& corner : *corners) {
    Eigen::Vector2d c(corner.x, corner.y);
    bool inside = true;
    for (int it = 0; it < kMaxIterations && inside; ++it) {
      Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
      Eigen::Vector2d g = Eigen::Vector2d::Zero();
      for (const Eigen::Vector3d& o : offsets) {
        const Eigen::Vector2d a = c + o.head<2>(), b = c - o.head<2>();
        double sa, sb, gxa, gxb, gya, gyb;
        inside = Sample(smooth, a.x(), a.y(), &sa) && Sample(smooth, b.x(), b.y(), &sb) &&
                 Sample(gx, a.x(), a.y(), &gxa) && Sample(gx, b.x(), b.y(), &gxb) &&
                 Sample(gy, a.x(), a.y(), &gya) && Sample(gy, b.x(), b.y(), &gyb);
        if (!inside) break;
        const Eigen::Vector2d J(gxa - gxb, gya - gyb);
        H += o.z() * J * J.transpose();
        g += o.z() * J * (sa - sb);
      }
      if (!inside) break;
      const Eigen::Vector2d step = -H.ldlt().solve(g);
      if (!step.allFinite()) {
        inside = false;
        break;
      }
      c += step;
      if (step.norm() < 1e-4) break;
    }
    if (inside && (c - Eigen::Vector2d(corner.x, corner.y)).norm() < 0.5 * radius)
      corner = cv::Point2f(static_cast<float>(c.x()), static_cast<float>(c.y()));
  }
}

}  // namespace dsm
