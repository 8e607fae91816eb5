// Checks the sizes a MATLAB .mat file claims against the bytes that hold
// them, before matio acts on them (core/io/mat_io.cc calls it on every open).
//
// matio trusts a variable's header: a name length, a dimension count, a cell
// count or a struct's field count is allocated as claimed while it scans the
// file for variable names, and a variable's data are allocated as its
// dimensions claim when it is read. A 400-byte file can so claim gigabytes.
// The check walks the file as matio will read it and bounds every claim by
// the bytes of the element that holds it:
//   v4   each record's header as matio reads it (byte order from the
//        thousands digit of its type, as matio decides), its name and its
//        data within the file.
//   v5   every data element's byte count within its parent's (a top-level
//        variable's within the file; the inflated size of a compressed one
//        within 1032 times its compressed bytes, deflate's largest ratio);
//        in each array (nested ones too): the dimensions, the name, the field
//        names, and at least 8 bytes (one tag) per cell or field claimed;
//        arrays nested more than kMaxMatNesting deep are refused. A numeric
//        variable's data are what its data element holds.
//   v7.3 (HDF5) not walked: its data are bounded by 1032 times the file size.
// The largest element count the data of each top-level numeric variable can
// hold is returned, for the reader to compare with its dimensions before it
// reads (an error there names that variable only: the others still read).
#ifndef NRSFM_CORE_IO_MAT_FILE_CHECK_H_
#define NRSFM_CORE_IO_MAT_FILE_CHECK_H_

#include <cstdint>
#include <map>
#include <string>

#include "core/io/input_budget.h"  // kMaxDeflateRatio
#include "core/model/status.h"

namespace nrsfm {

// Arrays nested in cells or structs deeper than this are refused (matio
// reads them recursively).
inline constexpr int kMaxMatNesting = 64;

struct MatFileClaims {
  // For each top-level variable of a v4 or v5 file (the first of a repeated
  // name), the largest number of elements its stored data can hold. Empty
  // for a v7.3 file.
  std::map<std::string, std::uint64_t> max_elements;
};

// Walks the file at `path` of `file_size` bytes (a readable regular file)
// as above. Fails with "<path>: not a MATLAB .mat file (v4, v5 or v7.3)"
// when the first v4 record is invalid, and with "<path>: the .mat file is
// truncated or corrupt (<what claims what>)" on a claim the file cannot
// hold (e.g. "variable 'W' claims a size of 60 x 40, more than the 9580
// bytes after its name hold").
Status CheckMatFileClaims(const std::string& path, std::uint64_t file_size,
                          MatFileClaims* claims);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_MAT_FILE_CHECK_H_
