// SPDX-License-Identifier: MIT
// SE(3): rigid transforms p -> R p + t. Tangent xi = (upsilon, omega): translation part first.
//
//   Exp(xi) = [ Exp(omega)  J_l(omega) upsilon ]      Adj = [ R   hat(t) R ]
//             [ 0           1                  ]            [ 0   R        ]
//
// Left perturbation (see so3.h): d/d(delta) [Exp(delta) * T * p] = [ I  -hat(T p) ].
#pragma once

#include "dsm/lie/so3.h"

namespace dsm {

template <typename Scalar>
class SE3 {
 public:
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Mat3 = Eigen::Matrix<Scalar, 3, 3>;
  using Mat4 = Eigen::Matrix<Scalar, 4, 4>;
  using Tangent = Eigen::Matrix<Scalar, 6, 1>;
  using AdjMatrix = Eigen::Matrix<Scalar, 6, 6>;
  static constexpr int kDof = 6;

  SE3() : t_(Vec3::Zero()) {}
  SE3(const SO3<Scalar>& r, const Vec3& t) : r_(r), t_(t) {}
  SE3(const Eigen::Quaternion<Scalar>& q, const Vec3& t) : r_(q), t_(t) {}
  explicit SE3(const Mat4& m) : r_(Mat3(m.template topLeftCorner<3, 3>())), t_(m.template topRightCorner<3, 1>()) {}

  static SE3 Exp(const Tangent& xi) {
    const Vec3 upsilon = xi.template head<3>();
    const Vec3 omega = xi.template tail<3>();
    return SE3(SO3<Scalar>::Exp(omega), SO3<Scalar>::LeftJacobian(omega) * upsilon);
  }

  Tangent Log() const {
    const Vec3 omega = r_.Log();
    Tangent xi;
    xi << SO3<Scalar>::LeftJacobianInverse(omega) * t_, omega;
    return xi;
  }

  SE3 Inverse() const {
    const SO3<Scalar> r_inv = r_.Inverse();
    return SE3(r_inv, -(r_inv * t_));
  }
  SE3 operator*(const SE3& o) const { return SE3(r_ * o.r_, r_ * o.t_ + t_); }
  Vec3 operator*(const Vec3& p) const { return r_ * p + t_; }

  AdjMatrix Adj() const {
    AdjMatrix a = AdjMatrix::Zero();
    const Mat3 R = r_.Matrix();
    a.template topLeftCorner<3, 3>() = R;
    a.template topRightCorner<3, 3>() = SO3<Scalar>::Hat(t_) * R;
    a.template bottomRightCorner<3, 3>() = R;
    return a;
  }

  Mat4 Matrix() const {
    Mat4 m = Mat4::Identity();
    m.template topLeftCorner<3, 3>() = r_.Matrix();
    m.template topRightCorner<3, 1>() = t_;
    return m;
  }

  const SO3<Scalar>& So3() const { return r_; }
  Mat3 Rotation() const { return r_.Matrix(); }
  const Vec3& Translation() const { return t_; }
  void SetTranslation(const Vec3& t) { t_ = t; }

  template <typename Other>
  SE3<Other> Cast() const {
    return SE3<Other>(r_.template Cast<Other>(), t_.template cast<Other>());
  }

 private:
  SO3<Scalar> r_;
  Vec3 t_;
};

using SE3d = SE3<double>;
using SE3f = SE3<float>;

}  // namespace dsm
