#include "solvers/pipeline/prior_rule.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/math/rotation.h"
#include "core/math/statistics.h"
#include "core/math/svd.h"
#include "core/model/option_checker.h"
#include "problems/extra_terms.h"
#include "solvers/start/low_rank_completion.h"

namespace nrsfm {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;

// The tracks view by view (a view's rows of W and of `visible` contiguous;
// in the measurements its entries are 2·F·M values apart), copied once for
// the steps of every lag, and the image spread.
struct ViewMajorTracks {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> w;
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> visible;
  double spread = 0.0;
};

ViewMajorTracks MakeViewMajor(const Measurements& measurements) {
  ViewMajorTracks tracks;
  tracks.spread = measurements.ImageSpreadRms();
  const int rows = static_cast<int>(measurements.W.rows());
  const int views = measurements.NumViews(), points = measurements.num_points;
  tracks.w.resize(rows, points);
  tracks.visible.resize(views, points);
  // In tiles of 64 points, so that both sides are read and written in
  // cache lines.
  constexpr int kTile = 64;
  for (int begin = 0; begin < points; begin += kTile) {
    const int width = std::min(kTile, points - begin);
    tracks.w.middleCols(begin, width) = measurements.W.middleCols(begin, width);
    tracks.visible.middleCols(begin, width) =
        measurements.visible.middleCols(begin, width);
  }
  return tracks;
}

double MedianTrackStep(const Measurements& measurements,
                       const ViewMajorTracks& tracks, int lag) {
  if (!(tracks.spread > 0.0) || lag < 1) return -1.0;
  std::vector<double> steps;
  for (int t = lag; t < measurements.num_frames; ++t) {
    double sum = 0.0;
    int count = 0;
    for (int c = 0; c < measurements.num_cameras; ++c) {
      const int view = measurements.View(t, c);
      const int previous = measurements.View(t - lag, c);
      const double* u = tracks.w.row(2 * view).data();
      const double* v = tracks.w.row(2 * view + 1).data();
      const double* u0 = tracks.w.row(2 * previous).data();
      const double* v0 = tracks.w.row(2 * previous + 1).data();
      const bool* seen = tracks.visible.row(view).data();
      const bool* seen0 = tracks.visible.row(previous).data();
      for (int p = 0; p < measurements.num_points; ++p) {
        if (!seen[p] || !seen0[p]) continue;
        sum += Eigen::Vector2d(u[p] - u0[p], v[p] - v0[p]).squaredNorm();
        ++count;
      }
    }
    if (count > 0) steps.push_back(std::sqrt(sum / count) / tracks.spread);
  }
  return UpperMedian(std::move(steps), -1.0);
}

double TrackOrder(const Measurements& measurements,
                  const ViewMajorTracks& tracks) {
  const double step = MedianTrackStep(measurements, tracks, 1);
  if (measurements.num_frames < 8 || !(step > 0.0)) return -1.0;
  double order = -1.0;
  for (int lag = 2; lag <= measurements.num_frames / 2; lag *= 2) {
    order = std::max(order, MedianTrackStep(measurements, tracks, lag) / step);
  }
  return order;
}

}  // namespace

Status PriorRuleOptions::Check() const {
  OptionChecker check("prior rule options");
  check.Require(std::isfinite(min_track_order) && min_track_order > 1.0,
                "min_track_order must be > 1 (frames in no order have a ratio "
                "near 1), got " +
                    std::to_string(min_track_order));
  check.FinitePositive("min_basis_fraction", min_basis_fraction);
  check.FinitePositive("temporal_shape_weight", temporal_shape_weight);
  check.Require(
      std::isfinite(min_temporal_shape_weight) &&
          min_temporal_shape_weight > 0.0 &&
          min_temporal_shape_weight <= temporal_shape_weight,
      "min_temporal_shape_weight must be in (0, temporal_shape_weight], "
      "got " +
          std::to_string(min_temporal_shape_weight));
  check.FinitePositive("deformation_weight", deformation_weight);
  check.FinitePositive("rigidity_weight", rigidity_weight);
  check.FiniteAtLeast("max_path_acceleration_deg", max_path_acceleration_deg,
                      0.0);
  check.FiniteAtLeast("max_prior_fit_ratio", max_prior_fit_ratio, 1.0);
  check.FinitePositive("rotation_acceleration_weight",
                       rotation_acceleration_weight);
  check.Require(camera_rank_fraction > 0.0 && camera_rank_fraction < 1.0,
                "camera_rank_fraction must be in (0, 1), got " +
                    std::to_string(camera_rank_fraction));
  check.FiniteAtLeast("camera_fit_threshold", camera_fit_threshold, 1.0);
  check.Require(
      camera_function_tolerance > 0.0 && camera_function_tolerance < 1.0,
      "camera_function_tolerance must be in (0, 1), got " +
          std::to_string(camera_function_tolerance));
  return check.status();
}

double MedianTrackStep(const Measurements& measurements, int lag) {
  if (lag < 1) return -1.0;
  return MedianTrackStep(measurements, MakeViewMajor(measurements), lag);
}

double TrackOrder(const Measurements& measurements) {
  return TrackOrder(measurements, MakeViewMajor(measurements));
}

double MedianPathAccelerationDeg(const Model& model, int lag) {
  if (lag < 1 || model.num_frames < 2 * lag + 1) return -1.0;
  std::vector<double> accelerations;
  accelerations.reserve(model.num_frames - 2 * lag);
  const double lag2 = static_cast<double>(lag) * lag;
  for (int t = lag; t + lag < model.num_frames; ++t) {
    const Eigen::Vector3d before = RotationToAngleAxis(
        model.Rotation(t, 0) * model.Rotation(t - lag, 0).transpose());
    const Eigen::Vector3d after = RotationToAngleAxis(
        model.Rotation(t + lag, 0) * model.Rotation(t, 0).transpose());
    accelerations.push_back((after - before).norm() / lag2 * kDegreesPerRadian);
  }
  return UpperMedian(std::move(accelerations), -1.0);
}

double PathAccelerationDeg(const Model& model) {
  constexpr int kLag = 4;
  const double long_lag = MedianPathAccelerationDeg(model, kLag);
  if (long_lag < 0.0) return -1.0;
  return std::max(
      0.0, long_lag - MedianPathAccelerationDeg(model, 1) / (kLag * kLag));
}

double TemporalNoiseRms(const Measurements& measurements) {
  // d = x_(t+3) − 3 x_(t+2) + 3 x_(t+1) − x_t over four consecutive frames
  // where the point is visible: white noise of variance σ² gives
  // Var(d) = 20 σ²; a smooth track's d is its small third derivative. The
  // median absolute value is robust to the frames where the motion is not
  // smooth: σ̂ = 1.4826 · median|d| / √20.
  std::vector<double> differences;
  for (int c = 0; c < measurements.num_cameras; ++c) {
    for (int p = 0; p < measurements.num_points; ++p) {
      for (int t = 0; t + 3 < measurements.num_frames; ++t) {
        bool seen = true;
        for (int i = 0; i < 4; ++i)
          seen &= measurements.visible(measurements.View(t + i, c), p);
        if (!seen) continue;
        for (int row = 0; row < 2; ++row) {
          const auto x = [&](int i) {
            return measurements.W(2 * measurements.View(t + i, c) + row, p);
          };
          differences.push_back(
              std::abs(x(3) - 3.0 * x(2) + 3.0 * x(1) - x(0)));
        }
      }
    }
  }
  if (differences.empty()) return -1.0;
  return 1.4826 * UpperMedian(std::move(differences), -1.0) / std::sqrt(20.0);
}

int LargestSupportedBases(const Measurements& measurements) {
  // A rank-3K' fit needs 3K' + 1 ≤ min(P, 2FM), and with missing entries
  // every view with 3K' + 1 points and every point in ⌈3K' / 2⌉ views
  // (solvers/start/low_rank_completion.h).
  int largest =
      (std::min(measurements.num_points, 2 * measurements.NumViews()) - 1) / 3;
  if (!measurements.IsComplete()) {
    const int fewest_points = measurements.VisiblePerView().minCoeff();
    const int fewest_views = measurements.VisiblePerPoint().minCoeff();
    while (largest > 0 && (fewest_points < 3 * largest + 1 ||
                           2 * fewest_views < 3 * largest)) {
      --largest;
    }
  }
  return std::max(0, largest);
}

int CameraBasesCap(const PriorRuleOptions& options,
                   const Measurements& measurements) {
  const int smaller =
      std::min(measurements.num_points, 2 * measurements.NumViews());
  return std::max(
      1, std::min(
             {LargestSupportedBases(measurements), kMaxCameraBases,
              static_cast<int>(options.camera_rank_fraction * smaller / 3.0)}));
}

Status AnalyseTrackRank(const PriorRuleOptions& options,
                        const Measurements& measurements, int num_bases,
                        bool video, PriorDecision* decision,
                        LowRankCompletionMemo* completions) {
  decision->model_explains_tracks = true;
  decision->camera_num_bases = num_bases;
  decision->noise_rms = -1.0;
  decision->exactly_low_rank = false;
  const int rows = 2 * measurements.NumViews();
  const int points = measurements.num_points;
  const bool complete = measurements.IsComplete();
  int largest = LargestSupportedBases(measurements);
  largest = std::min(largest, kMaxCameraBases + 1);
  // A rank-3K fit needs that many bases supported (the start fails
  // otherwise, with its own message).
  if (largest < num_bases) return Status::OK();

  // RSS(r), what a rank-r affine fit of the tracks leaves on the visible
  // entries: from the singular values of the row-centred tracks, or, with
  // missing entries, the residual of the rank-r completion.
  Eigen::VectorXd sigma;
  double spread2 = 0.0;  // mean squared centred coordinate
  if (complete) {
    const Eigen::MatrixXd centred =
        measurements.W.colwise() - measurements.W.rowwise().mean();
    sigma = ComputeThinSvd(centred, SingularVectors::kNone).singular_values;
    spread2 = centred.squaredNorm() / centred.size();
  } else {
    const double spread = measurements.ImageSpreadRms();
    spread2 = spread * spread / 2.0;
  }
  const double n_total = complete ? static_cast<double>(rows) * points
                                  : 2.0 * measurements.NumVisible();
  Status failed;
  const auto rss = [&](int r) {
    if (complete) {
      return r < sigma.size() ? sigma.tail(sigma.size() - r).squaredNorm()
                              : 0.0;
    }
    LowRankCompletion completion;
    const Status status =
        completions != nullptr
            ? completions->Complete(r, LowRankCompletionOptions(), &completion)
            : CompleteLowRankAffine(measurements, r, LowRankCompletionOptions(),
                                    &completion);
    if (!status.ok()) failed = status;
    return completion.residual_rms * completion.residual_rms * n_total;
  };
  // n(r): the free parameters of a rank-r fit (a factor pair less its r × r
  // gauge, plus a translation per row).
  const auto parameters = [&](int r) {
    return static_cast<double>(rows) * (r + 1) +
           static_cast<double>(points) * r - static_cast<double>(r) * r;
  };
  // Noise-free data: no residual below round-off is asked for, nor, with
  // missing entries, below what the completion itself reaches on exact data
  // (its ridge and ALS leave 10⁻⁵–10⁻⁴ of the spread: 7·10⁻⁶ on the shoe,
  // 1.0·10⁻⁴ on its first 100 frames with rarely seen points left out).
  const double floor_rms = (complete ? 1e-6 : 1e-4) * std::sqrt(2.0 * spread2);
  // Exact low rank: within camera_fit_threshold of that floor (10⁻⁴ of the
  // spread) with every entry, 5· that with missing ones: real tracks, whose
  // noise is 1 px or more over a spread of hundreds, are far above both.
  const double exact_rms =
      (complete ? 1.0 : 5.0) * options.camera_fit_threshold * floor_rms;
  const auto fit_rms = [&](int k) {
    return std::sqrt(2.0 * rss(3 * k) / n_total);
  };
  decision->exactly_low_rank = fit_rms(num_bases) <= exact_rms;
  if (largest <= num_bases) return failed.WithContext("rank of the tracks");
  // With missing entries the completion's residual is no unbiased reading
  // of the misfit (its ridge and unconverged rounds leave about the same
  // excess at every rank: on the seed's shoe 1.28–1.38× the noise from rank
  // 12 to 42, each completion 10–18 s); the camera is then estimated with K
  // bases, and the noise is estimated only for a video (third differences).
  if (!complete) {
    const double noise = video ? TemporalNoiseRms(measurements) : -1.0;
    if (noise >= 0.0) decision->noise_rms = noise;
    return failed.WithContext("rank of the tracks");
  }
  // The noise per coordinate: for a video from the tracks' third
  // differences (TemporalNoiseRms), which the deformation does not enter;
  // otherwise what the largest rank leaves, per degree of freedom.
  double variance = -1.0;
  if (video) {
    const double noise = TemporalNoiseRms(measurements);
    if (noise >= 0.0) variance = noise * noise;
  }
  if (variance < 0.0) {
    // At most half the smaller dimension: the residual of a rank close to
    // it keeps only the smallest singular values of the noise, and
    // underestimates it (with 400 × 60 tracks of 1 % noise, rank 51 read the
    // rank-9 model of 3 exact bases as a misfit).
    const int noise_bases = std::min(largest, std::min(points, rows) / 6);
    if (noise_bases <= num_bases) return Status::OK();
    const double dof = n_total - parameters(3 * noise_bases);
    if (!(dof > 0.0)) return Status::OK();
    variance = rss(3 * noise_bases) / dof;
  }
  decision->noise_rms = std::sqrt(variance);
  const auto explains = [&](int k) {
    const double rms = fit_rms(k);
    const double expected = std::sqrt(
        variance * 2.0 * std::max(0.0, n_total - parameters(3 * k)) / n_total);
    return rms <= options.camera_fit_threshold * std::max(expected, floor_rms);
  };
  decision->model_explains_tracks = explains(num_bases);
  if (decision->model_explains_tracks)
    return failed.WithContext("rank of the tracks");
  const int cap = CameraBasesCap(options, measurements);
  for (int k = num_bases + 1; k <= cap; ++k) {
    decision->camera_num_bases = k;
    if (explains(k)) break;
  }
  return failed.WithContext("rank of the tracks");
}

Status DecidePriors(const PriorRuleOptions& options,
                    const Measurements& measurements, int num_bases,
                    PriorDecision* decision,
                    LowRankCompletionMemo* completions) {
  const ViewMajorTracks tracks = MakeViewMajor(measurements);
  decision->track_step = MedianTrackStep(measurements, tracks, 1);
  decision->track_order = TrackOrder(measurements, tracks);
  decision->video = decision->track_order >= options.min_track_order;
  NRSFM_RETURN_IF_ERROR(AnalyseTrackRank(options, measurements, num_bases,
                                         decision->video, decision,
                                         completions));
  const bool basis_absorbs_rotation =
      3.0 * num_bases >= options.min_basis_fraction * measurements.num_points;
  if (!decision->exactly_low_rank || basis_absorbs_rotation) {
    if (decision->video) {
      decision->term_weights[kTemporalShapeTerm] =
          options.temporal_shape_weight;
    } else {
      decision->term_weights[kDeformationTerm] = options.deformation_weight;
    }
  }
  if (measurements.num_cameras > 1) {
    decision->term_weights[kRigidityTerm] = options.rigidity_weight;
  }
  return Status::OK();
}

void DecideStartPriors(const PriorRuleOptions& options, const Model& start,
                       const Model& path_start, double strength,
                       PriorDecision* decision) {
  for (const char* name : {kTemporalShapeTerm, kDeformationTerm}) {
    const auto it = decision->term_weights.find(name);
    if (it != decision->term_weights.end()) it->second *= strength;
  }
  const auto temporal = decision->term_weights.find(kTemporalShapeTerm);
  if (temporal == decision->term_weights.end()) return;
  decision->deformation_coherence = DeformationCoherence(start);
  decision->temporal_shape_alternative = temporal->second;
  if (decision->deformation_coherence >= 0.0) {
    const double full = options.temporal_shape_weight;
    const double c = decision->deformation_coherence;
    decision->temporal_shape_alternative =
        strength * full *
        std::pow(options.min_temporal_shape_weight / full,
                 std::pow(1.0 - c, 4));
  }
  decision->path_acceleration_deg = PathAccelerationDeg(path_start);
  if (decision->path_acceleration_deg >= 0.0 &&
      decision->path_acceleration_deg < options.max_path_acceleration_deg) {
    decision->term_weights[kRotationAccelerationTerm] =
        options.rotation_acceleration_weight;
  }
}

double DeformationCoherence(const Model& model) {
  const int frames = model.num_frames, bases = model.num_bases;
  if (frames < 2 || bases < 1) return -1.0;
  // S_t = Σ_k l_tk S_k, so ||Σ_k a_k S_k||² = aᵀ G a with G the Gram matrix
  // of the basis shapes over the points that are defined.
  Eigen::MatrixXd basis = model.basis;
  for (int p = 0; p < model.num_points; ++p) {
    if (!basis.col(p).allFinite()) basis.col(p).setZero();
  }
  Eigen::MatrixXd gram(bases, bases);
  for (int k = 0; k < bases; ++k) {
    for (int j = 0; j <= k; ++j) {
      gram(k, j) = gram(j, k) = (basis.middleRows(3 * k, 3).array() *
                                 basis.middleRows(3 * j, 3).array())
                                    .sum();
    }
  }
  const Eigen::MatrixXd& l = model.weights;
  if (!l.allFinite()) return -1.0;
  const Eigen::VectorXd mean = l.rowwise().mean();
  double spread = 0.0, change = 0.0;
  for (int t = 0; t < frames; ++t) {
    const Eigen::VectorXd d = l.col(t) - mean;
    spread += d.dot(gram * d);
    if (t > 0) {
      const Eigen::VectorXd a = l.col(t) - l.col(t - 1);
      change += a.dot(gram * a);
    }
  }
  if (!(spread > 0.0)) return 1.0;
  const double expected = 2.0 * (frames - 1) / frames * spread;
  return std::clamp(1.0 - change / expected, 0.0, 1.0);
}

double LargestViewAngleDeg(const Model& model) {
  // The angle of R_t R_sᵀ from its trace, 1 + 2 cos θ = Σ_ij (R_t)_ij (R_s)_ij:
  // ample precision for the tens of degrees this is about, O(F²) cheap.
  std::vector<Eigen::Matrix3d> rotations(model.num_frames);
  for (int t = 0; t < model.num_frames; ++t)
    rotations[t] = model.Rotation(t, 0);
  double smallest_cosine = 1.0;
  for (int s = 0; s < model.num_frames; ++s) {
    for (int t = s + 1; t < model.num_frames; ++t) {
      const double cosine =
          0.5 * (rotations[t].cwiseProduct(rotations[s]).sum() - 1.0);
      smallest_cosine = std::min(smallest_cosine, cosine);
    }
  }
  return std::acos(std::clamp(smallest_cosine, -1.0, 1.0)) * kDegreesPerRadian;
}

}  // namespace nrsfm
