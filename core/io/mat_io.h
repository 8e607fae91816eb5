// Reading and writing numeric variables of MATLAB .mat files (v4, v5 and
// v7.3) through matio. Nothing of matio shows in this header.
//
// Arrays are column-major, as in MATLAB: element (i, j, k) of an
// d0 × d1 × d2 array is number i + d0·(j + d1·k) of its data. Every numeric
// class (double, single, int8…uint64, logical) is returned as double (int64
// values beyond 2^53 lose precision).
//
// Files are not trusted: every function checks that the path is a readable,
// non-empty regular file, that every size it claims fits in the bytes that
// hold it before matio reads anything (core/io/mat_file_check.h: for a file of
// N bytes no single allocation is larger than about 8 · 1032 · N bytes), that
// matio recognises it, and the class, flags, rank and size of the variable
// before it reads the data. Errors name the
// file and the variable. These functions install a process-wide matio log
// function (Mat_LogInitFunc) that prints nothing: matio's messages (and the
// HDF5 errors it forwards) are captured, and the one that explains a failure
// is appended to the error. All matio calls made through this file are
// serialised by one mutex (matio is not thread-safe).
#ifndef NRSFM_CORE_IO_MAT_IO_H_
#define NRSFM_CORE_IO_MAT_IO_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"

namespace nrsfm {

// Reads a 2-D numeric variable as double. Fails when the file is missing, is
// a directory, is empty, is not a .mat file or is truncated/corrupt; when the
// variable does not exist (the message lists the variables that do); when it
// is not numeric (char, struct, cell, object, sparse, complex) or not 2-D;
// when a dimension or the element count is more than the file can hold
// ("claims a size of …, more than the file can hold").
// An empty variable (0 rows or 0 columns) is returned as such: callers must
// check the size before they index it.
Status ReadMatVariable(const std::string& path, const std::string& name,
                       Eigen::MatrixXd* value);

// Reads a 3-D numeric array A (d0 × d1 × d2, e.g. X = 3 × P × F) as d2
// matrices of size d0 × d1: (*slices)[k] = A(:, :, k). A 2-D variable is
// one slice (d2 = 1). Fails as ReadMatVariable, and on more than 3
// dimensions. An empty array (d0, d1 or d2 is 0) gives no slice at all:
// *slices is empty, and callers must check that before they index it.
// `dims`, when given, gets {d0, d1, d2} (d2 = 1 for a 2-D variable).
Status ReadMatArray3(const std::string& path, const std::string& name,
                     std::vector<Eigen::MatrixXd>* slices,
                     std::vector<std::size_t>* dims = nullptr);

// "d0 x d1" or "d0 x d1 x d2" (when d2 != 1): the size of ReadMatArray3's
// `dims` as error messages show it.
std::string MatDimsString(const std::vector<std::size_t>& dims);

// The names of the variables in a .mat file, in file order (v7.3: in
// HDF5 order, i.e. sorted by name).
Status ListMatVariables(const std::string& path,
                        std::vector<std::string>* names);

enum class MatVersion { kV4, kV5, kV73 };

// One variable to write: `value` holds the data column-major. With `dims`
// empty the variable is value.rows() × value.cols(); otherwise `dims` gives
// its size (2-D or N-D, column-major like MATLAB) and the product of dims
// must equal value.size(). Example: a 3 × P × F array X is written from the
// 3 × (P·F) matrix [X_0 X_1 … X_{F-1}] with dims = {3, P, F}.
struct MatVariable {
  std::string name;
  Eigen::MatrixXd value;
  std::vector<int> dims;
};

// Writes double variables to a new .mat file (replacing an existing file).
// v5 data are zlib-compressed; v4 cannot hold N-D arrays (an error). Names
// must be valid MATLAB identifiers (a letter, then letters, digits or '_',
// at most 63 characters) and distinct. A file that could not be written
// completely is removed.
Status WriteMat(const std::string& path, MatVersion version,
                const std::vector<MatVariable>& variables);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_MAT_IO_H_
