// superquadric suite (Torresani et al. 2001, Fig. 5c): the octant-deforming
// superquadric (core/synthetic/synthetic.h GenerateSuperquadric, exact model K
// = 4), F = 300, P = 200 (default run: 100), rotations up to 90°, noise 0.005
// (shape ~1 across); K = 1 … 8 (default run: 1, 4, 6), median 3D and z error (%
// of shape size) over R runs (default 1, --full 30).
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

Status RunSuperquadricSuite(const BenchConfig& config, Json* out) {
  constexpr double kNoise = 0.005;
  std::cout
      << "\n== superquadric: Torresani et al. 2001, Fig. 5c (F = 300, P = "
      << (config.full ? 200 : 100) << ", 90 deg, noise " << kNoise << ") ==\n";
  const int runs = config.runs > 0 ? config.runs : (config.full ? 30 : 1);
  const std::vector<int> ks = config.full
                                  ? std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8}
                                  : std::vector<int>{1, 4, 6};
  const bool full = config.full;
  const auto make = [full](std::uint64_t seed, SyntheticSequence* sequence) {
    SuperquadricOptions options;
    options.noise_stddev = kNoise;
    options.num_points = full ? 200 : 100;
    options.seed = seed;
    return GenerateSuperquadric(options, sequence);
  };
  const auto options = [&config](int k) {
    return DefaultReconstructOptions(k, config.threads);
  };
  const SweepResult sweep = SweepK(make, ks, runs, options, config.jobs);
  Table table({"K", "median 3D err %", "median z err %", "median e3D",
               "median s", "failed"});
  PlotSpec plot{"superquadric_error",
                "superquadric: median error (Torresani et al. 2001, Fig. 5c)",
                "K",
                "% of shape size",
                false,
                false,
                {}};
  PlotSeries s3d{"3D error", {}, {}}, sz{"z error", {}, {}};
  Json medians = Json::array();
  for (const SweepPoint& p : sweep.points) {
    table.AddRow({std::to_string(p.num_bases), Fmt(p.median_error3d_pct, 2),
                  Fmt(p.median_zerror_pct, 2), Fmt(p.median_e3d, 4),
                  Fmt(p.median_seconds, 2),
                  std::to_string(p.failures) + "/" + std::to_string(runs)});
    s3d.x.push_back(p.num_bases);
    s3d.y.push_back(p.median_error3d_pct);
    sz.x.push_back(p.num_bases);
    sz.y.push_back(p.median_zerror_pct);
    medians.push_back({{"num_bases", p.num_bases},
                       {"median_error3d_pct", p.median_error3d_pct},
                       {"median_zerror_pct", p.median_zerror_pct},
                       {"median_e3d", p.median_e3d},
                       {"median_seconds", p.median_seconds},
                       {"failures", p.failures}});
  }
  plot.series = {s3d, sz};
  std::cout << "R = " << runs << " runs per setting\n" << table.ToString();
  (*out)["num_runs"] = runs;
  (*out)["noise_stddev"] = kNoise;
  (*out)["medians"] = medians;
  (*out)["runs"] = sweep.runs;
  const std::string path = WritePlot(config, plot);
  if (!path.empty()) (*out)["plots"].push_back(path);
  return Status::OK();
}

}  // namespace bench
}  // namespace nrsfm
