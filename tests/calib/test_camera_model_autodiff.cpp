// SPDX-License-Identifier: MIT
/// @brief The camera templates instantiated with ceres::Jet (what calibration will optimise
///        through): autodiff derivatives equal the analytic Jacobians.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "tests/calib/camera_model_fixtures.h"
#include "tests/support/jacobian_check.h"

namespace telesphere::test {
namespace {

template <template <typename> class Model>
void expectAutodiffMatchesAnalytic() {
  using Cam = Model<double>;
  constexpr int N = Cam::kNumParams;
  using Jet = ceres::Jet<double, 3 + N>;
  const Cam cam(Lens<Model>::typical());
  Eigen::Matrix<Jet, N, 1> params_jet;
  for (int i = 0; i < N; ++i) params_jet[i] = Jet(cam.params()[i], 3 + i);
  const Model<Jet> cam_jet(params_jet);
  int checked = 0;
  for (const Eigen::Vector3d& dir : sphereDirections(300)) {
    if (std::acos(dir.z()) > cam.maxAngle() - 1e-3) continue;
    const Eigen::Vector3d p = 1.7 * dir;
    Eigen::Vector2d px;
    typename Cam::Mat2x3 J_p;
    typename Cam::Mat2xP J_params;
    ASSERT_TRUE(cam.project(p, px, &J_p, &J_params));
    Eigen::Matrix<Jet, 3, 1> p_jet;
    for (int i = 0; i < 3; ++i) p_jet[i] = Jet(p[i], i);
    Eigen::Matrix<Jet, 2, 1> px_jet;
    ASSERT_TRUE(cam_jet.project(p_jet, px_jet));
    Eigen::Matrix<double, 2, 3 + N> J_auto;
    for (int r = 0; r < 2; ++r) {
      EXPECT_NEAR(px_jet[r].a, px[r], 1e-9);
      J_auto.row(r) = px_jet[r].v.transpose();
    }
    EXPECT_TRUE(jacobianNear(J_p, J_auto.template leftCols<3>(), 1e-9));
    EXPECT_TRUE(jacobianNear(J_params, J_auto.template rightCols<N>(), 1e-9));
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

TEST(CameraModelAutodiff, DoubleSphere) { expectAutodiffMatchesAnalytic<calib::DoubleSphereCamera>(); }
TEST(CameraModelAutodiff, ExtendedUnified) {
  expectAutodiffMatchesAnalytic<calib::ExtendedUnifiedCamera>();
}
TEST(CameraModelAutodiff, KannalaBrandt) { expectAutodiffMatchesAnalytic<calib::KannalaBrandtCamera>(); }
TEST(CameraModelAutodiff, PinholeRadtan) { expectAutodiffMatchesAnalytic<calib::PinholeRadtanCamera>(); }

}  // namespace
}  // namespace telesphere::test
