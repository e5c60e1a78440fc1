// SPDX-License-Identifier: MIT
// One property suite for SO3, SE3 and Sim3: round trips, group axioms, the adjoint identity, the
// left-perturbation convention, and Jacobians against central differences.
#include <random>

#include <gtest/gtest.h>

#include "dsm/lie/sim3.h"

namespace dsm {
namespace {

template <typename Group>
typename Group::Tangent RandomTangent(std::mt19937& rng, double rot_scale = 1.0) {
  std::normal_distribution<double> n(0.0, 1.0);
  typename Group::Tangent xi;
  for (int i = 0; i < Group::kDof; ++i) xi(i) = n(rng);
  // Keep rotations inside |omega| < pi for the Log round trip.
  const int rot = Group::kDof == 3 ? 0 : 3;
  xi.template segment<3>(rot) *= rot_scale * 0.8 / std::max(1.0, xi.template segment<3>(rot).norm());
  if constexpr (Group::kDof == 7) xi(6) *= 0.5;
  return xi;
}

template <typename Group>
auto Mat(const Group& g) {
  return g.Matrix();
}

template <typename Group>
class LieGroupTest : public ::testing::Test {
 protected:
  std::mt19937 rng_{42};
};

using Groups = ::testing::Types<SO3d, SE3d, Sim3d>;
TYPED_TEST_SUITE(LieGroupTest, Groups);

TYPED_TEST(LieGroupTest, ExpLogRoundTrip) {
  for (int i = 0; i < 200; ++i) {
    const auto xi = RandomTangent<TypeParam>(this->rng_, 3.0);
    const auto back = TypeParam::Exp(xi).Log();
    EXPECT_LT((back - xi).norm(), 1e-9) << xi.transpose();
    const TypeParam g = TypeParam::Exp(xi);
    EXPECT_LT((Mat(TypeParam::Exp(g.Log())) - Mat(g)).norm(), 1e-9);
  }
}

TYPED_TEST(LieGroupTest, SmallAnglesAreAccurate) {
  for (double scale : {1e-3, 1e-6, 1e-9, 0.0}) {
    auto xi = RandomTangent<TypeParam>(this->rng_);
    xi *= scale;
    EXPECT_LT((TypeParam::Exp(xi).Log() - xi).norm(), 1e-12 + 1e-9 * scale);
  }
}

TYPED_TEST(LieGroupTest, GroupAxioms) {
  const TypeParam a = TypeParam::Exp(RandomTangent<TypeParam>(this->rng_));
  const TypeParam b = TypeParam::Exp(RandomTangent<TypeParam>(this->rng_));
  const TypeParam c = TypeParam::Exp(RandomTangent<TypeParam>(this->rng_));
  EXPECT_LT((Mat((a * b) * c) - Mat(a * (b * c))).norm(), 1e-12);
  EXPECT_LT((Mat(a * a.Inverse()) - Mat(TypeParam())).norm(), 1e-12);
  EXPECT_LT((Mat(a * b) - Mat(a) * Mat(b)).norm(), 1e-12);
}

TYPED_TEST(LieGroupTest, AdjointIdentity) {
  // X Exp(xi) X^-1 = Exp(Adj(X) xi)
  for (int i = 0; i < 50; ++i) {
    const TypeParam x = TypeParam::Exp(RandomTangent<TypeParam>(this->rng_));
    const auto xi = RandomTangent<TypeParam>(this->rng_, 0.5);
    const auto lhs = Mat(x * TypeParam::Exp(xi) * x.Inverse());
    const auto rhs = Mat(TypeParam::Exp(x.Adj() * xi));
    EXPECT_LT((lhs - rhs).norm(), 1e-9);
  }
}

TYPED_TEST(LieGroupTest, ActionJacobianMatchesLeftPerturbation) {
  // d/d(delta) [Exp(delta) X p] at delta = 0, numerically, against the closed form.
  const TypeParam x = TypeParam::Exp(RandomTangent<TypeParam>(this->rng_));
  const Eigen::Vector3d p(0.3, -1.2, 2.5);
  const Eigen::Vector3d q = x * p;
  Eigen::Matrix<double, 3, TypeParam::kDof> numeric, analytic;
  const double h = 1e-6;
  for (int k = 0; k < TypeParam::kDof; ++k) {
    typename TypeParam::Tangent d = TypeParam::Tangent::Zero();
    d(k) = h;
    numeric.col(k) = ((TypeParam::Exp(d) * x) * p - (TypeParam::Exp(-d) * x) * p) / (2 * h);
  }
  const Eigen::Matrix3d hat_q = SO3d::Hat(q);
  if constexpr (TypeParam::kDof == 3) {
    analytic = -hat_q;
  } else if constexpr (TypeParam::kDof == 6) {
    analytic << Eigen::Matrix3d::Identity(), -hat_q;
  } else {
    analytic << Eigen::Matrix3d::Identity(), -hat_q, q;
  }
  EXPECT_LT((numeric - analytic).norm(), 1e-7) << numeric << "\n\n" << analytic;
}

TEST(SO3, LeftJacobianAgainstCentralDifferences) {
  // Exp(w + d) ~= Exp(J_l(w) d) Exp(w): J_l = d Log(Exp(w + d) Exp(w)^-1) / dd.
  std::mt19937 rng(7);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d w = RandomTangent<SO3d>(rng, 2.0);
    Eigen::Matrix3d numeric;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * h;
      numeric.col(k) = ((SO3d::Exp(w + d) * SO3d::Exp(w).Inverse()).Log() -
                        (SO3d::Exp(w - d) * SO3d::Exp(w).Inverse()).Log()) / (2 * h);
    }
    EXPECT_LT((numeric - SO3d::LeftJacobian(w)).norm(), 1e-7);
    EXPECT_LT((SO3d::LeftJacobian(w) * SO3d::LeftJacobianInverse(w) - Eigen::Matrix3d::Identity()).norm(), 1e-10);
    // Right Jacobian: Exp(w + d) ~= Exp(w) Exp(J_r d).
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * h;
      numeric.col(k) = ((SO3d::Exp(w).Inverse() * SO3d::Exp(w + d)).Log() -
                        (SO3d::Exp(w).Inverse() * SO3d::Exp(w - d)).Log()) / (2 * h);
    }
    EXPECT_LT((numeric - SO3d::RightJacobian(w)).norm(), 1e-7);
  }
}

TEST(Sim3, ExpMatchesMatrixExponentialSeries) {
  // The generator of (upsilon, omega, sigma) is [[hat(w) + sigma I, upsilon], [0, 0]].
  std::mt19937 rng(3);
  for (int i = 0; i < 20; ++i) {
    const Sim3d::Tangent xi = RandomTangent<Sim3d>(rng);
    Eigen::Matrix4d G = Eigen::Matrix4d::Zero();
    G.topLeftCorner<3, 3>() = SO3d::Hat(xi.segment<3>(3)) + xi(6) * Eigen::Matrix3d::Identity();
    G.topRightCorner<3, 1>() = xi.head<3>();
    Eigen::Matrix4d sum = Eigen::Matrix4d::Identity(), term = Eigen::Matrix4d::Identity();
    for (int k = 1; k < 40; ++k) {
      term = term * G / k;
      sum += term;
    }
    EXPECT_LT((Sim3d::Exp(xi).Matrix() - sum).norm(), 1e-10);
  }
}

TEST(SE3, KnownValues) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 1, 2, 3, 0, 0, M_PI / 2;
  const SE3d T = SE3d::Exp(xi);
  EXPECT_NEAR((T * Eigen::Vector3d(1, 0, 0) - T.Translation()).y(), 1.0, 1e-12);
  EXPECT_NEAR(T.Translation().z(), 3.0, 1e-12);
}

}  // namespace
}  // namespace dsm
