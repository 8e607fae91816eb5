// How the nrsfm_bench suites report: statistics and numbers for the stdout
// tables, the tables themselves, the metrics of a run as JSON fields, the
// JSON file, and the line plots drawn by gnuplot (SVG), skipped with a note
// when plots are off or gnuplot is missing.
#ifndef NRSFM_BENCH_REPORT_H_
#define NRSFM_BENCH_REPORT_H_

#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "core/eval/metrics.h"

namespace nrsfm {
namespace bench {

double Median(std::vector<double> values);  // NaN when empty

// Fixed-precision number ("nan" for NaN).
std::string Fmt(double value, int precision = 3);

// A plain-text table with right-aligned columns.
class Table {
 public:
  explicit Table(std::vector<std::string> headers);
  void AddRow(std::vector<std::string> cells);
  std::string ToString() const;

 private:
  std::vector<std::string> headers_;
  std::vector<std::vector<std::string>> rows_;
};

// Sets (*j)[name] = value for every metric of `errors` (MetricList,
// core/eval/metrics.h: the names result.json and `nrsfm evaluate` use).
void AddMetrics(const ShapeErrors& errors, Json* j);

// Writes `json` to <output_dir>/<file>; returns the path or "" on failure
// (with a note on stderr).
std::string WriteJson(const BenchConfig& config, const std::string& file,
                      const Json& json);

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

#endif  // NRSFM_BENCH_REPORT_H_
