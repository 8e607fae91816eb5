#include "bench/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <utility>

namespace nrsfm {
namespace bench {

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string Fmt(double value, int precision) {
  if (std::isnan(value)) return "nan";
  std::ostringstream out;
  out << std::fixed << std::setprecision(precision) << value;
  return out.str();
}

Table::Table(std::vector<std::string> headers) : headers_(std::move(headers)) {}

void Table::AddRow(std::vector<std::string> cells) {
  cells.resize(headers_.size());
  rows_.push_back(std::move(cells));
}

std::string Table::ToString() const {
  std::vector<size_t> widths(headers_.size());
  for (size_t c = 0; c < headers_.size(); ++c) {
    widths[c] = headers_[c].size();
    for (const auto& row : rows_)
      widths[c] = std::max(widths[c], row[c].size());
  }
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& cells) {
    for (size_t c = 0; c < cells.size(); ++c) {
      out << (c == 0 ? "" : "  ") << std::setw(static_cast<int>(widths[c]))
          << cells[c];
    }
    out << "\n";
  };
  line(headers_);
  size_t total = 0;
  for (size_t w : widths) total += w + 2;
  out << std::string(total > 2 ? total - 2 : 0, '-') << "\n";
  for (const auto& row : rows_) line(row);
  return out.str();
}

void AddMetrics(const ShapeErrors& errors, Json* j) {
  for (const auto& [name, value] : MetricList(errors)) (*j)[name] = value;
}

std::string WriteJson(const BenchConfig& config, const std::string& file,
                      const Json& json) {
  const std::string path =
      (std::filesystem::path(config.output_dir) / file).string();
  std::ofstream out(path);
  if (!out) {
    std::fprintf(stderr, "note: cannot write %s\n", path.c_str());
    return "";
  }
  out << json.dump(2) << "\n";
  return path;
}

std::string WritePlot(const BenchConfig& config, const PlotSpec& spec) {
  if (!config.plots) return "";
  static int gnuplot_state = -1;  // -1 unknown, 0 missing, 1 present
  if (gnuplot_state < 0) {
    gnuplot_state =
        std::system("command -v gnuplot > /dev/null 2>&1") == 0 ? 1 : 0;
    if (gnuplot_state == 0) {
      std::fprintf(stderr,
                   "note: gnuplot not found; plots skipped "
                   "(apt-get install gnuplot-nox)\n");
    }
  }
  if (gnuplot_state == 0) return "";
  namespace fs = std::filesystem;
  const fs::path dir(config.output_dir);
  const std::string data = (dir / (spec.name + ".dat")).string();
  const std::string script = (dir / (spec.name + ".gp")).string();
  const std::string image = (dir / (spec.name + ".svg")).string();
  {
    std::ofstream out(data);
    for (size_t s = 0; s < spec.series.size(); ++s) {
      out << "# " << spec.series[s].title << "\n";
      for (size_t i = 0; i < spec.series[s].x.size(); ++i) {
        out << spec.series[s].x[i] << " " << spec.series[s].y[i] << "\n";
      }
      out << "\n\n";
    }
  }
  {
    std::ofstream out(script);
    out << "set terminal svg size 720,480 dynamic enhanced font 'sans,12'\n"
        << "set output '" << image << "'\n"
        << "set title '" << spec.title << "' noenhanced\n"
        << "set xlabel '" << spec.xlabel << "' noenhanced\n"
        << "set ylabel '" << spec.ylabel << "' noenhanced\n"
        << "set grid\nset key top right noenhanced\n";
    if (spec.logx) out << "set logscale x\n";
    if (spec.logy) out << "set logscale y\n";
    out << "plot ";
    for (size_t s = 0; s < spec.series.size(); ++s) {
      out << (s == 0 ? "" : ", ") << "'" << data << "' index " << s
          << " using 1:2 with linespoints title '" << spec.series[s].title
          << "'";
    }
    out << "\n";
  }
  const std::string command = "gnuplot '" + script + "' > /dev/null 2>&1";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "note: gnuplot failed on %s; plot skipped\n",
                 script.c_str());
    return "";
  }
  return image;
}

}  // namespace bench
}  // namespace nrsfm
