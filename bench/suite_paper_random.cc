// paper-random suite (Torresani et al. 2001, Fig. 5 a/b): data from N = 5, 10
// and 20 random basis shapes (core/synthetic/synthetic.h GenerateRandomBasis:
// points in the unit cube, first basis dominant), F = 300, P = 100, rotations
// spanning up to 90° about each axis, Gaussian noise 0.01 (unit-cube units);
// reconstruct with K = 1 … N; median 3D error and z error (% of shape size)
// over R runs. Default: R = 1 and K in {1, N/2, N}; --full: R = 30 and every K.
#include <iostream>
#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "bench/k_sweep.h"
#include "bench/report.h"
#include "bench/suites.h"
#include "core/synthetic/synthetic.h"

namespace nrsfm {
namespace bench {
namespace {

constexpr int kFrames = 300;
constexpr int kPoints = 100;
constexpr double kNoise = 0.01;

std::vector<int> KValues(int n, bool full) {
  std::vector<int> ks;
  if (full) {
    for (int k = 1; k <= n; ++k) ks.push_back(k);
    return ks;
  }
  if (n <= 5) return {1, 3, 5};
  if (n <= 10) return {1, 5, 10};
  return {1, 10, 20};
}

}  // namespace

Status RunPaperRandomSuite(const BenchConfig& config, Json* out) {
  std::cout << "\n== paper-random: Torresani et al. 2001, Fig. 5 a/b (F = "
            << kFrames << ", P = " << kPoints << ", 90 deg, noise " << kNoise
            << ") ==\n";
  const int runs = config.runs > 0 ? config.runs : (config.full ? 30 : 1);
  Table table({"N (gen)", "K", "median 3D err %", "median z err %",
               "median e3D", "median s", "failed"});
  PlotSpec plot_3d{
      "paper_random_error3d",
      "random bases: median 3D error (Torresani et al. 2001, Fig. 5a)",
      "K",
      "3D error, % of shape size",
      false,
      true,
      {}};
  PlotSpec plot_z{
      "paper_random_zerror",
      "random bases: median z error (Torresani et al. 2001, Fig. 5b)",
      "K",
      "z error, % of shape size",
      false,
      true,
      {}};
  Json settings = Json::array();
  for (int n : {5, 10, 20}) {
    const auto make = [n](std::uint64_t seed, SyntheticSequence* sequence) {
      RandomBasisOptions options;
      options.num_frames = kFrames;
      options.num_points = kPoints;
      options.num_bases = n;
      options.max_rotation_deg = 90.0;
      options.noise_stddev = kNoise;
      options.seed = seed;
      return GenerateRandomBasis(options, sequence);
    };
    const auto options = [&config](int k) {
      return DefaultReconstructOptions(k, config.threads);
    };
    const SweepResult sweep =
        SweepK(make, KValues(n, config.full), runs, options, config.jobs);
    PlotSeries s3d{std::to_string(n) + " bases", {}, {}};
    PlotSeries sz = s3d;
    for (const SweepPoint& p : sweep.points) {
      table.AddRow({std::to_string(n), std::to_string(p.num_bases),
                    Fmt(p.median_error3d_pct, 2), Fmt(p.median_zerror_pct, 2),
                    Fmt(p.median_e3d, 4), Fmt(p.median_seconds, 2),
                    std::to_string(p.failures) + "/" + std::to_string(runs)});
      s3d.x.push_back(p.num_bases);
      s3d.y.push_back(p.median_error3d_pct);
      sz.x.push_back(p.num_bases);
      sz.y.push_back(p.median_zerror_pct);
      Json j;
      j["generating_bases"] = n;
      j["num_bases"] = p.num_bases;
      j["median_error3d_pct"] = p.median_error3d_pct;
      j["median_zerror_pct"] = p.median_zerror_pct;
      j["median_e3d"] = p.median_e3d;
      j["median_seconds"] = p.median_seconds;
      j["failures"] = p.failures;
      settings.push_back(j);
    }
    plot_3d.series.push_back(s3d);
    plot_z.series.push_back(sz);
    (*out)["runs_" + std::to_string(n)] = sweep.runs;
  }
  std::cout << "R = " << runs << " runs per setting\n" << table.ToString();
  (*out)["num_runs"] = runs;
  (*out)["frames"] = kFrames;
  (*out)["points"] = kPoints;
  (*out)["noise_stddev"] = kNoise;
  (*out)["medians"] = settings;
  for (const PlotSpec* spec : {&plot_3d, &plot_z}) {
    const std::string path = WritePlot(config, *spec);
    if (!path.empty()) (*out)["plots"].push_back(path);
  }
  return Status::OK();
}

}  // namespace bench
}  // namespace nrsfm
