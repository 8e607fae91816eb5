// shoe suite (Torresani et al. 2001, Table 1 style): the shoe-style sequence of
// core/synthetic/synthetic.h (GenerateShoe: F = 500, P = 110, exact K = 4, yaw
// span 120°, self-occlusion ~15 % of the entries), noise 0.002 (shoe length 1).
// K = 2, 4 (--full: 2 … 8; the default run of every suite: K = 4 only): 3D
// and z error (% of shape size), camera 0, with the --max_seconds cap, for
//   monocular   camera 0's tracks alone;
//   two cameras both views, shared weights;
// each with the manual setting of the seed (priors = manual, the smoothness
// term kShoeSmoothnessWeight, and for two cameras the rigidity term of
// EnableTwoCameraRigidity(), bench_config.h) and with the default pipeline
// (priors = auto, nothing set: what `nrsfm reconstruct --K N` does).
// Median over R runs (default 1 as in the paper's Table 1, --full 5).
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "bench/k_sweep.h"
#include "bench/report.h"
#include "bench/suites.h"
#include "core/math/parallel_for.h"
#include "core/synthetic/synthetic.h"
#include "problems/extra_terms.h"

namespace nrsfm {
namespace bench {

// The Delaunay-neighbour smoothness term (problems/smoothness_error.h) ties
// each point to its image-plane neighbours, which is what carries the points
// hidden by self-occlusion; 0.01 is the weight its tests were written with
// (tests/solvers/extra_terms_test.cc, a point seen in 2 of 40 frames), not
// tuned on this suite.
constexpr double kShoeSmoothnessWeight = 0.01;

Status RunShoeSuite(const BenchConfig& config, Json* out) {
  constexpr double kNoise = 0.002;
  std::cout << "\n== shoe: Torresani et al. 2001, Table 1 style (F = 500, P = "
               "110, self-occlusion, "
               "noise "
            << kNoise << ", smoothness " << kShoeSmoothnessWeight << ") ==\n";
  const int runs = config.runs > 0 ? config.runs : (config.full ? 5 : 1);
  // Default run: the exact K only (--suite=shoe alone adds K = 2).
  const std::vector<int> ks =
      config.full
          ? std::vector<int>{2, 3, 4, 5, 6, 7, 8}
          : (config.quick ? std::vector<int>{4} : std::vector<int>{2, 4});
  ReconstructOptions probe;
  const bool rigidity = EnableTwoCameraRigidity(&probe);
  const std::string two_label =
      rigidity ? "2 cams + rigidity" : "2 cams, NO rigidity";

  // Four sweeps: index = 2 · (default pipeline) + (cameras − 1); two run
  // side by side (--jobs; core/math/parallel_for.h runs a sweep's own loop
  // inside this one on its calling thread, so at most two reconstructions run
  // at once here).
  std::vector<SweepResult> results(4);
  ParallelFor(4, config.jobs, /*grain=*/1, [&](int begin, int end) {
    for (int index = begin; index < end; ++index) {
      const int cameras = index % 2 + 1;
      const bool manual = index < 2;
      const auto make = [cameras](std::uint64_t seed,
                                  SyntheticSequence* sequence) {
        ShoeOptions options;
        options.num_cameras = cameras;
        options.noise_stddev = kNoise;
        options.seed = seed;
        return GenerateShoe(options, sequence);
      };
      const auto options = [&config, cameras, manual](int k) {
        ReconstructOptions o = DefaultReconstructOptions(k, config.threads);
        o.solver.max_seconds = config.max_seconds;
        if (!manual) return o;
        o.priors = PriorMode::kManual;
        o.problem.term_weights[kSmoothnessTerm] = kShoeSmoothnessWeight;
        if (cameras == 2) EnableTwoCameraRigidity(&o);
        return o;
      };
      results[index] =
          SweepK(make, ks, runs, options, std::max(1, config.jobs / 2));
    }
  });
  Json sweeps;
  sweeps["monocular"] = results[0].runs;
  sweeps["two_cameras"] = results[1].runs;
  sweeps["monocular_default"] = results[2].runs;
  sweeps["two_cameras_default"] = results[3].runs;
  // Fraction of hidden entries of the first run's data.
  SyntheticSequence first;
  ShoeOptions first_options;
  first_options.num_cameras = 1;
  first_options.noise_stddev = kNoise;
  double missing = 0;
  if (GenerateShoe(first_options, &first).ok()) {
    const auto& m = first.measurements;
    missing = 1.0 - static_cast<double>(m.NumVisible()) /
                        (static_cast<double>(m.NumViews()) * m.num_points);
  }

  Table table({"K", "mono 3D %", "mono z %", "mono default 3D %",
               two_label + " 3D %", two_label + " z %", "2-cam default 3D %",
               "mono s", "mono default s", "2-cam s", "2-cam default s"});
  PlotSpec plot{"shoe_error",
                "shoe: 3D error vs K (Table 1 style)",
                "K",
                "% of shape size",
                false,
                false,
                {}};
  PlotSeries mono{"monocular 3D", {}, {}}, mono_z{"monocular z", {}, {}},
      two{two_label + " 3D", {}, {}},
      mono_default{"monocular default 3D", {}, {}},
      two_default{"2 cams default 3D", {}, {}};
  Json medians = Json::array();
  for (size_t i = 0; i < ks.size(); ++i) {
    const SweepPoint& m = results[0].points[i];
    const SweepPoint& b = results[1].points[i];
    const SweepPoint& md = results[2].points[i];
    const SweepPoint& bd = results[3].points[i];
    const auto error = [runs](const SweepPoint& p) {
      return p.failures == runs ? std::string("FAIL")
                                : Fmt(p.median_error3d_pct, 2);
    };
    table.AddRow({std::to_string(ks[i]), error(m), Fmt(m.median_zerror_pct, 2),
                  error(md), error(b), Fmt(b.median_zerror_pct, 2), error(bd),
                  Fmt(m.median_seconds, 2), Fmt(md.median_seconds, 2),
                  Fmt(b.median_seconds, 2), Fmt(bd.median_seconds, 2)});
    mono.x.push_back(ks[i]);
    mono.y.push_back(m.median_error3d_pct);
    mono_z.x.push_back(ks[i]);
    mono_z.y.push_back(m.median_zerror_pct);
    two.x.push_back(ks[i]);
    two.y.push_back(b.median_error3d_pct);
    mono_default.x.push_back(ks[i]);
    mono_default.y.push_back(md.median_error3d_pct);
    two_default.x.push_back(ks[i]);
    two_default.y.push_back(bd.median_error3d_pct);
    medians.push_back({{"num_bases", ks[i]},
                       {"mono_error3d_pct", m.median_error3d_pct},
                       {"mono_zerror_pct", m.median_zerror_pct},
                       {"mono_failures", m.failures},
                       {"two_error3d_pct", b.median_error3d_pct},
                       {"two_zerror_pct", b.median_zerror_pct},
                       {"two_failures", b.failures},
                       {"mono_seconds", m.median_seconds},
                       {"two_seconds", b.median_seconds},
                       {"mono_default_error3d_pct", md.median_error3d_pct},
                       {"mono_default_failures", md.failures},
                       {"mono_default_seconds", md.median_seconds},
                       {"two_default_error3d_pct", bd.median_error3d_pct},
                       {"two_default_failures", bd.failures},
                       {"two_default_seconds", bd.median_seconds}});
  }
  plot.series = {mono, mono_z, two, mono_default, two_default};
  std::cout << "R = " << runs << " run(s) per setting; camera 0 hides "
            << Fmt(100.0 * missing, 1) << " % of its entries (seed 1)\n"
            << table.ToString();
  if (config.max_seconds > 0) {
    std::cout << "(each refinement capped at " << config.max_seconds
              << " s wall time, --max_seconds; 0 removes the cap)\n";
  }
  (*out)["refine_max_seconds"] = config.max_seconds;
  (*out)["num_runs"] = runs;
  (*out)["noise_stddev"] = kNoise;
  (*out)["missing_fraction_camera0_seed1"] = missing;
  (*out)["two_camera_rigidity"] = rigidity;
  (*out)["medians"] = medians;
  (*out)["runs"] = sweeps;
  const std::string path = WritePlot(config, plot);
  if (!path.empty()) (*out)["plots"].push_back(path);
  return Status::OK();
}

}  // namespace bench
}  // namespace nrsfm
