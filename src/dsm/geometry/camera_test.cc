// SPDX-License-Identifier: MIT
#include "dsm/geometry/camera.h"

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

std::vector<CameraCalibration> AllModels() {
  CameraCalibration pinhole{CameraModel::kPinhole, 640, 480, 400, 410, 320, 240, {}};
  CameraCalibration radtan{CameraModel::kRadTan, 752, 480, 458.654, 457.296, 367.215, 248.375,
                           {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}};
  CameraCalibration radtan5{CameraModel::kRadTan, 640, 480, 500, 500, 320, 240, {-0.2, 0.05, 0.001, -0.002, 0.01}};
  CameraCalibration equi{CameraModel::kEquidistant, 512, 512, 190.98, 190.98, 254.93, 256.90,
                         {0.0034823894, 0.0007150348, -0.0020532361, 0.0002029688}};
  CameraCalibration fov{CameraModel::kFov, 1280, 1024, 446.9, 447.1, 631.2, 510.5, {0.933271}};
  return {pinhole, radtan, radtan5, equi, fov};
}

TEST(Camera, ProjectionJacobianMatchesCentralDifferences) {
  for (const auto& cam : AllModels()) {
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, -0.2, 2.0), Eigen::Vector3d(-0.5, 0.4, 1.1),
                                    Eigen::Vector3d(1e-9, 0.0, 3.0)}) {
      Eigen::Matrix<double, 2, 3> J, numeric;
      cam.Project(p, &J);
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * h;
        numeric.col(k) = (cam.Project(p + d) - cam.Project(p - d)) / (2 * h);
      }
      EXPECT_LT((J - numeric).norm(), 1e-5 * (1 + J.norm())) << CameraModelName(cam.model) << "\n" << J << "\n" << numeric;
    }
  }
}

TEST(Camera, UnprojectInvertsProject) {
  for (const auto& cam : AllModels()) {
    for (int v = 10; v < cam.height; v += 57) {
      for (int u = 10; u < cam.width; u += 61) {
        // This fisheye sees beyond 90 degrees in its corners, which normalized coordinates cannot hold.
        const double rd = std::hypot((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy);
        if (cam.model == CameraModel::kEquidistant && rd > 1.3) continue;
        // The fov model reaches at most r_d = pi / (2 w) (a ray at 90 degrees).
        if (cam.model == CameraModel::kFov && rd > 0.95 * M_PI / (2 * cam.distortion[0])) continue;
        Eigen::Vector2d xy;
        ASSERT_TRUE(cam.Unproject({double(u), double(v)}, &xy)) << CameraModelName(cam.model);
        const Eigen::Vector2d back = cam.Project(Eigen::Vector3d(xy.x(), xy.y(), 1.0));
        EXPECT_NEAR(back.x(), u, 1e-6);
        EXPECT_NEAR(back.y(), v, 1e-6);
      }
    }
  }
}

TEST(Camera, FovMatchesClosedForm) {
  // r_d = atan(2 r tan(w/2)) / w
  const CameraCalibration fov{CameraModel::kFov, 640, 480, 300, 300, 320, 240, {0.9}};
  const double r = 0.7;
  const Eigen::Vector2d d = fov.Distort({r, 0.0});
  EXPECT_NEAR(d.x(), std::atan(2 * r * std::tan(0.45)) / 0.9, 1e-12);
}

TEST(Camera, ValidateNamesTheSourceAndProblem) {
  CameraCalibration cam{CameraModel::kRadTan, 640, 480, 400, 400, 320, 240, {0.1, 0.2}};
  try {
    cam.Validate("calib.yaml");
    FAIL() << "accepted 2 radtan coefficients";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("calib.yaml"), std::string::npos);
    EXPECT_NE(msg.find("radtan"), std::string::npos);
  }
  cam.distortion = {0, 0, 0, 0};
  cam.fx = -1;
  EXPECT_THROW(cam.Validate("x"), InputError);
  cam.fx = 400;
  cam.width = 0;
  EXPECT_THROW(cam.Validate("x"), InputError);
  EXPECT_THROW(ParseCameraModel("banana", "x"), InputError);
  EXPECT_EQ(ParseCameraModel("radial-tangential", "x"), CameraModel::kRadTan);
}

TEST(PinholeCamera, LevelCameraKeepsRaysThroughPixelCentres) {
  const PinholeCamera cam{640, 480, 400, 410, 319.5, 239.5};
  const PinholeCamera c2 = cam.AtLevel(2);
  EXPECT_EQ(c2.width, 160);
  EXPECT_DOUBLE_EQ(c2.fx, 100);
  // A point projecting to level-0 pixel (x, y) projects to ((x + 0.5) / 4 - 0.5, ...) at level 2.
  const Eigen::Vector3d p(0.3, -0.2, 2.0);
  const Eigen::Vector2d u0 = cam.Project(p), u2 = c2.Project(p);
  EXPECT_NEAR(u2.x(), (u0.x() + 0.5) / 4 - 0.5, 1e-12);
  EXPECT_NEAR(u2.y(), (u0.y() + 0.5) / 4 - 0.5, 1e-12);
}

}  // namespace
}  // namespace dsm
