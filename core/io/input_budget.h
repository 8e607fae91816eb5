// How much a file may make the readers allocate: what its size justifies.
//
// A file of N bytes holds at most N bytes of numbers, or, deflated (a v5
// .mat variable, an HDF5 dataset), at most 1032 N: zlib never inflates more
// than 1032 bytes from one. The readers check every size a file claims
// against the bytes that hold it (core/io/mat_file_check.h) and build an
// observation list's W only as large as this budget allows (core/io/text_io.h),
// so that no input array of a file of N bytes takes more than
// InputArrayBudget(N) bytes; the 64 MB leave room for small files. The fuzz
// targets hold the readers to the same figure (tests/fuzz/allocation_budget.h).
#ifndef NRSFM_CORE_IO_INPUT_BUDGET_H_
#define NRSFM_CORE_IO_INPUT_BUDGET_H_

#include <cstdint>

namespace nrsfm {

// zlib's deflate never inflates more than 1032 bytes from one (zlib
// technical details): the most a compressed byte can claim.
inline constexpr std::uint64_t kMaxDeflateRatio = 1032;

inline constexpr std::uint64_t kInputBudgetSlackBytes = std::uint64_t(64) << 20;

// 64 MB + 1032 · file_size bytes.
inline constexpr std::uint64_t InputArrayBudget(std::uint64_t file_size) {
  return kInputBudgetSlackBytes + kMaxDeflateRatio * file_size;
}

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_INPUT_BUDGET_H_
