#include "bench/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

}  // namespace bench
}  // namespace nrsfm
