// The plots of the nrsfm_bench suites: line plots drawn by gnuplot (SVG),
// skipped with a note when plots are off or gnuplot is missing.
#ifndef NRSFM_BENCH_PLOT_H_
#define NRSFM_BENCH_PLOT_H_

#include <string>
#include <vector>

#include "bench/bench_config.h"

namespace nrsfm {
namespace bench {

// A line plot: one curve per series. Written as <output_dir>/<name>.svg
// (gnuplot, svg terminal) with its data in <name>.dat and script in <name>.gp.
struct PlotSeries {
  std::string title;
  std::vector<double> x, y;
};
struct PlotSpec {
  std::string name;  // file stem
  std::string title;
  std::string xlabel, ylabel;
  bool logx = false, logy = false;
  std::vector<PlotSeries> series;
};
// Returns the path of the plot, or "" with a one-line note on stderr when
// plots are off or gnuplot is missing or fails (never an error).
std::string WritePlot(const BenchConfig& config, const PlotSpec& spec);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_PLOT_H_
