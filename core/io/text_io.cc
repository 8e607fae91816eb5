#include "core/io/text_io.h"

#include <glog/logging.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>
#include <system_error>
#include <tuple>
#include <vector>

#include "core/io/input_budget.h"

namespace nrsfm {
namespace {

// TextWriter's buffer: written out when it holds this much.
constexpr std::size_t kBufferBytes = 1 << 20;

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
                  const char* name, int* index) {
  double value = 0.0;
  NRSFM_RETURN_IF_ERROR(ParseNumber(field, where, column, &value));
  const std::string at = where + ", column " + std::to_string(column) + ": " +
                         name + " index '" + std::string(field) + "'";
  if (std::isnan(value) || value != std::floor(value)) {
    return Status::Error(at + " is not an integer");
  }
  if (value < 0) return Status::Error(at + " is negative");
  if (value >= 2147483647.0) return Status::Error(at + " is too large");
  *index = static_cast<int>(value);
  return Status::OK();
}

// One line of an observation list.
struct Observation {
  int frame, camera, point;
  double u, v;
  int line;
};

// The same (frame, camera, point) on two lines is an error naming both (the
// first repeat in file order). Sorts the observations by index.
Status CheckNoRepeatedObservation(const std::string& path,
                                  std::vector<Observation>* observations) {
  const auto key = [](const Observation& o) {
    return std::tie(o.frame, o.camera, o.point);
  };
  std::sort(observations->begin(), observations->end(),
            [](const Observation& a, const Observation& b) {
              return std::make_tuple(a.frame, a.camera, a.point, a.line) <
                     std::make_tuple(b.frame, b.camera, b.point, b.line);
            });
  // In each run of one index, the first holds the first line and the second
  // the first repeat.
  const Observation* repeat = nullptr;
  int first_line = 0;
  for (std::size_t i = 1; i < observations->size(); ++i) {
    const Observation& a = (*observations)[i - 1];
    const Observation& b = (*observations)[i];
    const bool a_starts_run = i == 1 || key((*observations)[i - 2]) != key(a);
    if (key(a) == key(b) && a_starts_run &&
        (repeat == nullptr || b.line < repeat->line)) {
      repeat = &b;
      first_line = a.line;
    }
  }
  if (repeat == nullptr) return Status::OK();
  return Status::Error(
      Where(path, repeat->line) + ": frame " + std::to_string(repeat->frame) +
      ", camera " + std::to_string(repeat->camera) + ", point " +
      std::to_string(repeat->point) + " was already given on line " +
      std::to_string(first_line));
}

// Bytes of W and its visibility mask for F frames, M cameras, P points
// (saturating).
std::uint64_t DenseBytes(std::int64_t frames, std::int64_t cameras,
                         std::int64_t points) {
  // views < 2^62
  const std::uint64_t views = std::uint64_t(frames) * std::uint64_t(cameras);
  constexpr std::uint64_t kBytesPerEntry = 2 * sizeof(double) + sizeof(bool);
  if (points != 0 && views > std::numeric_limits<std::uint64_t>::max() /
                                 kBytesPerEntry / std::uint64_t(points)) {
    return std::numeric_limits<std::uint64_t>::max();
  }
  return views * std::uint64_t(points) * kBytesPerEntry;
}

std::string MegaBytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.0f MB", bytes / 1e6);
  return text;
}

// The distinct values of one index of the observations, increasing.
std::vector<int> MentionedIndices(const std::vector<Observation>& observations,
                                  int Observation::*index) {
  std::vector<int> ids;
  ids.reserve(observations.size());
  for (const Observation& o : observations) ids.push_back(o.*index);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

int IndexOf(const std::vector<int>& ids, int id) {
  return static_cast<int>(std::lower_bound(ids.begin(), ids.end(), id) -
                          ids.begin());
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
  TextWriter out;
  NRSFM_RETURN_IF_ERROR(out.Open(path));
  for (Eigen::Index i = 0; i < matrix.rows(); ++i) {
    for (Eigen::Index j = 0; j < matrix.cols(); ++j) {
      if (j > 0) out.Char(' ');
      out.Number(matrix(i, j), "NaN");
    }
    out.Char('\n');
  }
  return out.Close();
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
    num_frames = std::max(num_frames, std::int64_t{o.frame} + 1);
    num_cameras = std::max(num_cameras, std::int64_t{o.camera} + 1);
    num_points = std::max(num_points, std::int64_t{o.point} + 1);
    observations.push_back(o);
  }
  if (in.bad()) return Status::Error(path + ": read error");
  if (observations.empty())
    return Status::Error(path + ": no observations in the file");
  NRSFM_RETURN_IF_ERROR(CheckNoRepeatedObservation(path, &observations));

  // W over every index up to the largest, when the budget allows it; else
  // over the frames and points the list mentions (their ids kept).
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  const std::uint64_t budget = InputArrayBudget(ec ? 0 : file_size);
  // W's rows (2FM) must also be int indices (Measurements::Row).
  const auto fits = [budget, num_cameras](std::int64_t frames,
                                          std::int64_t points) {
    return DenseBytes(frames, num_cameras, points) <= budget &&
           2 * frames * num_cameras <= std::numeric_limits<int>::max();
  };
  Measurements m;
  m.num_cameras = static_cast<int>(num_cameras);
  if (!fits(num_frames, num_points)) {
    m.frame_ids = MentionedIndices(observations, &Observation::frame);
    m.point_ids = MentionedIndices(observations, &Observation::point);
    const std::int64_t frames = static_cast<std::int64_t>(m.frame_ids.size());
    const std::int64_t points = static_cast<std::int64_t>(m.point_ids.size());
    if (!fits(frames, points)) {
      return Status::Error(
          path + ": the " + std::to_string(observations.size()) +
          " observations of F = " + std::to_string(frames) +
          " frames, M = " + std::to_string(num_cameras) + " cameras and P = " +
          std::to_string(points) + " points would need a W of " +
          MegaBytes(DenseBytes(frames, num_cameras, points)) +
          ", more than a list of its size may take (" + MegaBytes(budget) +
          ", " + std::to_string(kInputBudgetSlackBytes >> 20) + " MB + " +
          std::to_string(kMaxDeflateRatio) +
          " bytes per byte of the file): too sparse for nrsfm's dense W");
    }
    num_frames = frames;
    num_points = points;
  }
  m.num_frames = static_cast<int>(num_frames);
  m.num_points = static_cast<int>(num_points);
  m.W.setConstant(2 * m.NumViews(), m.num_points, std::nan(""));
  m.visible.setConstant(m.NumViews(), m.num_points, false);
  for (const Observation& o : observations) {
    const int t = m.frame_ids.empty() ? o.frame : IndexOf(m.frame_ids, o.frame);
    const int p = m.point_ids.empty() ? o.point : IndexOf(m.point_ids, o.point);
    const int view = m.View(t, o.camera);
    m.W(2 * view, p) = o.u;
    m.W(2 * view + 1, p) = o.v;
    m.visible(view, p) = true;
  }
  *measurements = std::move(m);
  return Status::OK();
}

Status WriteObservationList(const std::string& path,
                            const Measurements& measurements) {
  TextWriter out;
  NRSFM_RETURN_IF_ERROR(out.Open(path));
  out.Text("# frame camera point u v\n");
  for (int t = 0; t < measurements.num_frames; ++t) {
    for (int c = 0; c < measurements.num_cameras; ++c) {
      const int view = measurements.View(t, c);
      for (int p = 0; p < measurements.num_points; ++p) {
        if (!measurements.visible(view, p)) continue;
        out.Int(measurements.frame_ids.empty() ? t : measurements.frame_ids[t])
            .Char(' ')
            .Int(c)
            .Char(' ')
            .Int(measurements.point_ids.empty() ? p : measurements.point_ids[p])
            .Char(' ')
            .Number(measurements.W(2 * view, p))
            .Char(' ')
            .Number(measurements.W(2 * view + 1, p))
            .Char('\n');
      }
    }
  }
  return out.Close();
}

TextWriter::~TextWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

Status TextWriter::Open(const std::string& path) {
  CHECK(file_ == nullptr) << "TextWriter opened twice";
  path_ = path;
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) {
    return Status::Error(path +
                         ": cannot create the file: " + std::strerror(errno));
  }
  error_.clear();
  buffer_.clear();
  buffer_.reserve(kBufferBytes + 256);
  return Status::OK();
}

TextWriter& TextWriter::Text(std::string_view text) {
  buffer_.append(text);
  FlushIfFull();
  return *this;
}

TextWriter& TextWriter::Char(char c) {
  buffer_.push_back(c);
  FlushIfFull();
  return *this;
}

TextWriter& TextWriter::Int(long long value) {
  char digits[24];
  const std::to_chars_result end =
      std::to_chars(digits, digits + sizeof(digits), value);
  buffer_.append(digits, end.ptr);
  FlushIfFull();
  return *this;
}

TextWriter& TextWriter::Number(double value, std::string_view nan_text) {
  if (std::isnan(value)) return Text(nan_text);
  char digits[32];  // the longest shortest form is 24 characters
  const std::to_chars_result end =
      std::to_chars(digits, digits + sizeof(digits), value);
  CHECK(end.ec == std::errc()) << "to_chars failed on " << value;
  buffer_.append(digits, end.ptr);
  FlushIfFull();
  return *this;
}

void TextWriter::FlushIfFull() {
  if (buffer_.size() >= kBufferBytes) Flush();
}

void TextWriter::Flush() {
  CHECK(file_ != nullptr)
      << "TextWriter written before Open() or after Close()";
  if (error_.empty() && !buffer_.empty() &&
      std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
    error_ = std::strerror(errno);
  buffer_.clear();
}

Status TextWriter::Close() {
  Flush();
  if (error_.empty() && std::fflush(file_) != 0) error_ = std::strerror(errno);
  if (std::fclose(file_) != 0 && error_.empty()) error_ = std::strerror(errno);
  file_ = nullptr;
  if (!error_.empty())
    return Status::Error(path_ + ": error while writing the file: " + error_);
  return Status::OK();
}

}  // namespace nrsfm
