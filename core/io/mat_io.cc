#include "core/io/mat_io.h"

#include <matio.h>

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <system_error>

#include "core/io/mat_file_check.h"

namespace nrsfm {
namespace {

// The messages matio logs while a MatioSession is alive; nullptr otherwise
// (then messages are dropped: the library never prints).
std::vector<std::string>* g_matio_log = nullptr;

void CaptureMatioLog(int /*log_level*/, char* message) {
  if (g_matio_log != nullptr && message != nullptr) {
    g_matio_log->push_back(message);
  }
}

std::mutex& MatioMutex() {
  static std::mutex mutex;
  return mutex;
}

// Holds the matio lock and captures matio's log for the lifetime of one
// public call. The log function is (re)installed on every call because matio
// also routes HDF5's error stack (which is per thread) through it.
class MatioSession {
 public:
  MatioSession() : lock_(MatioMutex()) {
    g_matio_log = &log_;
    Mat_LogInitFunc("nrsfm", &CaptureMatioLog);
  }
  ~MatioSession() { g_matio_log = nullptr; }
  MatioSession(const MatioSession&) = delete;
  MatioSession& operator=(const MatioSession&) = delete;

  bool HasLog() const { return !log_.empty(); }
  void ClearLog() { log_.clear(); }
  // " (matio: <reason>)" or "": the innermost HDF5 "minor:" reason when
  // there is one, else the first line of the first message.
  std::string LogSuffix() const {
    if (log_.empty()) return "";
    std::string reason = log_.front().substr(0, log_.front().find('\n'));
    for (const std::string& message : log_) {
      const std::size_t minor = message.rfind("minor: ");
      if (minor != std::string::npos) reason = message.substr(minor + 7);
    }
    return " (matio: " + reason + ")";
  }

 private:
  std::lock_guard<std::mutex> lock_;
  std::vector<std::string> log_;
};

struct MatCloser {
  void operator()(mat_t* mat) const { Mat_Close(mat); }
};
struct VarFreer {
  void operator()(matvar_t* var) const { Mat_VarFree(var); }
};
using MatFilePtr = std::unique_ptr<mat_t, MatCloser>;
using MatVarPtr = std::unique_ptr<matvar_t, VarFreer>;

std::string Quote(const std::string& s) { return "'" + s + "'"; }

// Checks that `path` is a non-empty regular file we can read; sets its size.
Status CheckReadableFile(const std::string& path, std::uintmax_t* size) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return Status::Error(path + ": no such file");
  if (fs::is_directory(status)) {
    return Status::Error(path + ": is a directory, not a .mat file");
  }
  if (!fs::is_regular_file(status)) {
    return Status::Error(path + ": not a regular file");
  }
  *size = fs::file_size(path, ec);
  if (ec)
    return Status::Error(path + ": cannot read the file size: " + ec.message());
  if (*size == 0)
    return Status::Error(path + ": file is empty, not a .mat file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) return Status::Error(path + ": cannot open the file for reading");
  return Status::OK();
}

// Opens the file for matio once every size it claims has been checked
// against the bytes that hold it (core/io/mat_file_check.h).
Status OpenMat(const std::string& path, MatioSession* session, MatFilePtr* mat,
               std::uintmax_t* file_size, MatFileClaims* claims) {
  NRSFM_RETURN_IF_ERROR(CheckReadableFile(path, file_size));
  NRSFM_RETURN_IF_ERROR(CheckMatFileClaims(path, *file_size, claims));
  mat->reset(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (*mat == nullptr) {
    return Status::Error(path + ": not a MATLAB .mat file (v4, v5 or v7.3)" +
                         session->LogSuffix());
  }
  // A v7.3 file whose HDF5 part cannot be opened still yields a handle.
  if (session->HasLog()) {
    return Status::Error(path + ": the .mat file is truncated or corrupt" +
                         session->LogSuffix());
  }
  return Status::OK();
}

// Variable names in file order. A scan that logs a problem means the file is
// truncated or corrupt.
Status ScanNames(const std::string& path, mat_t* mat, MatioSession* session,
                 std::vector<std::string>* names) {
  names->clear();
  session->ClearLog();
  Mat_Rewind(mat);
  while (true) {
    MatVarPtr var(Mat_VarReadNextInfo(mat));
    if (var == nullptr) break;
    names->push_back(var->name != nullptr ? var->name : "");
  }
  if (session->HasLog()) {
    return Status::Error(path + ": the .mat file is truncated or corrupt" +
                         session->LogSuffix());
  }
  return Status::OK();
}

std::string JoinNames(const std::vector<std::string>& names) {
  if (names.empty()) return "(none)";
  std::string joined;
  for (const std::string& name : names) {
    if (!joined.empty()) joined += ", ";
    joined += name;
  }
  return joined;
}

const char* ClassName(matio_classes class_type) {
  switch (class_type) {
    case MAT_C_CELL:
      return "a cell array";
    case MAT_C_STRUCT:
      return "a struct";
    case MAT_C_OBJECT:
      return "an object";
    case MAT_C_CHAR:
      return "a char array";
    case MAT_C_SPARSE:
      return "a sparse matrix";
    case MAT_C_FUNCTION:
      return "a function handle";
    case MAT_C_OPAQUE:
      return "an opaque object";
    default:
      return "of an unknown class";
  }
}

bool IsNumericClass(matio_classes class_type) {
  switch (class_type) {
    case MAT_C_EMPTY:
    case MAT_C_DOUBLE:
    case MAT_C_SINGLE:
    case MAT_C_INT8:
    case MAT_C_UINT8:
    case MAT_C_INT16:
    case MAT_C_UINT16:
    case MAT_C_INT32:
    case MAT_C_UINT32:
    case MAT_C_INT64:
    case MAT_C_UINT64:
      return true;
    default:
      return false;
  }
}

std::string DimsString(const matvar_t& var) {
  std::ostringstream s;
  for (int i = 0; i < var.rank; ++i) s << (i ? " x " : "") << var.dims[i];
  return s.str();
}

// Checks class, flags, rank (2..max_rank) and size of a variable header and
// returns its element count. The count may not exceed `max_elements`, what
// the variable's stored data can hold (core/io/mat_file_check.h). Each
// dimension on its own is bounded by the file size too: an empty array (a
// zero dimension) has no data to bound the others, and 0 x 2^60 is no real
// variable.
Status CheckHeader(const std::string& what, const matvar_t& var, int max_rank,
                   std::uintmax_t file_size, std::uint64_t max_elements,
                   std::size_t* numel) {
  if (!IsNumericClass(var.class_type)) {
    return Status::Error(what + " is " + ClassName(var.class_type) +
                         ", not a numeric array");
  }
  if (var.isComplex)
    return Status::Error(what + " is complex; expected real numbers");
  if (var.rank < 2 || var.dims == nullptr) {
    return Status::Error(what + " has an invalid rank " +
                         std::to_string(var.rank) + " (corrupt file?)");
  }
  if (var.rank > max_rank) {
    return Status::Error(what + " is " + std::to_string(var.rank) + "-D (" +
                         DimsString(var) + "); expected " +
                         (max_rank == 2 ? "a 2-D matrix" : "at most 3-D"));
  }
  const std::uintmax_t max_dimension =
      file_size * kMaxDeflateRatio + (1u << 20);
  std::uintmax_t count = 1;
  bool too_large = false;
  for (int i = 0; i < var.rank; ++i) {
    too_large = too_large || var.dims[i] > max_dimension;
    // Saturates at max_elements + 1 (a zero dimension still makes 0).
    count = var.dims[i] > 0 && count > (max_elements + 1) / var.dims[i]
                ? max_elements + 1
                : count * var.dims[i];
  }
  if (too_large || count > max_elements) {
    return Status::Error(
        what + " claims a size of " + DimsString(var) +
        ", more than the file can hold (truncated or corrupt file?)");
  }
  *numel = static_cast<std::size_t>(count);
  return Status::OK();
}

// What the stored data of variable `name` can hold: from the walk of a v4
// or v5 file, else (v7.3, compressed by HDF5) 1032 one-byte elements per
// byte of the file.
std::uint64_t MaxElements(const MatFileClaims& claims, const std::string& name,
                          std::uintmax_t file_size) {
  const auto it = claims.max_elements.find(name);
  return it != claims.max_elements.end() ? it->second
                                         : file_size * kMaxDeflateRatio;
}

template <typename T>
void ConvertToDouble(const void* data, std::size_t n, double* out) {
  const T* in = static_cast<const T*>(data);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(in[i]);
}

// Converts the data of a fully read numeric variable (laid out as its
// data_type, which matio sets to the class's type on read) to double.
Status DataToDouble(const std::string& what, const matvar_t& var,
                    std::size_t numel, double* out) {
  if (numel == 0) return Status::OK();
  const std::size_t size = Mat_SizeOf(var.data_type);
  if (var.data == nullptr || size == 0 ||
      static_cast<std::size_t>(var.data_size) != size ||
      var.nbytes < numel * size) {
    return Status::Error(
        what + ": the data could not be read (truncated or corrupt file?)");
  }
  switch (var.data_type) {
    case MAT_T_DOUBLE:
      ConvertToDouble<double>(var.data, numel, out);
      break;
    case MAT_T_SINGLE:
      ConvertToDouble<float>(var.data, numel, out);
      break;
    case MAT_T_INT8:
      ConvertToDouble<std::int8_t>(var.data, numel, out);
      break;
    case MAT_T_UINT8:
      ConvertToDouble<std::uint8_t>(var.data, numel, out);
      break;
    case MAT_T_INT16:
      ConvertToDouble<std::int16_t>(var.data, numel, out);
      break;
    case MAT_T_UINT16:
      ConvertToDouble<std::uint16_t>(var.data, numel, out);
      break;
    case MAT_T_INT32:
      ConvertToDouble<std::int32_t>(var.data, numel, out);
      break;
    case MAT_T_UINT32:
      ConvertToDouble<std::uint32_t>(var.data, numel, out);
      break;
    case MAT_T_INT64:
      ConvertToDouble<std::int64_t>(var.data, numel, out);
      break;
    case MAT_T_UINT64:
      ConvertToDouble<std::uint64_t>(var.data, numel, out);
      break;
    default:
      return Status::Error(what + ": unsupported stored data type " +
                           std::to_string(static_cast<int>(var.data_type)));
  }
  return Status::OK();
}

// Reads variable `name` of at most `max_rank` dimensions: its dims (padded
// with 1 to 3 entries) and its data as double, column-major.
Status ReadNumeric(const std::string& path, const std::string& name,
                   int max_rank, std::vector<std::size_t>* dims,
                   std::vector<double>* data) {
  MatioSession session;
  MatFilePtr mat;
  std::uintmax_t file_size = 0;
  MatFileClaims claims;
  NRSFM_RETURN_IF_ERROR(OpenMat(path, &session, &mat, &file_size, &claims));
  const std::string what = path + ": variable " + Quote(name);

  session.ClearLog();
  MatVarPtr info(name.empty() ? nullptr
                              : Mat_VarReadInfo(mat.get(), name.c_str()));
  if (info == nullptr) {
    if (session.HasLog()) {
      return Status::Error(
          path + ": the .mat file is truncated or corrupt while looking for " +
          Quote(name) + session.LogSuffix());
    }
    std::vector<std::string> names;
    NRSFM_RETURN_IF_ERROR(ScanNames(path, mat.get(), &session, &names));
    return Status::Error(path + ": no variable " + Quote(name) +
                         "; the file has: " + JoinNames(names));
  }
  std::size_t numel = 0;
  const std::uint64_t max_elements = MaxElements(claims, name, file_size);
  NRSFM_RETURN_IF_ERROR(
      CheckHeader(what, *info, max_rank, file_size, max_elements, &numel));

  session.ClearLog();
  MatVarPtr var(Mat_VarRead(mat.get(), name.c_str()));
  // matio returns a variable with partly missing data from a truncated
  // compressed v5 file, and only logs a warning.
  if (var == nullptr || session.HasLog()) {
    return Status::Error(
        what + ": the data could not be read (truncated or corrupt file?)" +
        session.LogSuffix());
  }
  // Never trust the second read to agree with the first.
  std::size_t numel_read = 0;
  NRSFM_RETURN_IF_ERROR(
      CheckHeader(what, *var, max_rank, file_size, max_elements, &numel_read));
  if (numel_read != numel) {
    return Status::Error(what +
                         ": inconsistent size in the file (corrupt file?)");
  }
  data->assign(numel, 0.0);
  NRSFM_RETURN_IF_ERROR(DataToDouble(what, *var, numel, data->data()));
  dims->assign(3, 1);
  for (int i = 0; i < var->rank; ++i) (*dims)[i] = var->dims[i];
  return Status::OK();
}

bool IsValidMatlabName(const std::string& name) {
  if (name.empty() || name.size() > 63) return false;
  if (!std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

Status CheckVariablesToWrite(const std::string& path, MatVersion version,
                             const std::vector<MatVariable>& variables) {
  std::set<std::string> seen;
  for (const MatVariable& v : variables) {
    const std::string what = path + ": variable " + Quote(v.name);
    if (!IsValidMatlabName(v.name)) {
      return Status::Error(what + " is not a valid MATLAB name");
    }
    if (!seen.insert(v.name).second)
      return Status::Error(what + " is given twice");
    if (v.dims.empty()) continue;
    if (v.dims.size() < 2)
      return Status::Error(what + ": dims needs at least 2 entries");
    Eigen::Index product = 1;
    for (int d : v.dims) {
      if (d < 0)
        return Status::Error(what + ": negative dimension " +
                             std::to_string(d));
      product *= d;
    }
    if (product != v.value.size()) {
      return Status::Error(what + ": the product of dims (" +
                           std::to_string(product) +
                           ") differs from the number of values (" +
                           std::to_string(v.value.size()) + ")");
    }
    if (version == MatVersion::kV4 && v.dims.size() > 2) {
      return Status::Error(what + ": MATLAB v4 files cannot hold N-D arrays");
    }
  }
  return Status::OK();
}

}  // namespace

Status ReadMatVariable(const std::string& path, const std::string& name,
                       Eigen::MatrixXd* value) {
  std::vector<std::size_t> dims;
  std::vector<double> data;
  NRSFM_RETURN_IF_ERROR(ReadNumeric(path, name, /*max_rank=*/2, &dims, &data));
  *value = Eigen::Map<const Eigen::MatrixXd>(data.data(), dims[0], dims[1]);
  return Status::OK();
}

Status ReadMatArray3(const std::string& path, const std::string& name,
                     std::vector<Eigen::MatrixXd>* slices,
                     std::vector<std::size_t>* dims) {
  std::vector<std::size_t> size;
  std::vector<double> data;
  NRSFM_RETURN_IF_ERROR(ReadNumeric(path, name, /*max_rank=*/3, &size, &data));
  slices->clear();
  if (dims != nullptr) *dims = size;
  // An empty array has no slice: a 0 x 0 x d2 array does not make d2 empty
  // matrices (d2 is bounded by the file size only, which allows millions).
  if (data.empty()) return Status::OK();
  const std::size_t slice_size = size[0] * size[1];
  slices->reserve(size[2]);
  for (std::size_t k = 0; k < size[2]; ++k) {
    slices->push_back(Eigen::Map<const Eigen::MatrixXd>(
        data.data() + k * slice_size, size[0], size[1]));
  }
  return Status::OK();
}

std::string MatDimsString(const std::vector<std::size_t>& dims) {
  std::string text;
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i == 2 && dims[i] == 1) break;
    text += (i ? " x " : "") + std::to_string(dims[i]);
  }
  return text;
}

Status ListMatVariables(const std::string& path,
                        std::vector<std::string>* names) {
  MatioSession session;
  MatFilePtr mat;
  std::uintmax_t file_size = 0;
  MatFileClaims claims;
  NRSFM_RETURN_IF_ERROR(OpenMat(path, &session, &mat, &file_size, &claims));
  return ScanNames(path, mat.get(), &session, names);
}

Status WriteMat(const std::string& path, MatVersion version,
                const std::vector<MatVariable>& variables) {
  NRSFM_RETURN_IF_ERROR(CheckVariablesToWrite(path, version, variables));
  const mat_ft file_version = version == MatVersion::kV4   ? MAT_FT_MAT4
                              : version == MatVersion::kV5 ? MAT_FT_MAT5
                                                           : MAT_FT_MAT73;
  const matio_compression compression =
      version == MatVersion::kV5 ? MAT_COMPRESSION_ZLIB : MAT_COMPRESSION_NONE;

  MatioSession session;
  MatFilePtr mat(Mat_CreateVer(path.c_str(), nullptr, file_version));
  if (mat == nullptr) {
    return Status::Error(path + ": cannot create the .mat file" +
                         session.LogSuffix());
  }
  Status status;
  for (const MatVariable& v : variables) {
    std::vector<std::size_t> dims;
    if (v.dims.empty()) {
      dims = {static_cast<std::size_t>(v.value.rows()),
              static_cast<std::size_t>(v.value.cols())};
    } else {
      dims.assign(v.dims.begin(), v.dims.end());
    }
    // matio does not modify the data it writes (MAT_F_DONT_COPY_DATA).
    MatVarPtr var(Mat_VarCreate(v.name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE,
                                static_cast<int>(dims.size()), dims.data(),
                                const_cast<double*>(v.value.data()),
                                MAT_F_DONT_COPY_DATA));
    if (var == nullptr ||
        Mat_VarWrite(mat.get(), var.get(), compression) != 0) {
      status = Status::Error(path + ": cannot write variable " + Quote(v.name) +
                             session.LogSuffix());
      break;
    }
  }
  const int close_error = Mat_Close(mat.release());
  if (status.ok() && close_error != 0) {
    status = Status::Error(path + ": error while closing the .mat file" +
                           session.LogSuffix());
  }
  if (!status.ok()) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
  return status;
}

}  // namespace nrsfm
