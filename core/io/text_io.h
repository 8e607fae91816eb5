// Plain-text inputs: a measurement matrix W as text/CSV, a sparse observation
// list, and the CSV tables nrsfm writes (docs/guide.md, "Outputs").
//
// Common text rules: fields are separated by whitespace and/or single commas;
// `#` starts a comment that runs to the end of the line; blank and
// comment-only lines are skipped; "\r\n" line ends are accepted. Numbers are
// parsed independently of the locale ("1.5", "-2e-3", "+4"). `NaN` (any case)
// marks a missing value; ±Inf is always an error. Errors name the file, the
// 1-based line and, for a bad field, the 1-based column (field number).
#ifndef NRSFM_CORE_IO_TEXT_IO_H_
#define NRSFM_CORE_IO_TEXT_IO_H_

#include <Eigen/Core>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/status.h"

namespace nrsfm {

// A text file written through a buffer, numbers in the shortest decimal form
// that reads back to the same double (std::to_chars: "0.1", "-2.5e-07",
// "3"; as exact as %.17g and several times faster to format). After a
// write error the rest is dropped; Close() reports the error, naming the
// file and the reason. Destroying a writer that was opened and not closed
// closes the file without writing what is still buffered (a result that was
// not Close()d is incomplete anyway). Open() once and Close() once (a CHECK
// on misuse).
class TextWriter {
 public:
  TextWriter() = default;
  TextWriter(const TextWriter&) = delete;
  TextWriter& operator=(const TextWriter&) = delete;
  ~TextWriter();

  // Creates (truncates) `path`; errors name the path and the reason.
  Status Open(const std::string& path);
  TextWriter& Text(std::string_view text);
  TextWriter& Char(char c);
  TextWriter& Int(long long value);
  // NaN is written as `nan_text`; ±Inf as "inf" / "-inf".
  TextWriter& Number(double value, std::string_view nan_text = "nan");
  // Flushes and closes; errors on any write or close failure.
  Status Close();

 private:
  void FlushIfFull();
  void Flush();  // writes the buffer out (unless an error came before)

  std::string path_;
  std::FILE* file_ = nullptr;
  std::string buffer_;
  std::string error_;  // the first write error's reason, "" = none
};

// Reads a matrix, one row per line; every row must have the same number of
// fields (the error names the first line that differs). NaN entries are kept
// as NaN. Fails on an empty file (no numbers), a field that is not a number,
// an empty field ("1,,2") and on ±Inf.
Status ReadTextMatrix(const std::string& path, Eigen::MatrixXd* matrix);

// Writes a matrix in the format ReadTextMatrix reads: one row per line,
// values separated by single spaces, full precision (TextWriter: values
// round trip exactly), NaN as "NaN".
Status WriteTextMatrix(const std::string& path, const Eigen::MatrixXd& matrix);

// Reads a CSV table whose first (non-comment) line is a header that must
// equal `header` (field by field, e.g. {"frame", "point", "x"}), followed by
// numeric rows of header.size() fields. `table` gets one row per data line.
// Fails on an empty file, another header, a bad row and on no data row.
Status ReadCsvTable(const std::string& path,
                    const std::vector<std::string>& header,
                    Eigen::MatrixXd* table);

// Reads a sparse observation list: one observation per line,
//   frame camera point u v
// with 0-based integer indices (written as integers, "3", or integral
// numbers, "3.0") and finite u, v. The list is held sparse until its
// indices are known; then W (2FM × P) and its mask are built as follows.
//   - F, M and P are each the largest index + 1 (frames and points that no
//     line mentions are simply not visible: the solvers leave them out and
//     report them), when that W with its mask (17 bytes an entry) fits in
//     InputArrayBudget(file size) = 64 MB + 1032 bytes per byte of the file
//     (core/io/input_budget.h);
//   - otherwise F and P count only the frames and points the list mentions,
//     numbered in increasing order of their index, and
//     measurements->frame_ids / point_ids give each one's index in the list
//     (a frame index of a million with one observation is one more frame,
//     not a 2 GB W). M stays the largest camera index + 1.
// Fails on a line with other than 5 fields, a negative or non-integer index
// (or one of 2^31 - 1 or more), non-finite u or v, the same (frame, camera,
// point) twice (naming both lines), no observation at all, or when even the
// W of the mentioned frames and points exceeds the budget (the error names
// F, M, P and the sizes).
Status ReadObservationList(const std::string& path, Measurements* measurements);

// Writes the visible observations of `measurements` as an observation list
// (frame-major order, full precision), with the input's indices when it has
// frame_ids / point_ids.
Status WriteObservationList(const std::string& path,
                            const Measurements& measurements);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_TEXT_IO_H_
