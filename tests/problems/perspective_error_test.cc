// The pinhole data term (problems/perspective_error.h): its residual at
// hand-computed points and its Jacobian against numeric differentiation.
#include "problems/perspective_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "core/model/model.h"
#include "tests/problems/functor_test_util.h"

namespace nrsfm {
namespace {

TEST(PerspectiveReprojectionErrorTest,
     ResidualIsThePinholeImageMinusTheObservation) {
  // K = 1, identity rotation, weight 2: X = 2 · (1, -2, 3) + (0.5, 1, 7)
  // = (2.5, -3, 13); u = 800 · 2.5 / 13 + 320, v = 700 · -3 / 13 + 240.
  const Eigen::Vector4d k(800.0, 700.0, 320.0, 240.0);
  const Eigen::Vector2d observed(470.0, 80.0);
  std::unique_ptr<ceres::CostFunction> cost(
      PerspectiveReprojectionError::Create(1, k, observed, 3.0));
  const double rotation[3] = {0.0, 0.0, 0.0}, translation[2] = {0.5, 1.0},
               weights[1] = {2.0}, basis[3] = {1.0, -2.0, 3.0},
               depth[1] = {7.0};
  const double* parameters[] = {rotation, translation, weights, basis, depth};
  double residuals[2];
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], 3.0 * (800.0 * 2.5 / 13.0 + 320.0 - 470.0), 1e-12);
  EXPECT_NEAR(residuals[1], 3.0 * (700.0 * -3.0 / 13.0 + 240.0 - 80.0), 1e-12);
}

TEST(PerspectiveReprojectionErrorTest, PointBehindTheCameraFailsTheEvaluation) {
  std::unique_ptr<ceres::CostFunction> cost(
      PerspectiveReprojectionError::Create(1, Eigen::Vector4d(500, 500, 0, 0),
                                           Eigen::Vector2d(0, 0), 1.0));
  const double rotation[3] = {0, 0, 0}, translation[2] = {0, 0},
               weights[1] = {1.0}, basis[3] = {0.0, 0.0, -3.0},
               depth[1] = {2.0};  // z = 2 - 3 < 0
  const double* parameters[] = {rotation, translation, weights, basis, depth};
  double residuals[2];
  EXPECT_FALSE(cost->Evaluate(parameters, residuals, nullptr));
}

TEST(PerspectiveReprojectionErrorTest, JacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(3);
  for (const int num_bases : {1, 3}) {
    std::unique_ptr<ceres::CostFunction> cost(
        PerspectiveReprojectionError::Create(
            num_bases, Eigen::Vector4d(600, 650, 300, 200),
            Eigen::Vector2d(310, 190), 0.7));
    const std::vector<double> rotation = testing_util::Random(3, &rng);
    const std::vector<double> translation = testing_util::Random(2, &rng);
    const std::vector<double> weights = testing_util::Random(num_bases, &rng);
    const std::vector<double> basis = testing_util::Random(3 * num_bases, &rng);
    const std::vector<double> depth = {6.0};
    testing_util::ExpectGradientCheckPasses(
        *cost, {rotation.data(), translation.data(), weights.data(),
                basis.data(), depth.data()});
  }
}

TEST(PerspectiveModelTest, ProjectIsThePinholeImageOfShapeInCamera) {
  Model model;
  model.Resize(1, 1, 1, 1);
  model.camera = CameraModel::kPerspective;
  model.intrinsics = Eigen::Vector4d(800.0, 700.0, 320.0, 240.0);
  model.weights(0, 0) = 2.0;
  model.basis.col(0) << 1.0, -2.0, 3.0;
  model.translations.col(0) << 0.5, 1.0;
  model.depths(0) = 7.0;
  ASSERT_TRUE(model.Validate().ok());
  EXPECT_TRUE(model.ShapeInCamera(0, 0).col(0).isApprox(
      Eigen::Vector3d(2.5, -3.0, 13.0)));
  const Eigen::Vector2d w = model.Project(0, 0).col(0);
  EXPECT_NEAR(w.x(), 800.0 * 2.5 / 13.0 + 320.0, 1e-12);
  EXPECT_NEAR(w.y(), 700.0 * -3.0 / 13.0 + 240.0, 1e-12);
  model.intrinsics(0, 0) = 0.0;
  EXPECT_FALSE(model.Validate().ok());
}

}  // namespace
}  // namespace nrsfm
