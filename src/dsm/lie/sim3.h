// SPDX-License-Identifier: MIT
// Sim(3): similarity transforms p -> s R p + t, s = e^sigma > 0.
// Tangent xi = (upsilon, omega, sigma).
//
//   Exp(xi) = ( e^sigma, Exp(omega), W(omega, sigma) upsilon ),
//   W = integral_0^1 e^(sigma tau) Exp(tau omega) d tau
//     = A I + B hat(omega) + C hat(omega)^2  with, for theta = |omega|,
//   A = (e^sigma - 1) / sigma,
//   B = b / theta,  C = (A - c) / theta^2,  where c + i b = (e^(sigma + i theta) - 1) / (sigma + i theta).
//
//   Adj = [ s R   hat(t) R   -t ]
//         [ 0     R           0 ]
//         [ 0     0           1 ]
#pragma once

#include <cmath>

#include "dsm/lie/se3.h"

namespace dsm {

template <typename Scalar>
class Sim3 {
 public:
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Mat3 = Eigen::Matrix<Scalar, 3, 3>;
  using Mat4 = Eigen::Matrix<Scalar, 4, 4>;
  using Tangent = Eigen::Matrix<Scalar, 7, 1>;
  using AdjMatrix = Eigen::Matrix<Scalar, 7, 7>;
  static constexpr int kDof = 7;

  Sim3() : scale_(1), t_(Vec3::Zero()) {}
  Sim3(Scalar scale, const SO3<Scalar>& r, const Vec3& t) : scale_(scale), r_(r), t_(t) {}
  explicit Sim3(const SE3<Scalar>& T) : scale_(1), r_(T.So3()), t_(T.Translation()) {}

  static Sim3 Exp(const Tangent& xi) {
    using std::exp;
    const Vec3 upsilon = xi.template head<3>();
    const Vec3 omega = xi.template segment<3>(3);
    const Scalar sigma = xi(6);
    return Sim3(exp(sigma), SO3<Scalar>::Exp(omega), W(omega, sigma) * upsilon);
  }

  Tangent Log() const {
    using std::log;
    const Vec3 omega = r_.Log();
    const Scalar sigma = log(scale_);
    Tangent xi;
    xi << W(omega, sigma).lu().solve(t_), omega, sigma;
    return xi;
  }

  Sim3 Inverse() const {
    const SO3<Scalar> r_inv = r_.Inverse();
    const Scalar s_inv = Scalar(1) / scale_;
    return Sim3(s_inv, r_inv, -(s_inv * (r_inv * t_)));
  }
  Sim3 operator*(const Sim3& o) const {
    return Sim3(scale_ * o.scale_, r_ * o.r_, scale_ * (r_ * o.t_) + t_);
  }
  Vec3 operator*(const Vec3& p) const { return scale_ * (r_ * p) + t_; }

  AdjMatrix Adj() const {
    AdjMatrix a = AdjMatrix::Zero();
    const Mat3 R = r_.Matrix();
    a.template block<3, 3>(0, 0) = scale_ * R;
    a.template block<3, 3>(0, 3) = SO3<Scalar>::Hat(t_) * R;
    a.template block<3, 1>(0, 6) = -t_;
    a.template block<3, 3>(3, 3) = R;
    a(6, 6) = Scalar(1);
    return a;
  }

  Mat4 Matrix() const {
    Mat4 m = Mat4::Identity();
    m.template topLeftCorner<3, 3>() = scale_ * r_.Matrix();
    m.template topRightCorner<3, 1>() = t_;
    return m;
  }

  Scalar Scale() const { return scale_; }
  const SO3<Scalar>& So3() const { return r_; }
  Mat3 Rotation() const { return r_.Matrix(); }
  const Vec3& Translation() const { return t_; }

  // W(omega, sigma), see the header comment.
  static Mat3 W(const Vec3& omega, Scalar sigma) {
    using std::abs;
    using std::cos;
    using std::exp;
    using std::expm1;
    using std::sin;
    using std::sqrt;
    const Scalar theta2 = omega.squaredNorm();
    const Scalar es = exp(sigma);
    const bool small_sigma = abs(sigma) < Scalar(1e-6);
    const Scalar A = small_sigma ? Scalar(1) + sigma / Scalar(2) + sigma * sigma / Scalar(6) : expm1(sigma) / sigma;
    Scalar B, C;
    if (theta2 < Scalar(1e-12)) {
      // B = int tau e^(sigma tau), C = int tau^2/2 e^(sigma tau).
      if (abs(sigma) < Scalar(1e-4)) {
        B = Scalar(0.5) + sigma / Scalar(3) + sigma * sigma / Scalar(8);
        C = Scalar(1) / Scalar(6) + sigma / Scalar(8) + sigma * sigma / Scalar(20);
      } else {
        B = ((sigma - Scalar(1)) * es + Scalar(1)) / (sigma * sigma);
        C = (es * (sigma * sigma - Scalar(2) * sigma + Scalar(2)) - Scalar(2)) /
            (Scalar(2) * sigma * sigma * sigma);
      }
    } else {
      const Scalar theta = sqrt(theta2);
      const Scalar denom = sigma * sigma + theta2;
      const Scalar c = (sigma * (es * cos(theta) - Scalar(1)) + theta * es * sin(theta)) / denom;
      const Scalar b = (sigma * es * sin(theta) - theta * (es * cos(theta) - Scalar(1))) / denom;
      B = b / theta;
      C = (A - c) / theta2;
    }
    const Mat3 Om = SO3<Scalar>::Hat(omega);
    return A * Mat3::Identity() + B * Om + C * Om * Om;
  }

 private:
  Scalar scale_;
  SO3<Scalar> r_;
  Vec3 t_;
};

using Sim3d = Sim3<double>;

}  // namespace dsm
