// MATLAB v5 .mat files built byte by byte (uncompressed, little-endian), for
// tests and fuzz seeds of what the readers must handle: variables that
// core/io/mat_io.h's WriteMat cannot write (other classes, an empty 3-D array,
// a cell, a struct with an empty field) and files that are corrupt in a
// known way.
//
// Layout (MATLAB "MAT-File Format", v5): a 128-byte header, then one
// miMATRIX data element per variable. A data element is an 8-byte tag
// (uint32 type, uint32 byte count) and its payload, padded to 8 bytes. An
// array's payload is: array flags (class, flags, nzmax), dims, name, then its
// contents (the data elements of its class).
#ifndef NRSFM_TESTS_MAT_V5_BYTES_H_
#define NRSFM_TESTS_MAT_V5_BYTES_H_

#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

#include "core/io/mat_v5_format.h"

namespace nrsfm {
namespace testing_util {
namespace v5 {

// The format's data types (kMi…) and array classes (kMx…).
using namespace ::nrsfm::mat_v5;

// Array flags.
constexpr std::uint8_t kFlagComplex = 0x08, kFlagLogical = 0x02;

// The bytes of `values`, as they lie in memory (little-endian here).
template <typename T>
std::string Raw(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()),
                     sizeof(T) * values.size());
}

// The 128-byte header: text, subsystem offset, version 0x0100 and "IM"
// (little-endian).
inline std::string Header() {
  std::string text = "MATLAB 5.0 MAT-file, written by nrsfm tests";
  text.resize(116, ' ');
  text += std::string(8, '\0');
  return text + Raw(std::vector<std::uint16_t>{0x0100}) + "IM";
}

// A data element: tag (type, payload size) and the payload padded to 8 bytes.
inline std::string Element(std::uint32_t type, const std::string& payload) {
  std::string element = Raw(std::vector<std::uint32_t>{
                            type, static_cast<std::uint32_t>(payload.size())}) +
                        payload;
  element.resize((element.size() + 7) / 8 * 8, '\0');
  return element;
}

// An array of class `mx_class` (with `flags`), size `dims` and name `name`
// ("" inside a cell or struct); `contents` are its data elements, which need
// not match dims (a corrupt file).
inline std::string Matrix(std::uint8_t mx_class, std::uint8_t flags,
                          const std::vector<int>& dims, const std::string& name,
                          const std::string& contents,
                          std::uint32_t nzmax = 0) {
  const std::vector<std::uint32_t> array_flags = {
      static_cast<std::uint32_t>(mx_class) |
          (static_cast<std::uint32_t>(flags) << 8),
      nzmax};
  const std::vector<std::int32_t> dims32(dims.begin(), dims.end());
  return Element(kMiMatrix, Element(kMiUint32, Raw(array_flags)) +
                                Element(kMiInt32, Raw(dims32)) +
                                Element(kMiInt8, name) + contents);
}

// A double array (column-major values; their count need not match dims).
inline std::string Double(const std::string& name, const std::vector<int>& dims,
                          const std::vector<double>& values) {
  return Matrix(kMxDouble, 0, dims, name, Element(kMiDouble, Raw(values)));
}

// A miCOMPRESSED element holding `element` (e.g. a Matrix) deflated with
// zlib, as MATLAB writes v7 files; not padded. `claimed_size` replaces the
// inflated element's byte count when given (a corrupt file).
inline std::string Compressed(std::string element,
                              std::int64_t claimed_size = -1) {
  if (claimed_size >= 0) {
    const std::uint32_t size = static_cast<std::uint32_t>(claimed_size);
    element.replace(4, 4, Raw(std::vector<std::uint32_t>{size}));
  }
  uLongf length = compressBound(element.size());
  std::string deflated(length, '\0');
  compress(reinterpret_cast<Bytef*>(deflated.data()), &length,
           reinterpret_cast<const Bytef*>(element.data()), element.size());
  deflated.resize(length);
  return Raw(std::vector<std::uint32_t>{15,
                                        static_cast<std::uint32_t>(length)}) +
         deflated;
}

// An empty miMATRIX element (no bytes at all): how MATLAB stores the []
// of an empty cell or struct field.
inline std::string EmptyMatrix() { return Element(kMiMatrix, ""); }

// A cell array; `cells` are its elements (arrays named ""), column-major.
inline std::string Cell(const std::string& name, const std::vector<int>& dims,
                        const std::vector<std::string>& cells) {
  std::string contents;
  for (const std::string& cell : cells) contents += cell;
  return Matrix(kMxCell, 0, dims, name, contents);
}

// A 1 × 1 struct with fields `field_names` (each shorter than 32
// characters) holding `values` (arrays named ""), in the same order.
inline std::string Struct(const std::string& name,
                          const std::vector<std::string>& field_names,
                          const std::vector<std::string>& values) {
  constexpr std::uint32_t kFieldNameLength = 32;
  std::string names;
  for (const std::string& field : field_names) {
    std::string padded = field;
    padded.resize(kFieldNameLength, '\0');
    names += padded;
  }
  // The field name length is a "small" int32 element: type and byte count
  // in the first 4 bytes, the value in the next 4.
  std::string contents =
      Raw(std::vector<std::uint32_t>{(4u << 16) | kMiInt32, kFieldNameLength}) +
      Element(kMiInt8, names);
  for (const std::string& value : values) contents += value;
  return Matrix(kMxStruct, 0, {1, 1}, name, contents);
}

}  // namespace v5
}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_MAT_V5_BYTES_H_
