#include "core/eval/metrics.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

using Frames = std::vector<Eigen::Matrix3Xd>;

// A centred 5-point shape whose x row is orthogonal to its y and z rows and
// whose point 0 lies on the x axis: (2, 0, 0), (−0.5, ±b, 0), (−0.5, 0, ±c).
// These properties make the e3D alignment of the hand cases below the
// identity, so the errors have closed forms.
Eigen::Matrix3Xd Cross(double b, double c) {
  Eigen::Matrix3Xd x(3, 5);
  x << 2.0, -0.5, -0.5, -0.5, -0.5,  //
      0.0, b, -b, 0.0, 0.0,          //
      0.0, 0.0, 0.0, c, -c;
  return x;
}

Frames TwoCrosses() { return {Cross(1.0, 1.0), Cross(2.0, 0.5)}; }

// e3D's s for TwoCrosses(): the population std of the rows of Cross(b, c)
// are x: 1, y: b √(2/5), z: c √(2/5); s is their mean over the 6 rows.
double E3DScaleOfTwoCrosses() {
  const double k = std::sqrt(0.4);
  return (1.0 + k * 1.0 + k * 1.0 + 1.0 + k * 2.0 + k * 0.5) / 6.0;
}

// A generic frame-varying sequence for the invariance checks.
Frames RandomSequence(int frames, int points, unsigned seed) {
  std::srand(seed);
  Frames shapes;
  for (int t = 0; t < frames; ++t) {
    shapes.push_back(Eigen::Matrix3Xd::Random(3, points));
  }
  return shapes;
}

Frames Transformed(const Frames& shapes, const Eigen::Matrix3d& m) {
  Frames out;
  for (size_t t = 0; t < shapes.size(); ++t) {
    // A different translation per frame: the metrics must ignore it.
    out.push_back((m * shapes[t]).colwise() +
                  Eigen::Vector3d(t, -2.0 * t, 0.5));
  }
  return out;
}

const Eigen::Matrix3d kFlipZ = Eigen::Vector3d(1, 1, -1).asDiagonal();

// Shapes S_t = A + a_t B + b_t C (rank 3 in the F × 3P matrix, rank 2 after
// centring over frames is not asked: the SVD is of the shapes themselves).
// Rank 3 reproduces them (floor 0); rank 1 keeps the best rank-1 part,
// whose e3D is computed here by hand from the same SVD.
TEST(Metrics, RankFloorIsTheE3DOfTheTruncatedTruth) {
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix3Xd a(3, 7), b(3, 7), c(3, 7);
  for (Eigen::Matrix3Xd* m : {&a, &b, &c}) {
    for (int i = 0; i < m->size(); ++i) m->data()[i] = normal(rng);
  }
  std::vector<Eigen::Matrix3Xd> truth;
  for (int t = 0; t < 20; ++t) {
    Eigen::Matrix3Xd shape =
        a + std::sin(0.3 * t) * b + 0.5 * std::cos(0.2 * t) * c;
    truth.push_back(shape.colwise() - shape.rowwise().mean());
  }
  EXPECT_LT(ComputeRankFloorE3D(truth, 3), 1e-12);
  EXPECT_LT(ComputeRankFloorE3D(truth, 5), 1e-12);
  Eigen::MatrixXd rows(20, 21);
  for (int t = 0; t < 20; ++t)
    rows.row(t) = Eigen::Map<const Eigen::RowVectorXd>(truth[t].data(), 21);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(
      rows, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::MatrixXd one = svd.matrixU().col(0) * svd.singularValues()(0) *
                              svd.matrixV().col(0).transpose();
  std::vector<Eigen::Matrix3Xd> estimate;
  for (int t = 0; t < 20; ++t) {
    const Eigen::RowVectorXd row = one.row(t);
    estimate.push_back(Eigen::Map<const Eigen::Matrix3Xd>(row.data(), 3, 7));
  }
  const double floor1 = ComputeRankFloorE3D(truth, 1);
  EXPECT_GT(floor1, 0.01);
  EXPECT_NEAR(floor1, ComputeE3D(truth, estimate), 1e-12);
  EXPECT_GE(floor1, ComputeRankFloorE3D(truth, 2));
}

TEST(Metrics, RotatedCopyScoresZero) {
  const Frames truth = RandomSequence(6, 9, 7);
  const Frames estimate =
      Transformed(truth, AngleAxisToRotation(Eigen::Vector3d(0.3, -2.0, 1.1)));
  EXPECT_LT(ComputeE3D(truth, estimate), 1e-12);
  EXPECT_LT(ComputeError3DPercent(truth, estimate), 1e-10);
  EXPECT_LT(ComputeZErrorPercent(truth, estimate), 1e-10);
}

TEST(Metrics, ScaledE3DAlignsOneGlobalScale) {
  const Frames truth = RandomSequence(6, 9, 7);
  Frames estimate =
      Transformed(truth, AngleAxisToRotation(Eigen::Vector3d(0.3, -2.0, 1.1)));
  for (Eigen::Matrix3Xd& x : estimate) x *= 2.5;
  EXPECT_LT(ComputeScaledE3D(truth, estimate), 1e-12);
  // Without the scale, the nearest orthogonal map leaves the 2.5× size:
  // every centred point is 1.5× its own length off.
  EXPECT_GT(ComputeE3D(truth, estimate), 1.0);
  // A frame scaled on its own is not aligned away.
  estimate[0] *= 1.2;
  EXPECT_GT(ComputeScaledE3D(truth, estimate), 0.01);
}

TEST(Metrics, DepthReflectedCopyScoresZero) {
  const Frames truth = RandomSequence(6, 9, 8);
  const Frames estimate = Transformed(truth, kFlipZ);
  EXPECT_LT(ComputeE3D(truth, estimate), 1e-12);
  EXPECT_LT(ComputeFrobeniusZSign(truth, estimate), 1e-15);
  EXPECT_LT(ComputeError3DPercent(truth, estimate), 1e-10);
  // A reflection combined with a rotation is also aligned away by e3D.
  const Frames mirrored = Transformed(
      truth, AngleAxisToRotation(Eigen::Vector3d(1.0, 0.2, -0.4)) * kFlipZ);
  EXPECT_LT(ComputeE3D(truth, mirrored), 1e-12);
}

TEST(Metrics, E3DOfAKnownOffsetMatchesTheFormula) {
  // The estimate moves point 0 by +0.1 in x in every frame. After centring
  // the offset is 0.1 · (4/5, −1/5, −1/5, −1/5, −1/5) in x; it stays
  // orthogonal to the y and z rows, so the alignment is the identity and
  //   e3D = mean_p |offset_p| / s = (0.08 + 4 · 0.02) / 5 / s.
  const Frames truth = TwoCrosses();
  Frames estimate = truth;
  for (Eigen::Matrix3Xd& x : estimate) x(0, 0) += 0.1;
  const double expected = (0.08 + 4 * 0.02) / 5.0 / E3DScaleOfTwoCrosses();
  EXPECT_NEAR(ComputeE3D(truth, estimate), expected, 1e-14);
  // A global rotation and per-frame translations of the estimate change
  // nothing.
  const Frames moved = Transformed(
      estimate, AngleAxisToRotation(Eigen::Vector3d(0.5, 0.5, -1.5)));
  EXPECT_NEAR(ComputeE3D(truth, moved), expected, 1e-13);
}

TEST(Metrics, E3DUsesThePopulationStd) {
  // Truth = Cross(1, 1) alone, estimate = 0.9 · truth: the least-squares map
  // is 1/0.9 · I, Y = I, and e3D = 0.1 · mean_p ||X_p|| / s with
  // s = (1 + 2 √(2/5)) / 3 (divide by P = 5, not P − 1).
  const Frames truth = {Cross(1.0, 1.0)};
  const Frames estimate = {0.9 * Cross(1.0, 1.0)};
  const double mean_norm = (2.0 + 4.0 * std::sqrt(1.25)) / 5.0;
  const double s = (1.0 + 2.0 * std::sqrt(0.4)) / 3.0;
  EXPECT_NEAR(ComputeE3D(truth, estimate), 0.1 * mean_norm / s, 1e-14);
}

TEST(Metrics, FrobeniusZSignOnATwoFrameHandExample) {
  const Frames truth = TwoCrosses();
  // Frame 0: depth flipped (error 0 after the flip); frame 1: half the size
  // (relative error 0.5; flipping z would make it larger).
  const Frames estimate = {kFlipZ * truth[0], 0.5 * truth[1]};
  EXPECT_NEAR(ComputeFrobeniusZSign(truth, estimate), 0.25, 1e-15);

  // No rotation alignment: a copy turned by 180° about the optical axis,
  // diag(−1, −1, 1) X, keeps an error. Unflipped it is 2 ||(x, y)||_F,
  // flipped 2 ||X||_F; the minimum is the first.
  const Eigen::Matrix3d turn = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  const Frames turned = {turn * truth[0], turn * truth[1]};
  double expected = 0.0;
  for (const Eigen::Matrix3Xd& x : truth) {
    expected += 2.0 * x.topRows<2>().norm() / x.norm();
  }
  expected /= 2.0;
  EXPECT_NEAR(ComputeFrobeniusZSign(truth, turned), expected, 1e-14);
  EXPECT_GT(expected, 1.0);
}

TEST(Metrics, PercentErrorsOnAHandExample) {
  // Estimate = diag(0.5, 1, 0.5) X of Cross(1, 1): the least-squares map is
  // diag(2, 1, 2), Y = I, and the residual of point p is (0.5 x_p, 0, 0.5 z_p).
  const Frames truth = {Cross(1.0, 1.0)};
  const Frames estimate = {Eigen::Vector3d(0.5, 1.0, 0.5).asDiagonal() *
                           truth[0]};
  // Diameter: |(2, 0, 0) − (−0.5, 1, 0)| = √7.25.
  const double size = std::sqrt(7.25);
  EXPECT_NEAR(ShapeSize(truth), size, 1e-15);
  const double mean_distance =
      (1.0 + 0.25 + 0.25 + 2.0 * 0.5 * std::sqrt(1.25)) / 5.0;
  const double mean_z = 0.5 * 2.0 / 5.0;
  EXPECT_NEAR(ComputeError3DPercent(truth, estimate),
              100.0 * mean_distance / size, 1e-12);
  EXPECT_NEAR(ComputeZErrorPercent(truth, estimate), 100.0 * mean_z / size,
              1e-12);
}

TEST(Metrics, ShapeSizeIsTheMeanDiameter) {
  // Frame 1 = Cross(2, 0.5): the farthest pair is (−0.5, 2, 0), (−0.5, −2, 0).
  EXPECT_NEAR(ShapeSize(TwoCrosses()), (std::sqrt(7.25) + 4.0) / 2.0, 1e-15);
}

// The pruned search gives exactly the largest distance over every pair, on
// clouds of several shapes (Gaussian, a sphere's surface where most pairs
// come close to the diameter, a line, repeated points), with left-out (NaN)
// points not counted, and 0 below two finite points.
TEST(Metrics, ShapeSizeEqualsTheLargestDistanceOverEveryPair) {
  const auto every_pair = [](const Eigen::Matrix3Xd& x) {
    double max_squared = 0.0;
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      for (Eigen::Index j = i + 1; j < x.cols(); ++j) {
        if (x.col(i).allFinite() && x.col(j).allFinite()) {
          max_squared =
              std::max(max_squared, (x.col(i) - x.col(j)).squaredNorm());
        }
      }
    }
    return std::sqrt(max_squared);
  };
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int shape = 0; shape < 4; ++shape) {
    for (const int points : {2, 3, 17, 400}) {
      Eigen::Matrix3Xd x(3, points);
      for (int p = 0; p < points; ++p) {
        x.col(p) = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
        if (shape == 1) x.col(p).normalize();
        if (shape == 2)
          x.col(p) = Eigen::Vector3d(1.0, 2.0, -1.0) * normal(rng);
        if (shape == 3) x.col(p) = Eigen::Vector3d(p % 3, 0.0, 1.0);
      }
      SCOPED_TRACE(std::to_string(shape) + ", " + std::to_string(points));
      EXPECT_EQ(ShapeSize({x}), every_pair(x));
      if (points > 3) {
        x.col(1).setConstant(std::numeric_limits<double>::quiet_NaN());
        x(2, points - 1) = std::numeric_limits<double>::infinity();
        EXPECT_EQ(ShapeSize({x}), every_pair(x));
      }
    }
  }
  Eigen::Matrix3Xd one(3, 2);
  one << 1, std::numeric_limits<double>::quiet_NaN(), 2, 0, 3, 0;
  EXPECT_EQ(ShapeSize({one}), 0.0);
  EXPECT_EQ(ShapeSize({Eigen::Matrix3Xd(3, 0)}), 0.0);
}

// Camera-frame-only shapes for EvaluateShapes.
GroundTruth CameraOnly(const Frames& frames) {
  GroundTruth shapes;
  shapes.points_in_camera = frames;
  shapes.source = "test";
  return shapes;
}

TEST(Metrics, EvaluateShapesFillsEveryField) {
  const Frames truth = TwoCrosses();
  Frames estimate = truth;
  for (Eigen::Matrix3Xd& x : estimate) x(0, 0) += 0.1;
  ShapeErrors errors;
  ASSERT_TRUE(
      EvaluateShapes(CameraOnly(truth), CameraOnly(estimate), &errors).ok());
  EXPECT_EQ(errors.e3d_frame, EvaluationFrame::kCamera);
  EXPECT_EQ(errors.e3d_camera, errors.e3d);
  EXPECT_TRUE(std::isnan(errors.rotation_error));
  EXPECT_EQ(errors.num_frames, 2);
  EXPECT_EQ(errors.num_points, 5);
  EXPECT_EQ(errors.e3d, ComputeE3D(truth, estimate));
  EXPECT_EQ(errors.frob_zsign, ComputeFrobeniusZSign(truth, estimate));
  EXPECT_EQ(errors.error3d_pct, ComputeError3DPercent(truth, estimate));
  EXPECT_EQ(errors.zerror_pct, ComputeZErrorPercent(truth, estimate));
  EXPECT_GT(errors.error3d_pct, 0.0);
}

TEST(Metrics, EvaluateShapesRejectsBadInput) {
  const Frames truth = TwoCrosses();
  ShapeErrors errors;
  auto message = [&](const Frames& t, const Frames& e) {
    const Status status = EvaluateShapes(CameraOnly(t), CameraOnly(e), &errors);
    EXPECT_FALSE(status.ok());
    return status.message();
  };
  EXPECT_NE(
      message(truth, {truth[0]}).find("truth has 2 frames, estimate has 1"),
      std::string::npos);
  EXPECT_NE(message({}, {}).find("no frames"), std::string::npos);
  Frames fewer_points = truth;
  fewer_points[1] = truth[1].leftCols(4);
  EXPECT_NE(
      message(truth, fewer_points).find("frame 1 has 5 truth and 4 estimated"),
      std::string::npos);
  Frames with_nan = truth;
  with_nan[1](2, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(with_nan, truth).find("frame 1 of the truth has a NaN"),
            std::string::npos);
  Frames with_inf = truth;
  with_inf[1](2, 3) = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(truth, with_inf)
                .find("frame 1 of the estimate has a NaN or infinite"),
            std::string::npos);
  Frames all_nan = truth;
  for (Eigen::Matrix3Xd& x : all_nan) x.col(1).setConstant(NAN);
  all_nan[0].setConstant(NAN);
  all_nan[1].setConstant(NAN);
  EXPECT_NE(message(truth, all_nan)
                .find("every frame or every point of the estimate is NaN"),
            std::string::npos);
  Frames collapsed = truth;
  collapsed[0].setConstant(3.0);
  EXPECT_NE(
      message(collapsed, truth).find("all points of truth frame 0 coincide"),
      std::string::npos);
}

// NaN in the estimate marks what a reconstruction left out: a frame all NaN
// and a point NaN in some other frame are not scored; the errors are those
// of the rest, exactly as if the rest were given alone.
TEST(Metrics, EvaluateShapesLeavesOutWhatTheEstimateHoldsAsNaN) {
  const Frames truth = RandomSequence(4, 6, 11);
  Frames estimate =
      Transformed(truth, AngleAxisToRotation(Eigen::Vector3d(0.0, 0.0, 0.3)));
  for (Eigen::Matrix3Xd& x : estimate) x(1, 0) += 0.05;  // some error to score
  Frames with_nan = estimate;
  with_nan[2].setConstant(NAN);  // frame 2 left out
  with_nan[0](1, 4) = NAN;       // point 4 left out (one frame suffices)
  with_nan[3].col(4).setConstant(NAN);
  ShapeErrors errors;
  ASSERT_TRUE(
      EvaluateShapes(CameraOnly(truth), CameraOnly(with_nan), &errors).ok());
  EXPECT_EQ(errors.unscored_frames, (std::vector<int>{2}));
  EXPECT_EQ(errors.unscored_points, (std::vector<int>{4}));
  EXPECT_EQ(errors.num_frames, 4);
  EXPECT_EQ(errors.num_points, 6);
  Frames kept_truth, kept_estimate;
  for (int t : {0, 1, 3}) {
    Eigen::Matrix3Xd a(3, 5), b(3, 5);
    a << truth[t].leftCols(4), truth[t].col(5);
    b << estimate[t].leftCols(4), estimate[t].col(5);
    kept_truth.push_back(a);
    kept_estimate.push_back(b);
  }
  EXPECT_GT(errors.e3d, 0.0);
  EXPECT_EQ(errors.e3d, ComputeE3D(kept_truth, kept_estimate));
  EXPECT_EQ(errors.frob_zsign,
            ComputeFrobeniusZSign(kept_truth, kept_estimate));
  EXPECT_EQ(errors.error3d_pct,
            ComputeError3DPercent(kept_truth, kept_estimate));
}

Eigen::Matrix3d RotationZ(double angle) {
  return AngleAxisToRotation(Eigen::Vector3d(0.0, 0.0, angle));
}

TEST(Metrics, RotationErrorOfHandCases) {
  // Frames turned by +θ and −θ about the optical axis: by symmetry the
  // alignment is the identity on the first two rows, and each frame's 2 × 3
  // difference [[cos θ − 1, −sin θ, 0], [sin θ, cos θ − 1, 0]] has spectral
  // norm 2 sin(θ / 2).
  const double angle = 0.3;
  const std::vector<Eigen::Matrix3d> truth(2, Eigen::Matrix3d::Identity());
  EXPECT_NEAR(
      ComputeRotationError(truth, {RotationZ(angle), RotationZ(-angle)}),
      2.0 * std::sin(angle / 2.0), 1e-12);
  // A global rotation, and a global reflection of the object frame (the
  // depth-reflected reconstruction: rows of R times diag(1, 1, −1)), are
  // aligned away.
  std::vector<Eigen::Matrix3d> moving, rotated, reflected;
  const Eigen::Matrix3d global =
      AngleAxisToRotation(Eigen::Vector3d(0.3, -1.1, 0.4));
  const Eigen::Matrix3d flip = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
  for (int t = 0; t < 6; ++t) {
    moving.push_back(
        AngleAxisToRotation(Eigen::Vector3d(0.1 * t, 0.5, -0.2 * t)));
    rotated.push_back(moving.back() * global);
    reflected.push_back(flip * moving.back() * flip);
  }
  EXPECT_LT(ComputeRotationError(moving, rotated), 1e-12);
  EXPECT_LT(ComputeRotationError(moving, reflected), 1e-12);
}

// A sequence with an object frame: shapes S_t and rotations R_t.
GroundTruth WithObjectFrame(const Frames& object,
                            const std::vector<Eigen::Matrix3d>& rotations) {
  GroundTruth shapes;
  shapes.points_in_object = object;
  shapes.rotations = rotations;
  for (std::size_t t = 0; t < object.size(); ++t) {
    shapes.points_in_camera.push_back(rotations[t] * object[t]);
  }
  shapes.source = "test";
  return shapes;
}

TEST(Metrics, ObjectFrameProtocolScoresTheRotations) {
  // Truth: a turning camera around a deforming cross.
  Frames object;
  std::vector<Eigen::Matrix3d> rotations;
  for (int t = 0; t < 8; ++t) {
    object.push_back(Cross(1.0 + 0.1 * t, 1.5 - 0.05 * t));
    rotations.push_back(
        AngleAxisToRotation(Eigen::Vector3d(0.2, 0.1 * t, 0.05)));
  }
  const GroundTruth truth = WithObjectFrame(object, rotations);
  ShapeErrors errors;
  // The same sequence seen in another object frame (a global rotation G:
  // S'_t = G S_t, R'_t = R_t Gᵀ) scores 0 in every frame.
  const Eigen::Matrix3d global =
      AngleAxisToRotation(Eigen::Vector3d(-0.4, 0.9, 0.2));
  Frames object_g;
  std::vector<Eigen::Matrix3d> rotations_g;
  for (int t = 0; t < 8; ++t) {
    object_g.push_back(global * object[t]);
    rotations_g.push_back(rotations[t] * global.transpose());
  }
  ASSERT_TRUE(
      EvaluateShapes(truth, WithObjectFrame(object_g, rotations_g), &errors)
          .ok());
  EXPECT_EQ(errors.e3d_frame, EvaluationFrame::kObject);
  EXPECT_LT(errors.e3d, 1e-12);
  EXPECT_LT(errors.e3d_camera, 1e-12);
  EXPECT_LT(errors.rotation_error, 1e-12);
  // A per-frame drift Q_t of the object frame (S'_t = Q_t S_t, R'_t =
  // R_t Q_tᵀ) leaves the camera frame exact and is scored by the object-frame
  // e3D and the rotation error.
  Frames object_d;
  std::vector<Eigen::Matrix3d> rotations_d;
  for (int t = 0; t < 8; ++t) {
    const Eigen::Matrix3d drift = RotationZ(0.02 * t);
    object_d.push_back(drift * object[t]);
    rotations_d.push_back(rotations[t] * drift.transpose());
  }
  ASSERT_TRUE(
      EvaluateShapes(truth, WithObjectFrame(object_d, rotations_d), &errors)
          .ok());
  EXPECT_LT(errors.e3d_camera, 1e-12);
  EXPECT_EQ(errors.e3d, ComputeE3D(object, object_d));
  EXPECT_GT(errors.e3d, 0.01);
  EXPECT_GT(errors.rotation_error, 0.01);
  // Without an object frame in the estimate the protocol cannot be followed.
  const Status status =
      EvaluateShapes(truth, CameraOnly(truth.points_in_camera), &errors);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no object-frame shapes"), std::string::npos);
}

TEST(Metrics, ReprojectionRmsSkipsMissingEntries) {
  // F = 2, M = 2, P = 3, K = 1; camera 1 has scale 2 and its own rotation.
  Model model;
  model.Resize(2, 2, 3, 1);
  model.SetBasisShape(0, Cross(1.0, 1.0).leftCols(3));
  model.weights.setOnes();
  model.SetRotation(1, 1, AngleAxisToRotation(Eigen::Vector3d(0.0, 0.4, 0.0)));
  model.scales(model.View(1, 1)) = 2.0;
  model.translations.col(model.View(0, 1)) << 5.0, -1.0;

  Measurements m;
  m.num_frames = 2;
  m.num_cameras = 2;
  m.num_points = 3;
  m.W.resize(8, 3);
  m.visible = VisibilityMask::Constant(4, 3, true);
  for (int t = 0; t < 2; ++t) {
    for (int c = 0; c < 2; ++c)
      m.W.middleRows(m.Row(t, c), 2) = model.Project(t, c);
  }
  // Two errors: (0, 3) at (t 0, c 0, p 0) and (1, 2) at (t 1, c 1, p 2);
  // two missing entries with garbage in W. 10 visible entries:
  // RMS = √((9 + 5) / 10).
  m.W(m.Row(0, 0) + 1, 0) += 3.0;
  m.W(m.Row(1, 1), 2) += 1.0;
  m.W(m.Row(1, 1) + 1, 2) += 2.0;
  for (const auto& [t, c, p] : {std::tuple{0, 1, 1}, std::tuple{1, 0, 2}}) {
    m.visible(m.View(t, c), p) = false;
    m.W(m.Row(t, c), p) = std::numeric_limits<double>::quiet_NaN();
    m.W(m.Row(t, c) + 1, p) = 1e9;
  }
  ASSERT_TRUE(m.Validate().ok());
  EXPECT_NEAR(ReprojectionRms(m, model), std::sqrt(1.4), 1e-14);
  EXPECT_NEAR(ReprojectionSquaredError(m, model), 14.0, 1e-13);

  // The same from the reprojection matrix, per frame: frame 0 has 5 visible
  // entries and the error 9, frame 1 has 5 and the error 5.
  Eigen::MatrixXd reprojections(8, 3);
  for (int t = 0; t < 2; ++t) {
    for (int c = 0; c < 2; ++c)
      reprojections.middleRows(m.Row(t, c), 2) = model.Project(t, c);
  }
  FrameReprojectionRms by_frame = ComputeFrameReprojectionRms(m, reprojections);
  ASSERT_EQ(by_frame.frame_rms.size(), 2);
  EXPECT_NEAR(by_frame.frame_rms(0), std::sqrt(9.0 / 5.0), 1e-14);
  EXPECT_NEAR(by_frame.frame_rms(1), std::sqrt(5.0 / 5.0), 1e-14);
  EXPECT_NEAR(by_frame.rms, std::sqrt(1.4), 1e-14);
  // A frame with nothing visible has no RMS.
  m.visible.middleRows(m.View(1, 0), 2).setConstant(false);
  by_frame = ComputeFrameReprojectionRms(m, reprojections);
  EXPECT_TRUE(std::isnan(by_frame.frame_rms(1)));
  EXPECT_NEAR(by_frame.rms, std::sqrt(9.0 / 5.0), 1e-14);
}

TEST(Metrics, CameraFrameShapesAreShapeInCamera) {
  Model model;
  model.Resize(3, 2, 5, 1);
  model.SetBasisShape(0, Cross(1.0, 2.0));
  model.weights.setConstant(1.5);
  model.SetRotation(2, 1, AngleAxisToRotation(Eigen::Vector3d(0.1, 0.2, 0.3)));
  model.scales(model.View(2, 1)) = 0.5;
  const Frames shapes = CameraFrameShapes(model, 1);
  ASSERT_EQ(shapes.size(), 3u);
  EXPECT_LT(
      (shapes[2] - 0.75 * AngleAxisToRotation(Eigen::Vector3d(0.1, 0.2, 0.3)) *
                       Cross(1.0, 2.0))
          .norm(),
      1e-14);
  EXPECT_LT((CameraFrameShapes(model)[0] - 1.5 * Cross(1.0, 2.0)).norm(),
            1e-15);
}

}  // namespace
}  // namespace nrsfm
