// SPDX-License-Identifier: MIT
#include "dsm/tracking/two_view.h"

#include <algorithm>
#include <cmath>

#include "dsm/lie/so3.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

constexpr double kMinIdepth = 1e-4;
constexpr double kBehindCost = 1e6;  // A point behind the second camera costs this much.

struct State {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  std::vector<double> d;
};

// Pixel residual of track i: (fx (p_x / p_z - m_x), fy (p_y / p_z - m_y)) with p = R x + d t.
bool Residual(const TwoViewProblem& pr, const State& s, size_t i, Eigen::Vector3d* p, Eigen::Vector2d* e) {
  *p = s.R * pr.reference[i].homogeneous() + s.d[i] * s.t;
  if (p->z() <= 1e-9) return false;
  *e = Eigen::Vector2d(pr.fx * (p->x() / p->z() - pr.current[i].x()), pr.fy * (p->y() / p->z() - pr.current[i].y()));
  return true;
}

double Cost(const TwoViewProblem& pr, const State& s) {
  const double c2 = pr.loss_scale_px * pr.loss_scale_px;
  double cost = 0.0;
  Eigen::Vector3d p;
  Eigen::Vector2d e;
  for (size_t i = 0; i < pr.reference.size(); ++i)
    cost += Residual(pr, s, i, &p, &e) ? 0.5 * c2 * std::log1p(e.squaredNorm() / c2) : kBehindCost;
  return cost;
}

}  // namespace

TwoViewResult RefineTwoView(const TwoViewProblem& pr, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  DSM_CHECK(pr.reference.size() == pr.current.size(), "two-view refinement needs matched tracks");
  DSM_CHECK(translation.norm() > 0, "two-view refinement needs a translation");
  const size_t n = pr.reference.size();
  State s{rotation, translation.normalized(), std::vector<double>(n)};
  // Start depths: least squares along each ray. With a = R x, the projection of a + d t equals m when
  //   (a_x - m_x a_z) + d (t_x - m_x t_z) = 0  and  (a_y - m_y a_z) + d (t_y - m_y t_z) = 0.
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d a = s.R * pr.reference[i].homogeneous();
    const Eigen::Vector2d& m = pr.current[i];
    const Eigen::Vector2d A(s.t.x() - m.x() * s.t.z(), s.t.y() - m.y() * s.t.z());
    const Eigen::Vector2d B(a.x() - m.x() * a.z(), a.y() - m.y() * a.z());
    s.d[i] = std::max(kMinIdepth, -A.dot(B) / std::max(1e-12, A.squaredNorm()));
  }

  TwoViewResult out;
  out.initial_cost = Cost(pr, s);
  double cost = out.initial_cost;
  double lambda = 1e-3;
  const double c2 = pr.loss_scale_px * pr.loss_scale_px;
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  using Mat5 = Eigen::Matrix<double, 5, 5>;
  std::vector<Vec5> h_cd(n);       // d^2 E / d(motion) d(d_i)
  std::vector<double> h_dd(n), b_d(n);
  for (int it = 0; it < 30; ++it) {
    out.iterations = it + 1;
    // Tangent basis of the unit sphere at t.
    const Eigen::Vector3d b1 = s.t.unitOrthogonal();
    const Eigen::Vector3d b2 = s.t.cross(b1);
    Mat5 H_cc = Mat5::Zero();
    Vec5 b_c = Vec5::Zero();
    for (size_t i = 0; i < n; ++i) {
      Eigen::Vector3d p;
      Eigen::Vector2d e;
      h_cd[i].setZero();
      h_dd[i] = 0.0;
      b_d[i] = 0.0;
      if (!Residual(pr, s, i, &p, &e)) continue;
      const double w = 1.0 / (1.0 + e.squaredNorm() / c2);
      const double iz = 1.0 / p.z();
      Eigen::Matrix<double, 2, 3> J_p;  // d e / d p
      J_p << pr.fx * iz, 0.0, -pr.fx * p.x() * iz * iz, 0.0, pr.fy * iz, -pr.fy * p.y() * iz * iz;
      // p = Exp(w) R x + d t:  dp/dw = -[R x]_x;  dp/d(step k) = d b_k;  dp/dd = t.
      const Eigen::Vector3d rx = s.R * pr.reference[i].homogeneous();
      Eigen::Matrix<double, 2, 5> J_c;
      J_c.leftCols<3>() = -J_p * SO3d::Hat(rx);
      J_c.col(3) = J_p * b1 * s.d[i];
      J_c.col(4) = J_p * b2 * s.d[i];
      const Eigen::Vector2d J_d = J_p * s.t;
      H_cc.noalias() += w * J_c.transpose() * J_c;
      b_c.noalias() += w * J_c.transpose() * e;
      h_cd[i] = w * J_c.transpose() * J_d;
      h_dd[i] = w * J_d.squaredNorm();
      b_d[i] = w * J_d.dot(e);
    }
    // Damped normal equations; the depths are eliminated:
    //   (H_cc - sum_i h_cd h_cd^T / h_dd) dc = -(b_c - sum_i h_cd b_d / h_dd),
    //   dd_i = -(b_d + h_cd . dc) / h_dd.
    Mat5 S = H_cc;
    Vec5 g = b_c;
    S.diagonal() *= 1.0 + lambda;
    std::vector<double> damped(n);
    for (size_t i = 0; i < n; ++i) {
      damped[i] = h_dd[i] * (1.0 + lambda) + 1e-12;
      S.noalias() -= h_cd[i] * h_cd[i].transpose() / damped[i];
      g.noalias() -= h_cd[i] * (b_d[i] / damped[i]);
    }
    const Vec5 dc = -S.ldlt().solve(g);
    State next = s;
    next.R = SO3d::Exp(dc.head<3>()).Matrix() * s.R;
    next.t = (s.t + dc(3) * b1 + dc(4) * b2).normalized();
    for (size_t i = 0; i < n; ++i) next.d[i] = std::max(kMinIdepth, s.d[i] - (b_d[i] + h_cd[i].dot(dc)) / damped[i]);
    const double next_cost = Cost(pr, next);
    if (next_cost < cost) {
      const bool converged = cost - next_cost < 1e-8 * cost;
      s = std::move(next);
      cost = next_cost;
      lambda = std::max(1e-7, lambda * 0.3);
      if (converged) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e6) break;
    }
  }
  out.rotation = s.R;
  out.translation = s.t;
  out.idepth = std::move(s.d);
  out.final_cost = cost;
  return out;
}

}  // namespace dsm
