#include "core/model/model.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

#include "core/math/rotation.h"
#include "core/model/measurements.h"

namespace nrsfm {
namespace {

TEST(Model, ShapeAndProjectionFollowTheModelEquation) {
  Model model;
  model.Resize(/*frames=*/2, /*cameras=*/1, /*points=*/3, /*bases=*/2);
  model.SetBasisShape(
      0, (Eigen::Matrix3Xd(3, 3) << 1, 0, 0, 0, 1, 0, 0, 0, 1).finished());
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

// A model of F = 6 frames, P = 5 points whose shapes have rank 2, written
// with K = 4 bases (the last two mix the first two): every shape is
// S_t = a_t A + b_t B.
Model RankTwoModelWithFourBases() {
  Model model;
  model.Resize(/*frames=*/6, /*cameras=*/1, /*points=*/5, /*bases=*/4);
  Eigen::Matrix3Xd a(3, 5), b(3, 5);
  a << 1, 0, 0, 2, -1, 0, 1, 0, 1, 3, 0, 0, 1, -2, 1;
  b << 0, 2, 1, 0, 1, 1, 0, -1, 2, 0, 3, 1, 0, 0, -1;
  model.SetBasisShape(0, a);
  model.SetBasisShape(1, b);
  model.SetBasisShape(2, a + b);
  model.SetBasisShape(3, 2.0 * a - b);
  for (int t = 0; t < 6; ++t) {
    model.weights.col(t) << 1.0 + 0.1 * t, std::sin(t), 0.2 * t, -0.1 * t * t;
    model.SetRotation(t, 0,
                      Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitY())
                          .toRotationMatrix());
    model.translations.col(t) << t, -t;
  }
  return model;
}

TEST(Model, ReduceNumBasesKeepsARankKSequenceExactly) {
  const Model model = RankTwoModelWithFourBases();
  const Model reduced = ReduceNumBases(model, 2);
  EXPECT_EQ(reduced.num_bases, 2);
  EXPECT_EQ(reduced.weights.rows(), 2);
  EXPECT_EQ(reduced.basis.rows(), 6);
  for (int t = 0; t < model.num_frames; ++t) {
    EXPECT_LT((reduced.ShapeInObject(t) - model.ShapeInObject(t)).norm(), 1e-12)
        << t;
  }
  EXPECT_EQ(reduced.rotations, model.rotations);
  EXPECT_EQ(reduced.translations, model.translations);
  EXPECT_TRUE(reduced.Validate().ok());
  // One basis keeps the best rank-1 approximation: its residual is the
  // second singular value of the F × 3P shape matrix, by hand below.
  Eigen::MatrixXd shapes(6, 15);
  for (int t = 0; t < 6; ++t) {
    const Eigen::Matrix3Xd s = model.ShapeInObject(t);
    shapes.row(t) = Eigen::Map<const Eigen::RowVectorXd>(s.data(), 15);
  }
  const Eigen::VectorXd sigma =
      Eigen::JacobiSVD<Eigen::MatrixXd>(shapes).singularValues();
  const Model one = ReduceNumBases(model, 1);
  double residual = 0.0;
  for (int t = 0; t < 6; ++t) {
    residual += (one.ShapeInObject(t) - model.ShapeInObject(t)).squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(residual), sigma(1), 1e-10);
}

TEST(Model, ReduceNumBasesLeavesOutFramesWithNaNWeights) {
  Model model = RankTwoModelWithFourBases();
  model.weights.col(3).setConstant(std::nan(""));
  const Model reduced = ReduceNumBases(model, 2);
  EXPECT_TRUE(reduced.weights.col(3).array().isNaN().all());
  for (int t : {0, 1, 2, 4, 5}) {
    EXPECT_LT((reduced.ShapeInObject(t) - model.ShapeInObject(t)).norm(), 1e-12)
        << t;
  }
}

TEST(Model, MakeFirstBasisTheMeanKeepsTheShapes) {
  Model model = RankTwoModelWithFourBases();
  const Model before = model;
  ASSERT_TRUE(model.MakeFirstBasisTheMean());
  EXPECT_LT(
      (model.weights.rowwise().mean() - Eigen::VectorXd::Unit(4, 0)).norm(),
      1e-12);
  Eigen::Matrix3Xd mean = Eigen::Matrix3Xd::Zero(3, 5);
  for (int t = 0; t < 6; ++t) {
    EXPECT_LT((model.ShapeInObject(t) - before.ShapeInObject(t)).norm(), 1e-12)
        << t;
    mean += before.ShapeInObject(t) / 6.0;
  }
  EXPECT_LT((model.BasisShape(0) - mean).norm(), 1e-12);
  // Zero mean weights: nothing to do, nothing changed.
  model.weights.setZero();
  const Model zero = model;
  EXPECT_FALSE(model.MakeFirstBasisTheMean());
  EXPECT_EQ(model.basis, zero.basis);
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
  EXPECT_LT(
      (nearest * nearest.transpose() - Eigen::Matrix3d::Identity()).norm(),
      1e-12);
  EXPECT_NEAR(nearest.determinant(), 1.0, 1e-12);
  EXPECT_LT(RotationAngleBetween(nearest, r), 2e-3);
  EXPECT_NEAR(
      RotationAngleBetween(AngleAxisToRotation(Eigen::Vector3d(1e-9, 0, 0)),
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
