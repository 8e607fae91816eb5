#include "core/io/mat_byte_source.h"

#include <algorithm>

namespace nrsfm {
namespace mat_bytes {

bool FileSource::Read(unsigned char* out, std::size_t n) {
  in_->clear();
  in_->seekg(static_cast<std::streamoff>(position_));
  if (!in_->read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n)))
    return false;
  position_ += n;
  return true;
}

InflateSource::InflateSource(std::ifstream* in, std::uint64_t position,
                             std::uint64_t compressed_size)
    : in_(in), position_(position), compressed_left_(compressed_size) {
  stream_.zalloc = Z_NULL;
  stream_.zfree = Z_NULL;
  stream_.opaque = Z_NULL;
  stream_.next_in = Z_NULL;
  stream_.avail_in = 0;
  initialized_ = inflateInit(&stream_) == Z_OK;
  ok_ = initialized_;
}

InflateSource::~InflateSource() {
  if (initialized_) inflateEnd(&stream_);
}

bool InflateSource::Read(unsigned char* out, std::size_t n) {
  if (!ok_) return false;
  stream_.next_out = out;
  stream_.avail_out = static_cast<uInt>(n);
  while (stream_.avail_out > 0) {
    if (stream_.avail_in == 0 && !Refill()) return false;
    const int result = inflate(&stream_, Z_NO_FLUSH);
    if (result == Z_STREAM_END) return stream_.avail_out == 0;
    if (result != Z_OK && result != Z_BUF_ERROR) return ok_ = false;
  }
  return true;
}

bool InflateSource::Skip(std::uint64_t n) {
  unsigned char scratch[16384];
  while (n > 0) {
    const std::size_t chunk =
        static_cast<std::size_t>(std::min<std::uint64_t>(n, sizeof(scratch)));
    if (!Read(scratch, chunk)) return false;
    n -= chunk;
  }
  return true;
}

bool InflateSource::Refill() {
  if (compressed_left_ == 0) return false;
  const std::size_t chunk = static_cast<std::size_t>(
      std::min<std::uint64_t>(compressed_left_, sizeof(input_)));
  in_->clear();
  in_->seekg(static_cast<std::streamoff>(position_));
  if (!in_->read(reinterpret_cast<char*>(input_),
                 static_cast<std::streamsize>(chunk))) {
    return false;
  }
  position_ += chunk;
  compressed_left_ -= chunk;
  stream_.next_in = input_;
  stream_.avail_in = static_cast<uInt>(chunk);
  return true;
}

}  // namespace mat_bytes
}  // namespace nrsfm
