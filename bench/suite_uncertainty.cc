// uncertainty suite (docs/uncertainty.md): the per-point covariances of
// --uncertainty (solvers/pipeline/result_uncertainty.h) against the truth,
// each sequence reconstructed by the default pipeline at its true K.
//   calibration: random bases (F 100, P 40, K 3, 10 % missing) and the shoe
//     (F 500, P 110, K 4, monocular, self-occlusion ~15 %) with Gaussian noise
//     of 0.2, 1 and 3 % of the shape's extent (the largest side of the
//     truth's bounding box, median over frames; the shoe: its length 1),
//     seeds 1 … R (default 3, --full 10): the fraction of true points inside
//     their 95 % ellipsoid after the e3D alignment (core/eval/
//     uncertainty_metrics.h; 0.95 when right), the mean Mahalanobis² (3);
//   ranking: the real sequences of --datasets_dir at their published K, and
//     each re-projected over a slow 30° orbit (GenerateReprojection): the
//     Spearman correlation of each point's predicted std with its actual
//     error, and the predicted against the actual median;
// the time of the reconstruction and of the uncertainty.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "bench/mocap_data.h"
#include "bench/report.h"
#include "bench/suites.h"
#include "core/eval/metrics.h"
#include "core/eval/uncertainty_metrics.h"
#include "core/synthetic/synthetic.h"
#include "solvers/pipeline/reconstruct.h"
#include "solvers/pipeline/result_uncertainty.h"

namespace nrsfm {
namespace bench {
namespace {

struct Scored {
  Status status;
  UncertaintyCalibration score;
  double e3d = 0, reconstruct_seconds = 0, uncertainty_seconds = 0;
  double noise_std = 0;  // σ̂
  bool little_rotation_warning = false;
};

Scored ReconstructAndScore(const Measurements& measurements,
                           const std::vector<Eigen::Matrix3Xd>& truth, int k,
                           int threads) {
  Scored scored;
  const ReconstructOptions options = DefaultReconstructOptions(k, threads);
  ReconstructResult result;
  scored.status = Reconstruct(options, measurements, &result);
  if (!scored.status.ok()) return scored;
  scored.reconstruct_seconds = result.total_seconds;
  Uncertainty uncertainty;
  scored.status = ComputeResultUncertainty(UncertaintyOptions(), options,
                                           measurements, result, &uncertainty);
  if (!scored.status.ok()) return scored;
  scored.uncertainty_seconds = uncertainty.seconds;
  scored.noise_std = uncertainty.noise_std;
  const std::vector<Eigen::Matrix3Xd> estimate =
      CameraFrameShapes(result.model);
  scored.e3d = ComputeE3D(truth, estimate);
  // Camera 0's covariances, frame by frame.
  const int F = measurements.num_frames, M = measurements.num_cameras,
            P = measurements.num_points;
  std::vector<Eigen::Matrix3d> camera0;
  for (int t = 0; t < F; ++t) {
    for (int p = 0; p < P; ++p) {
      camera0.push_back(uncertainty.points[static_cast<size_t>(t) * M * P + p]);
    }
  }
  scored.score = ScoreUncertainty(truth, estimate, camera0);
  for (const std::string& w : result.warnings) {
    if (w.find("rotation") != std::string::npos) {
      scored.little_rotation_warning = true;
    }
  }
  return scored;
}

double Extent(const std::vector<Eigen::Matrix3Xd>& truth) {
  std::vector<double> sides;
  for (const auto& x : truth) {
    sides.push_back(
        (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).maxCoeff());
  }
  return Median(sides);
}

}  // namespace

Status RunUncertaintySuite(const BenchConfig& config, Json* out) {
  std::cout << "\n== uncertainty: calibration of the per-point covariances "
               "(default pipeline, true K) ==\n";
  const int runs = config.runs > 0 ? config.runs : (config.full ? 10 : 3);
  const std::vector<double> noises = {0.002, 0.01, 0.03};
  Table table({"data", "noise %", "runs", "inside 95 % (median)", "min", "max",
               "mean m²", "Spearman", "e3D", "σ̂/σ", "rec s", "unc s"});
  Json calibration = Json::array();
  for (const std::string data : {"random", "shoe"}) {
    for (double noise : noises) {
      std::vector<double> inside, m2, spearman, e3d, ratio, rec, unc;
      int failures = 0;
      for (int seed = 1; seed <= runs; ++seed) {
        SyntheticSequence sequence;
        double sigma = 0;
        int k = 0;
        if (data == "random") {
          RandomBasisOptions o;
          o.num_frames = 100;
          o.num_points = 40;
          o.num_bases = k = 3;
          o.missing_fraction = 0.1;
          o.seed = seed;
          SyntheticSequence clean;
          NRSFM_RETURN_IF_ERROR(GenerateRandomBasis(o, &clean));
          sigma = o.noise_stddev =
              noise * Extent(CameraFrameShapes(clean.truth));
          NRSFM_RETURN_IF_ERROR(GenerateRandomBasis(o, &sequence));
        } else {
          ShoeOptions o;
          o.num_cameras = 1;
          o.seed = seed;
          sigma = o.noise_stddev = noise;  // the shoe's length is 1
          k = 4;
          NRSFM_RETURN_IF_ERROR(GenerateShoe(o, &sequence));
        }
        const Scored s = ReconstructAndScore(sequence.measurements,
                                             CameraFrameShapes(sequence.truth),
                                             k, config.threads);
        Json row = {{"data", data}, {"noise_fraction", noise}, {"seed", seed}};
        if (!s.status.ok()) {
          ++failures;
          row["error"] = s.status.message();
          std::cout << data << " noise " << noise << " seed " << seed << ": "
                    << s.status.message() << "\n";
          calibration.push_back(row);
          continue;
        }
        inside.push_back(s.score.inside_95);
        m2.push_back(s.score.mean_mahalanobis_squared);
        spearman.push_back(s.score.spearman_per_entry);
        e3d.push_back(s.e3d);
        ratio.push_back(s.noise_std / sigma);
        rec.push_back(s.reconstruct_seconds);
        unc.push_back(s.uncertainty_seconds);
        row["inside_95"] = s.score.inside_95;
        row["mean_mahalanobis_squared"] = s.score.mean_mahalanobis_squared;
        row["spearman_per_entry"] = s.score.spearman_per_entry;
        row["e3d_camera"] = s.e3d;
        row["noise_std_ratio"] = s.noise_std / sigma;
        row["reconstruct_seconds"] = s.reconstruct_seconds;
        row["uncertainty_seconds"] = s.uncertainty_seconds;
        calibration.push_back(row);
      }
      const auto lo = [](const std::vector<double>& v) {
        return v.empty() ? NAN : *std::min_element(v.begin(), v.end());
      };
      const auto hi = [](const std::vector<double>& v) {
        return v.empty() ? NAN : *std::max_element(v.begin(), v.end());
      };
      table.AddRow(
          {data, Fmt(100 * noise, 1),
           std::to_string(runs - failures) + "/" + std::to_string(runs),
           Fmt(Median(inside), 3), Fmt(lo(inside), 3), Fmt(hi(inside), 3),
           Fmt(Median(m2), 2), Fmt(Median(spearman), 2), Fmt(Median(e3d), 4),
           Fmt(Median(ratio), 3), Fmt(Median(rec), 2), Fmt(Median(unc), 2)});
    }
  }
  std::cout << table.ToString();
  (*out)["calibration"] = calibration;

  // Ranking on the real sequences and their slow orbit.
  std::vector<MocapSequence> sequences;
  std::string why;
  if (!LoadMocapSequences(config, &sequences, &why)) {
    std::cout << "ranking: skipped (" << why << ")\n";
    (*out)["ranking"] = {{"skipped", why}};
    return Status::OK();
  }
  Table ranking({"sequence", "K", "path", "Spearman per point",
                 "Spearman per entry", "predicted median", "actual median",
                 "inside 95 %", "warning", "rec s", "unc s"});
  Json ranks = Json::array();
  for (const MocapSequence& sequence : sequences) {
    const int k = PublishedNumBases(sequence.name);
    for (const std::string path : {"original", "orbit30"}) {
      Measurements measurements = sequence.measurements;
      std::vector<Eigen::Matrix3Xd> truth = sequence.truth.points_in_camera;
      if (path == "orbit30") {
        ReprojectOptions o;
        o.total_rotation_deg = 30;
        ReprojectedSequence reprojected;
        if (!GenerateReprojection(sequence.truth, o, &reprojected).ok()) {
          continue;
        }
        measurements = reprojected.measurements;
        truth = reprojected.truth.points_in_camera;
      }
      const Scored s =
          ReconstructAndScore(measurements, truth, k, config.threads);
      Json row = {{"sequence", sequence.name}, {"K", k}, {"path", path}};
      if (!s.status.ok()) {
        row["error"] = s.status.message();
        ranking.AddRow({sequence.name, std::to_string(k), path,
                        "error: " + s.status.message()});
        ranks.push_back(row);
        continue;
      }
      row["spearman_per_point"] = s.score.spearman_per_point;
      row["spearman_per_entry"] = s.score.spearman_per_entry;
      row["median_predicted"] = s.score.median_predicted;
      row["median_actual"] = s.score.median_actual;
      row["inside_95"] = s.score.inside_95;
      row["little_rotation_warning"] = s.little_rotation_warning;
      row["reconstruct_seconds"] = s.reconstruct_seconds;
      row["uncertainty_seconds"] = s.uncertainty_seconds;
      ranks.push_back(row);
      ranking.AddRow(
          {sequence.name, std::to_string(k), path,
           Fmt(s.score.spearman_per_point, 2),
           Fmt(s.score.spearman_per_entry, 2), Fmt(s.score.median_predicted, 4),
           Fmt(s.score.median_actual, 4), Fmt(s.score.inside_95, 3),
           s.little_rotation_warning ? "yes" : "no",
           Fmt(s.reconstruct_seconds, 2), Fmt(s.uncertainty_seconds, 2)});
    }
  }
  std::cout << ranking.ToString();
  (*out)["ranking"] = ranks;
  return Status::OK();
}

}  // namespace bench
}  // namespace nrsfm
