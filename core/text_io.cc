#include "core/text_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <new>
#include <string_view>
#include <system_error>

namespace nrsfm {
namespace {

// Largest W (entries) an observation list may imply: 2^28 doubles = 2 GiB.
constexpr std::int64_t kMaxListEntries = std::int64_t(1) << 28;

Status OpenTextFile(const std::string& path, std::ifstream* in) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status))
    return Status::Error(path + ": no such file");
  if (std::filesystem::is_directory(status)) {
    return Status::Error(path + ": is a directory, not a text file");
  }
  in->open(path);
  if (!*in) return Status::Error(path + ": cannot open the file for reading");
  return Status::OK();
}

std::string Where(const std::string& path, int line) {
  return path + ": line " + std::to_string(line);
}

// Reads the next line that holds data (comment stripped); false at the end.
bool NextDataLine(std::ifstream* in, int* line_number, std::string* line) {
  while (std::getline(*in, *line)) {
    ++*line_number;
    const std::size_t hash = line->find('#');
    if (hash != std::string::npos) line->resize(hash);
    if (!line->empty() && line->back() == '\r') line->pop_back();
    for (char c : *line) {
      if (!std::isspace(static_cast<unsigned char>(c))) return true;
    }
  }
  return false;
}

// Splits `line` into fields separated by whitespace and/or single commas.
Status SplitFields(const std::string& line, const std::string& where,
                   std::vector<std::string_view>* fields) {
  fields->clear();
  const std::size_t n = line.size();
  std::size_t i = 0;
  auto skip_space = [&]() {
    while (i < n && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
  };
  skip_space();
  if (i == n) return Status::OK();
  while (true) {
    if (i == n || line[i] == ',') {
      return Status::Error(where + ", column " +
                           std::to_string(fields->size() + 1) +
                           ": empty field");
    }
    const std::size_t start = i;
    while (i < n && line[i] != ',' &&
           !std::isspace(static_cast<unsigned char>(line[i])))
      ++i;
    fields->push_back(std::string_view(line).substr(start, i - start));
    skip_space();
    if (i == n) return Status::OK();
    if (line[i] == ',') {
      ++i;
      skip_space();
    }
  }
}

// Parses a whole field as a double (NaN allowed, ±Inf rejected).
Status ParseNumber(std::string_view field, const std::string& where, int column,
                   double* value) {
  std::string_view text = field;
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  const std::from_chars_result result =
      std::from_chars(text.data(), end, *value);
  const std::string at = where + ", column " + std::to_string(column);
  if (text.empty() || result.ec == std::errc::invalid_argument ||
      result.ptr != end) {
    return Status::Error(at + ": '" + std::string(field) + "' is not a number");
  }
  if (result.ec == std::errc::result_out_of_range) {
    return Status::Error(at + ": '" + std::string(field) +
                         "' is out of the range of double");
  }
  if (std::isinf(*value)) {
    return Status::Error(at + ": infinite value '" + std::string(field) +
                         "'; use NaN to mark a missing value");
  }
  return Status::OK();
}

Status ParseRow(const std::string& line, const std::string& where,
                std::vector<std::string_view>* fields,
                std::vector<double>* values) {
  NRSFM_RETURN_IF_ERROR(SplitFields(line, where, fields));
  values->resize(fields->size());
  for (std::size_t j = 0; j < fields->size(); ++j) {
    NRSFM_RETURN_IF_ERROR(ParseNumber((*fields)[j], where,
                                      static_cast<int>(j) + 1, &(*values)[j]));
  }
  return Status::OK();
}

// Reads numeric rows of `num_columns` fields (the first row sets it when
// num_columns < 0) until the end of the file; no row at all is the error
// "<path>: <no_rows>".
Status ReadRows(const std::string& path, std::ifstream* in, int* line_number,
                int num_columns, const char* no_rows, Eigen::MatrixXd* matrix) {
  std::vector<double> values;  // row-major
  std::vector<std::string_view> fields;
  std::vector<double> row;
  std::string line;
  int first_line = 0;
  Eigen::Index rows = 0;
  while (NextDataLine(in, line_number, &line)) {
    const std::string where = Where(path, *line_number);
    NRSFM_RETURN_IF_ERROR(ParseRow(line, where, &fields, &row));
    if (num_columns < 0) {
      num_columns = static_cast<int>(row.size());
      first_line = *line_number;
    }
    if (static_cast<int>(row.size()) != num_columns) {
      std::string expected = "expected " + std::to_string(num_columns);
      if (first_line > 0)
        expected += " as on line " + std::to_string(first_line);
      return Status::Error(where + " has " + std::to_string(row.size()) +
                           " values, " + expected);
    }
    values.insert(values.end(), row.begin(), row.end());
    ++rows;
  }
  if (in->bad()) return Status::Error(path + ": read error");
  if (rows == 0) return Status::Error(path + ": " + no_rows);
  *matrix = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic,
                                           Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), rows, num_columns);
  return Status::OK();
}

// Index field of an observation list: an integral, non-negative number.
Status ParseIndex(std::string_view field, const std::string& where, int column,
                  const char* name, std::int64_t* index) {
  double value = 0.0;
  NRSFM_RETURN_IF_ERROR(ParseNumber(field, where, column, &value));
  const std::string at = where + ", column " + std::to_string(column) + ": " +
                         name + " index '" + std::string(field) + "'";
  if (std::isnan(value) || value != std::floor(value)) {
    return Status::Error(at + " is not an integer");
  }
  if (value < 0) return Status::Error(at + " is negative");
  if (value >= 2147483647.0) return Status::Error(at + " is too large");
  *index = static_cast<std::int64_t>(value);
  return Status::OK();
}

// Closes `file` and reports a write error on `path`.
Status FinishWrite(const std::string& path, std::FILE* file) {
  const bool failed = std::ferror(file) != 0;
  const bool close_failed = std::fclose(file) != 0;
  if (failed || close_failed)
    return Status::Error(path + ": error while writing the file");
  return Status::OK();
}

void WriteNumber(std::FILE* file, double value) {
  if (std::isnan(value)) {
    std::fputs("NaN", file);
  } else {
    std::fprintf(file, "%.17g", value);
  }
}

}  // namespace

Status ReadTextMatrix(const std::string& path, Eigen::MatrixXd* matrix) {
  std::ifstream in;
  NRSFM_RETURN_IF_ERROR(OpenTextFile(path, &in));
  int line_number = 0;
  return ReadRows(path, &in, &line_number, /*num_columns=*/-1,
                  "no numbers in the file", matrix);
}

Status WriteTextMatrix(const std::string& path, const Eigen::MatrixXd& matrix) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) return Status::Error(path + ": cannot create the file");
  for (Eigen::Index i = 0; i < matrix.rows(); ++i) {
    for (Eigen::Index j = 0; j < matrix.cols(); ++j) {
      if (j > 0) std::fputc(' ', file);
      WriteNumber(file, matrix(i, j));
    }
    std::fputc('\n', file);
  }
  return FinishWrite(path, file);
}

Status ReadCsvTable(const std::string& path,
                    const std::vector<std::string>& header,
                    Eigen::MatrixXd* table) {
  std::ifstream in;
  NRSFM_RETURN_IF_ERROR(OpenTextFile(path, &in));
  std::string expected;
  for (const std::string& name : header)
    expected += (expected.empty() ? "" : ",") + name;
  int line_number = 0;
  std::string line;
  if (!NextDataLine(&in, &line_number, &line)) {
    return Status::Error(path + ": empty file; expected the header " +
                         expected);
  }
  std::vector<std::string_view> fields;
  NRSFM_RETURN_IF_ERROR(SplitFields(line, Where(path, line_number), &fields));
  bool header_ok = fields.size() == header.size();
  for (std::size_t j = 0; header_ok && j < header.size(); ++j) {
    header_ok = fields[j] == header[j];
  }
  if (!header_ok) {
    return Status::Error(Where(path, line_number) + ": expected the header " +
                         expected);
  }
  return ReadRows(path, &in, &line_number, static_cast<int>(header.size()),
                  "no data rows after the header", table);
}

Status ReadObservationList(const std::string& path,
                           Measurements* measurements) {
  std::ifstream in;
  NRSFM_RETURN_IF_ERROR(OpenTextFile(path, &in));
  struct Observation {
    std::int64_t frame, camera, point;
    double u, v;
    int line;
  };
  std::vector<Observation> observations;
  std::vector<std::string_view> fields;
  std::string line;
  int line_number = 0;
  std::int64_t num_frames = 0, num_cameras = 0, num_points = 0;
  while (NextDataLine(&in, &line_number, &line)) {
    const std::string where = Where(path, line_number);
    NRSFM_RETURN_IF_ERROR(SplitFields(line, where, &fields));
    if (fields.size() != 5) {
      return Status::Error(where + " has " + std::to_string(fields.size()) +
                           " fields; expected 5: frame camera point u v");
    }
    Observation o;
    o.line = line_number;
    NRSFM_RETURN_IF_ERROR(ParseIndex(fields[0], where, 1, "frame", &o.frame));
    NRSFM_RETURN_IF_ERROR(ParseIndex(fields[1], where, 2, "camera", &o.camera));
    NRSFM_RETURN_IF_ERROR(ParseIndex(fields[2], where, 3, "point", &o.point));
    NRSFM_RETURN_IF_ERROR(ParseNumber(fields[3], where, 4, &o.u));
    NRSFM_RETURN_IF_ERROR(ParseNumber(fields[4], where, 5, &o.v));
    if (std::isnan(o.u) || std::isnan(o.v)) {
      return Status::Error(where +
                           ": u and v must be numbers (leave a missing "
                           "observation out of the list instead of NaN)");
    }
    num_frames = std::max(num_frames, o.frame + 1);
    num_cameras = std::max(num_cameras, o.camera + 1);
    num_points = std::max(num_points, o.point + 1);
    observations.push_back(o);
  }
  if (in.bad()) return Status::Error(path + ": read error");
  if (observations.empty())
    return Status::Error(path + ": no observations in the file");
  // Each factor is < 2^31, so the first product cannot overflow int64.
  const std::int64_t views = num_frames * num_cameras;
  if (views > kMaxListEntries || 2 * views * num_points > kMaxListEntries) {
    return Status::Error(
        path + ": the largest indices (F = " + std::to_string(num_frames) +
        ", M = " + std::to_string(num_cameras) + ", P = " +
        std::to_string(num_points) + ") imply a W larger than 2^28 entries");
  }

  Measurements m;
  m.num_frames = static_cast<int>(num_frames);
  m.num_cameras = static_cast<int>(num_cameras);
  m.num_points = static_cast<int>(num_points);
  Eigen::MatrixXi first_line;
  // The dense W of a sparse list can be far larger than the file (one line
  // may imply gigabytes): memory it cannot get is the file's error.
  try {
    m.W.setConstant(2 * m.NumViews(), m.num_points, std::nan(""));
    m.visible.setConstant(m.NumViews(), m.num_points, false);
    first_line.setZero(m.NumViews(), m.num_points);
  } catch (const std::bad_alloc&) {
    return Status::Error(
        path + ": the largest indices (F = " + std::to_string(num_frames) +
        ", M = " + std::to_string(num_cameras) +
        ", P = " + std::to_string(num_points) + ") imply a W of " +
        std::to_string(2 * views * num_points) +
        " entries, more than can be allocated");
  }
  for (const Observation& o : observations) {
    const int view =
        m.View(static_cast<int>(o.frame), static_cast<int>(o.camera));
    const int p = static_cast<int>(o.point);
    if (first_line(view, p) != 0) {
      return Status::Error(
          Where(path, o.line) + ": frame " + std::to_string(o.frame) +
          ", camera " + std::to_string(o.camera) + ", point " +
          std::to_string(o.point) + " was already given on line " +
          std::to_string(first_line(view, p)));
    }
    first_line(view, p) = o.line;
    m.W(2 * view, p) = o.u;
    m.W(2 * view + 1, p) = o.v;
    m.visible(view, p) = true;
  }
  *measurements = std::move(m);
  return Status::OK();
}

Status WriteObservationList(const std::string& path,
                            const Measurements& measurements) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) return Status::Error(path + ": cannot create the file");
  std::fputs("# frame camera point u v\n", file);
  for (int t = 0; t < measurements.num_frames; ++t) {
    for (int c = 0; c < measurements.num_cameras; ++c) {
      const int view = measurements.View(t, c);
      for (int p = 0; p < measurements.num_points; ++p) {
        if (!measurements.visible(view, p)) continue;
        std::fprintf(file, "%d %d %d %.17g %.17g\n", t, c, p,
                     measurements.W(2 * view, p),
                     measurements.W(2 * view + 1, p));
      }
    }
  }
  return FinishWrite(path, file);
}

}  // namespace nrsfm
