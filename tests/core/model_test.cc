#include "core/model.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/measurements.h"
#include "core/rotation.h"

namespace nrsfm {
namespace {

TEST(Model, ShapeAndProjectionFollowTheModelEquation) {
  Model model;
  model.Resize(/*frames=*/2, /*cameras=*/1, /*points=*/3, /*bases=*/2);
  model.SetBasisShape(0, (Eigen::Matrix3Xd(3, 3) << 1, 0, 0, 0, 1, 0, 0, 0, 1)
                             .finished());
  model.SetBasisShape(1, Eigen::Matrix3Xd::Ones(3, 3));
  model.weights.col(1) << 2.0, 0.5;
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  model.SetRotation(1, 0, r);
  model.translations.col(1) << 10.0, -3.0;

  // S_1 = 2 I + 0.5 * ones, by hand.
  Eigen::Matrix3d expected_shape = 2.0 * Eigen::Matrix3d::Identity();
  expected_shape.array() += 0.5;
  EXPECT_LT((model.ShapeInObject(1) - expected_shape).norm(), 1e-15);
  EXPECT_LT((model.ShapeInCamera(1, 0) - r * expected_shape).norm(), 1e-12);
  Eigen::Matrix2Xd expected_2d = (r * expected_shape).topRows<2>();
  expected_2d.colwise() += Eigen::Vector2d(10.0, -3.0);
  EXPECT_LT((model.Project(1, 0) - expected_2d).norm(), 1e-12);
  EXPECT_TRUE(model.Validate().ok());
  model.weights(0, 0) = std::nan("");
  EXPECT_FALSE(model.Validate().ok());
}

TEST(Rotation, AngleAxisRoundTripAndNearestRotation) {
  const Eigen::Vector3d aa(0.3, -1.2, 2.0);
  const Eigen::Matrix3d r = AngleAxisToRotation(aa);
  EXPECT_LT((RotationToAngleAxis(r) - aa).norm(), 1e-12);
  EXPECT_NEAR(RotationAngleBetween(r, Eigen::Matrix3d::Identity()), aa.norm(),
              1e-12);
  // A perturbed rotation snaps back; the result is orthonormal with det +1.
  const Eigen::Matrix3d noisy = r + 1e-3 * Eigen::Matrix3d::Ones();
  const Eigen::Matrix3d nearest = NearestRotation(noisy);
  EXPECT_LT((nearest * nearest.transpose() - Eigen::Matrix3d::Identity()).norm(),
            1e-12);
  EXPECT_NEAR(nearest.determinant(), 1.0, 1e-12);
  EXPECT_LT(RotationAngleBetween(nearest, r), 2e-3);
  EXPECT_NEAR(RotationAngleBetween(AngleAxisToRotation(Eigen::Vector3d(1e-9, 0, 0)),
                                   Eigen::Matrix3d::Identity()),
              1e-9, 1e-15);
}

TEST(Measurements, FromMatrixWithNaNBuildsTheMask) {
  Eigen::MatrixXd w(4, 3);
  w << 1, 2, NAN, 3, 4, NAN, 5, 6, 7, 8, 9, 10;
  Measurements m;
  ASSERT_TRUE(Measurements::FromMatrixWithNaN(w, 1, "W", &m).ok());
  EXPECT_EQ(m.num_frames, 2);
  EXPECT_EQ(m.num_points, 3);
  EXPECT_EQ(m.NumVisible(), 5);
  EXPECT_FALSE(m.visible(0, 2));
  EXPECT_EQ(m.VisiblePerView()(0), 2);
  EXPECT_EQ(m.VisiblePerPoint()(2), 1);
  EXPECT_TRUE(m.Validate().ok());

  Eigen::MatrixXd half_missing = w;
  half_missing(1, 0) = NAN;
  Status s = Measurements::FromMatrixWithNaN(half_missing, 1, "W", &m);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("only one coordinate"), std::string::npos);

  Eigen::MatrixXd inf = w;
  inf(3, 1) = INFINITY;
  s = Measurements::FromMatrixWithNaN(inf, 1, "W", &m);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("infinite value at row 4, column 2"),
            std::string::npos)
      << s.message();

  s = Measurements::FromMatrixWithNaN(Eigen::MatrixXd::Zero(3, 2), 1, "W", &m);
  EXPECT_FALSE(s.ok());
  s = Measurements::FromMatrixWithNaN(w, 2, "W", &m);
  EXPECT_TRUE(s.ok());  // 4 rows = 1 frame x 2 cameras.
  EXPECT_EQ(m.num_frames, 1);
  EXPECT_EQ(m.num_cameras, 2);
}

}  // namespace
}  // namespace nrsfm
