// The bytes core/io/mat_file_check.cc reads from a .mat file: the words of
// the format (little- or big-endian), sizes that saturate instead of
// overflowing, and the sources the check reads a region of the file from:
// the file itself (an uncompressed variable) or the inflated stream of a
// compressed one.
#ifndef NRSFM_CORE_IO_MAT_BYTE_SOURCE_H_
#define NRSFM_CORE_IO_MAT_BYTE_SOURCE_H_

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <limits>

namespace nrsfm {
namespace mat_bytes {

inline constexpr std::uint64_t kU64Max =
    std::numeric_limits<std::uint64_t>::max();

inline std::uint64_t SaturatingProduct(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > kU64Max / a) return kU64Max;
  return a * b;
}

inline std::uint64_t RoundUp8(std::uint64_t n) { return n + (8 - n % 8) % 8; }

inline std::uint32_t U32At(const unsigned char* bytes, bool big_endian) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i)
    value |= std::uint32_t(bytes[big_endian ? 3 - i : i]) << (8 * i);
  return value;
}

inline std::int32_t I32At(const unsigned char* bytes, bool big_endian) {
  return static_cast<std::int32_t>(U32At(bytes, big_endian));
}

// The bytes of one region of the file, read in order: the file itself
// (an uncompressed variable) or the inflated stream of a compressed one.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // Reads exactly n bytes; false when they cannot be had.
  virtual bool Read(unsigned char* out, std::size_t n) = 0;
  virtual bool Skip(std::uint64_t n) = 0;
};

// Reads the file from a position on. The element sizes are checked against
// the file size before anything within them is read.
class FileSource : public ByteSource {
 public:
  FileSource(std::ifstream* in, std::uint64_t position)
      : in_(in), position_(position) {}
  bool Read(unsigned char* out, std::size_t n) override;
  bool Skip(std::uint64_t n) override {
    position_ += n;
    return true;
  }

 private:
  std::ifstream* in_;
  std::uint64_t position_;
};

// Inflates the `compressed_size` bytes that start at `position`.
class InflateSource : public ByteSource {
 public:
  InflateSource(std::ifstream* in, std::uint64_t position,
                std::uint64_t compressed_size);
  ~InflateSource() override;
  InflateSource(const InflateSource&) = delete;
  InflateSource& operator=(const InflateSource&) = delete;

  bool Read(unsigned char* out, std::size_t n) override;
  // True once inflate has failed on the compressed data themselves.
  bool Corrupted() const { return initialized_ && !ok_; }
  bool Skip(std::uint64_t n) override;

 private:
  bool Refill();

  std::ifstream* in_;
  std::uint64_t position_;
  std::uint64_t compressed_left_;
  z_stream stream_;
  bool initialized_ = false;
  bool ok_ = false;  // no inflate error yet
  unsigned char input_[16384];
};

}  // namespace mat_bytes
}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_MAT_BYTE_SOURCE_H_
