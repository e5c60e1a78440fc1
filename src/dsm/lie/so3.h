// SPDX-License-Identifier: MIT
// SO(3): rotations, stored as a unit quaternion.
//
// Convention used by every group in this folder (lie/):
//   * Exp maps a tangent vector to the group, Log is its inverse (for |omega| < pi).
//   * Perturbations are applied on the LEFT: X(delta) = Exp(delta) * X. Jacobians "with respect to
//     X" are with respect to this delta at delta = 0.
//   * Adj(X) satisfies  X * Exp(xi) * X^-1 = Exp(Adj(X) * xi).
//
// Left Jacobian J_l(w) = sum_k (hat w)^k / (k+1)!:
//   Exp(w + d) ~= Exp(J_l(w) d) * Exp(w)    and    Exp(w + d) ~= Exp(w) * Exp(J_r(w) d),
//   J_r(w) = J_l(-w).
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dsm {

template <typename Scalar>
class SO3 {
 public:
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using Mat3 = Eigen::Matrix<Scalar, 3, 3>;
  using Quat = Eigen::Quaternion<Scalar>;
  using Tangent = Vec3;
  static constexpr int kDof = 3;

  SO3() : q_(Quat::Identity()) {}
  explicit SO3(const Quat& q) : q_(q.normalized()) {}
  explicit SO3(const Mat3& rotation) : q_(Quat(rotation).normalized()) {}
  // q bit for bit, not normalised again: for a rotation read back as it was written (the caller
  // has checked that |q| is 1 to rounding).
  static SO3 FromUnitQuaternion(const Quat& q) {
    SO3 r;
    r.q_ = q;
    return r;
  }

  static SO3 Exp(const Vec3& w) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Scalar theta2 = w.squaredNorm();
    Scalar real;
    Scalar imag_factor;  // sin(theta/2) / theta
    if (theta2 < Scalar(1e-16)) {
      real = Scalar(1) - theta2 / Scalar(8);
      imag_factor = Scalar(0.5) - theta2 / Scalar(48);
    } else {
      const Scalar theta = sqrt(theta2);
      real = cos(theta / Scalar(2));
      imag_factor = sin(theta / Scalar(2)) / theta;
    }
    SO3 r;
    r.q_ = Quat(real, imag_factor * w.x(), imag_factor * w.y(), imag_factor * w.z());
    r.q_.normalize();
    return r;
  }

  Vec3 Log() const {
    using std::atan2;
    using std::sqrt;
    // q = (cos(theta/2), sin(theta/2) n); use the representative with w >= 0 so |theta| <= pi.
    Quat q = q_;
    if (q.w() < Scalar(0)) q.coeffs() = -q.coeffs();
    const Vec3 v = q.vec();
    const Scalar s2 = v.squaredNorm();
    if (s2 < Scalar(1e-16)) {
      // theta ~= 2 s, theta / s ~= 2 / w * (1 - s^2 / (3 w^2))
      return v * (Scalar(2) / q.w() - Scalar(2) * s2 / (Scalar(3) * q.w() * q.w() * q.w()));
    }
    const Scalar s = sqrt(s2);
    const Scalar theta = Scalar(2) * atan2(s, q.w());
    return v * (theta / s);
  }

  SO3 Inverse() const { return SO3(q_.conjugate()); }
  SO3 operator*(const SO3& other) const { return SO3(q_ * other.q_); }
  Vec3 operator*(const Vec3& p) const { return q_ * p; }

  Mat3 Matrix() const { return q_.toRotationMatrix(); }
  Mat3 Adj() const { return Matrix(); }
  const Quat& Quaternion() const { return q_; }

  template <typename Other>
  SO3<Other> Cast() const {
    return SO3<Other>(q_.template cast<Other>());
  }

  static Mat3 Hat(const Vec3& w) {
    Mat3 m;
    m << Scalar(0), -w.z(), w.y(), w.z(), Scalar(0), -w.x(), -w.y(), w.x(), Scalar(0);
    return m;
  }
  static Vec3 Vee(const Mat3& m) { return Vec3(m(2, 1), m(0, 2), m(1, 0)); }

  // J_l(w) = I + (1 - cos t)/t^2 W + (t - sin t)/t^3 W^2,  W = hat(w), t = |w|.
  static Mat3 LeftJacobian(const Vec3& w) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Scalar t2 = w.squaredNorm();
    const Mat3 W = Hat(w);
    Scalar a, b;
    if (t2 < Scalar(1e-10)) {
      a = Scalar(0.5) - t2 / Scalar(24);
      b = Scalar(1) / Scalar(6) - t2 / Scalar(120);
    } else {
      const Scalar t = sqrt(t2);
      a = (Scalar(1) - cos(t)) / t2;
      b = (t - sin(t)) / (t2 * t);
    }
    return Mat3::Identity() + a * W + b * W * W;
  }

  // J_l^-1(w) = I - 1/2 W + (1/t^2 - (1 + cos t) / (2 t sin t)) W^2.
  static Mat3 LeftJacobianInverse(const Vec3& w) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Scalar t2 = w.squaredNorm();
    const Mat3 W = Hat(w);
    Scalar c;
    if (t2 < Scalar(1e-10)) {
      c = Scalar(1) / Scalar(12) + t2 / Scalar(720);
    } else {
      const Scalar t = sqrt(t2);
      c = Scalar(1) / t2 - (Scalar(1) + cos(t)) / (Scalar(2) * t * sin(t));
    }
    return Mat3::Identity() - Scalar(0.5) * W + c * W * W;
  }

  static Mat3 RightJacobian(const Vec3& w) { return LeftJacobian(-w); }

 private:
  Quat q_;
};

using SO3d = SO3<double>;
using SO3f = SO3<float>;

}  // namespace dsm
