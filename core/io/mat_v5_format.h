// The codes of MATLAB's v5 MAT-file format (MATLAB "MAT-File Format",
// Tables 1-1 and 1-3): the data type of a data element's tag and the class
// in an array's flags. core/io/mat_file_check.cc reads them; the tests write
// files byte by byte with them (tests/mat_v5_bytes.h).
#ifndef NRSFM_CORE_IO_MAT_V5_FORMAT_H_
#define NRSFM_CORE_IO_MAT_V5_FORMAT_H_

#include <cstdint>

namespace nrsfm {
namespace mat_v5 {

// Data types (miINT8 …): the first word of a data element's tag.
enum : std::uint32_t {
  kMiInt8 = 1,
  kMiUint8 = 2,
  kMiInt16 = 3,
  kMiUint16 = 4,
  kMiInt32 = 5,
  kMiUint32 = 6,
  kMiSingle = 7,
  kMiDouble = 9,
  kMiInt64 = 12,
  kMiUint64 = 13,
  kMiMatrix = 14,
  kMiCompressed = 15,
  kMiUtf8 = 16,
  kMiUtf16 = 17,
  kMiUtf32 = 18
};

// Array classes (mxCELL_CLASS …): the low byte of an array's flags.
enum : std::uint32_t {
  kMxCell = 1,
  kMxStruct = 2,
  kMxObject = 3,
  kMxChar = 4,
  kMxSparse = 5,
  kMxDouble = 6,
  kMxSingle = 7,
  kMxInt8 = 8,
  kMxUint8 = 9,
  kMxInt16 = 10,
  kMxUint16 = 11,
  kMxInt32 = 12,
  kMxUint32 = 13,
  kMxInt64 = 14,
  kMxUint64 = 15,
  kMxFunction = 16,
  kMxOpaque = 17
};

}  // namespace mat_v5
}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_MAT_V5_FORMAT_H_
