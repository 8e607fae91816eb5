#include "core/io/mat_file_check.h"

#include <algorithm>
#include <fstream>
#include <string>

#include "core/io/mat_byte_source.h"
#include "core/io/mat_v5_format.h"

namespace nrsfm {
namespace {

using namespace mat_bytes;  // words, sizes and the byte sources
using namespace mat_v5;     // the v5 codes

// Bytes per element of a v5 data type; 0 for a type that holds no numbers.
std::uint64_t SizeOfType(std::uint32_t type) {
  switch (type) {
    case kMiInt8:
    case kMiUint8:
    case kMiUtf8:
      return 1;
    case kMiInt16:
    case kMiUint16:
    case kMiUtf16:
      return 2;
    case kMiInt32:
    case kMiUint32:
    case kMiSingle:
    case kMiUtf32:
      return 4;
    case kMiDouble:
    case kMiInt64:
    case kMiUint64:
      return 8;
    default:
      return 0;
  }
}

// A data element's tag: type and byte count; a small element (byte count
// < 5 in the upper half of the first word) carries its payload in the tag.
struct Tag {
  std::uint32_t type = 0;
  std::uint64_t size = 0;
  bool small = false;
  unsigned char payload[4] = {0, 0, 0, 0};
};

// Walks the arrays of a v5 file (see the header).
class V5Walker {
 public:
  V5Walker(const std::string& path, bool big_endian)
      : path_(path), big_endian_(big_endian) {}

  // Whether the variable walked next is a compressed one (matio reads a
  // few things differently there).
  void SetCompressed(bool compressed) { compressed_ = compressed; }

  Status Corrupt(const std::string& what, const std::string& detail) const {
    return Status::Error(path_ + ": the .mat file is truncated or corrupt (" +
                         what + ": " + detail + ")");
  }

  // Reads a tag from the `*left` bytes that remain of its parent and takes
  // the tag (and a normal element's byte count) from them.
  Status ReadTag(ByteSource* source, const std::string& what,
                 std::uint64_t* left, Tag* tag) {
    unsigned char bytes[8];
    if (*left < 8 || !source->Read(bytes, 8)) {
      return Corrupt(what, "a tag runs past the end of its element");
    }
    *left -= 8;
    const std::uint32_t first = U32At(bytes, big_endian_);
    tag->small = (first >> 16) != 0;
    if (tag->small) {
      tag->type = first & 0xffff;
      tag->size = first >> 16;
      if (tag->size > 4) {
        return Corrupt(what, "a small data element claims " +
                                 std::to_string(tag->size) +
                                 " bytes (at most 4)");
      }
      std::copy(bytes + 4, bytes + 8, tag->payload);
      return Status::OK();
    }
    tag->type = first;
    tag->size = U32At(bytes + 4, big_endian_);
    if (tag->size > *left) {
      return Corrupt(what, "a data element claims " +
                               std::to_string(tag->size) +
                               " bytes, more than the " +
                               std::to_string(*left) + " left in its array");
    }
    return Status::OK();
  }

  // Skips the payload of a normal element (and its padding, when there).
  Status SkipPayload(ByteSource* source, const std::string& what,
                     const Tag& tag, std::uint64_t* left) {
    if (tag.small) return Status::OK();
    const std::uint64_t n = std::min(RoundUp8(tag.size), *left);
    if (!source->Skip(n)) return Corrupt(what, "its data cannot be read");
    *left -= n;
    return Status::OK();
  }

  // Walks one array (a miMATRIX element of `size` bytes) as matio reads it:
  // the array flags (16 bytes, whatever their tag says), the dimensions
  // (below), the name when its tag says miINT8 (or a
  // small miINT8 element of 1 to 4 bytes), then a cell's cells, a struct's
  // fields and, uncompressed, a function handle's arrays; a compressed
  // opaque object is not read into. At the top level (`name` and
  // `max_elements` given) it stops after the data tag of a numeric array;
  // nested, it reads the whole element.
  Status Array(ByteSource* source, const std::string& what, std::uint64_t size,
               int depth, std::string* name, std::uint64_t* max_elements,
               bool* numeric) {
    const bool top = name != nullptr;
    // [] in a cell or a struct field. (At the top level matio reads a
    // header whatever the size says: an empty one runs past its end.)
    if (size == 0 && !top) return Status::OK();
    if (depth > kMaxMatNesting) {
      return Corrupt(what, "arrays nested more than " +
                               std::to_string(kMaxMatNesting) + " deep");
    }
    std::uint64_t left = size;
    unsigned char head[16];
    if (left < 16 || !source->Read(head, 16)) {
      return Corrupt(what, "its array flags run past the end of its element");
    }
    left -= 16;
    // matio: empty when the flags' tag is not an integer
    std::uint32_t array_class = 0;
    const std::uint32_t flags_type = U32At(head, big_endian_);
    if (flags_type == kMiUint32 || flags_type == kMiInt32) {
      array_class = U32At(head + 8, big_endian_) & 0xff;
      if (array_class > kMxOpaque) array_class = 0;
    }
    if (array_class == kMxOpaque && compressed_)
      return SkipRest(source, what, top, left);

    unsigned char tag[8];
    if (left < 8 || !source->Read(tag, 8)) {
      return Corrupt(what, "a tag runs past the end of its element");
    }
    left -= 8;
    // The dimensions. Uncompressed, matio reads them under an miINT32 tag
    // (byte count / 4 of them and the padding) and goes on to the name
    // under any other; compressed, it reads the byte count padded to 8 (into
    // 4 bytes of memory per byte) under any tag whose low half says miINT32,
    // takes them as dimensions only under miINT32 itself, and fails the
    // variable under any other.
    const std::uint32_t dims_type = U32At(tag, big_endian_);
    const std::uint64_t dims_size = U32At(tag + 4, big_endian_);
    if (compressed_ && (dims_type & 0xffff) != kMiInt32) {
      return Corrupt(what, "invalid dimensions");
    }
    std::uint64_t count = 0;  // elements; 0 without dimensions
    if (compressed_ || dims_type == kMiInt32) {
      const std::uint64_t rank = dims_type == kMiInt32 ? dims_size / 4 : 0;
      const std::uint64_t bytes =
          compressed_ ? RoundUp8(dims_size) : 4 * rank + 4 * (rank % 2);
      if (bytes > left) {
        return Corrupt(what, "a data element claims " +
                                 std::to_string(dims_size) +
                                 " bytes, more than the " +
                                 std::to_string(left) + " left in its array");
      }
      count = rank > 0 ? 1 : 0;
      for (std::uint64_t i = 0; i < rank; ++i) {
        unsigned char dim[4];
        if (!source->Read(dim, 4))
          return Corrupt(what, "its dimensions cannot be read");
        count = SaturatingProduct(count, U32At(dim, big_endian_));
      }
      if (!source->Skip(bytes - 4 * rank))
        return Corrupt(what, "its dimensions cannot be read");
      left -= bytes;
    }

    if (left < 8 || !source->Read(tag, 8)) {
      return Corrupt(what, "a tag runs past the end of its element");
    }
    left -= 8;
    std::string array_name;
    const std::uint32_t name_type = U32At(tag, big_endian_);
    if (name_type == kMiInt8) {
      const std::uint64_t length = U32At(tag + 4, big_endian_);
      if (RoundUp8(length) > left) {
        return Corrupt(what, "a data element claims " + std::to_string(length) +
                                 " bytes, more than the " +
                                 std::to_string(left) + " left in its array");
      }
      // The name as matio returns it (up to the first NUL); only its first
      // 256 bytes are kept.
      const std::size_t kept =
          static_cast<std::size_t>(std::min<std::uint64_t>(length, 256));
      array_name.assign(kept, '\0');
      if (!source->Read(reinterpret_cast<unsigned char*>(array_name.data()),
                        kept) ||
          !source->Skip(RoundUp8(length) - kept)) {
        return Corrupt(what, "its name cannot be read");
      }
      left -= RoundUp8(length);
    } else if ((name_type & 0xffff) == kMiInt8 && (name_type >> 16) >= 1 &&
               (name_type >> 16) <= 4) {
      array_name.assign(reinterpret_cast<const char*>(tag + 4),
                        name_type >> 16);
    }
    array_name = array_name.substr(0, array_name.find('\0'));
    const std::string here = top ? "variable '" + array_name + "'" : what;
    if (top) *name = array_name;

    switch (array_class) {
      case kMxCell:
        return Children(source, here, count, "cells", left, depth);
      case kMxStruct:
        return Fields(source, here, count, left, depth);
      case kMxFunction:
        if (!compressed_)
          return Children(source, here, count, "arrays", left, depth);
        break;
      default:
        break;
    }
    if (top && array_class >= kMxDouble && array_class <= kMxUint64) {
      // What the data element holds (at most what is left of the array).
      *numeric = true;
      *max_elements = 0;
      if (left < 8 || !source->Read(tag, 8)) return Status::OK();
      const std::uint32_t first = U32At(tag, big_endian_);
      const bool small = (first >> 16) != 0;
      const std::uint64_t element = SizeOfType(small ? first & 0xffff : first);
      const std::uint64_t bytes =
          small
              ? std::min<std::uint64_t>(first >> 16, 4)
              : std::min<std::uint64_t>(U32At(tag + 4, big_endian_), left - 8);
      *max_elements = element == 0 ? 0 : bytes / element;
      return Status::OK();
    }
    // Sparse matrices, objects and the data of nested arrays: matio reads
    // them only when the array itself is read (never, nested, here).
    return SkipRest(source, here, top, left);
  }

  // The rest of an array: skipped when nested (the next one follows it); at
  // the top level the next variable's position comes from its tag.
  Status SkipRest(ByteSource* source, const std::string& what, bool top,
                  std::uint64_t left) {
    if (!top && !source->Skip(left))
      return Corrupt(what, "its data cannot be read");
    return Status::OK();
  }

  // `count` nested arrays (cells, or fields of struct elements) in `left`
  // bytes: each takes a tag at least.
  Status Children(ByteSource* source, const std::string& what,
                  std::uint64_t count, const std::string& kind,
                  std::uint64_t left, int depth) {
    if (count > left / 8) {
      return Corrupt(what, "it claims " + std::to_string(count) + " " + kind +
                               ", more than its " + std::to_string(left) +
                               " bytes can hold");
    }
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::string child = what + " element " + std::to_string(i + 1);
      Tag tag;
      NRSFM_RETURN_IF_ERROR(ReadTag(source, child, &left, &tag));
      if (tag.small || tag.type != kMiMatrix)
        return Corrupt(child, "not an array");
      NRSFM_RETURN_IF_ERROR(
          Array(source, child, tag.size, depth + 1, nullptr, nullptr, nullptr));
      left -= tag.size;
      const std::uint64_t padding =
          std::min(RoundUp8(tag.size) - tag.size, left);
      if (!source->Skip(padding))
        return Corrupt(child, "its data cannot be read");
      left -= padding;
    }
    if (!source->Skip(left)) return Corrupt(what, "its data cannot be read");
    return Status::OK();
  }

  // A struct's field name length, field names and `count` × fields
  // arrays.
  Status Fields(ByteSource* source, const std::string& what,
                std::uint64_t count, std::uint64_t left, int depth) {
    Tag tag;
    NRSFM_RETURN_IF_ERROR(ReadTag(source, what, &left, &tag));
    std::uint32_t name_length = 0;
    if (tag.small && tag.size == 4) {
      name_length = U32At(tag.payload, big_endian_);
    } else {
      unsigned char value[4];
      if (tag.small || tag.size != 4 || !source->Read(value, 4)) {
        return Corrupt(what, "invalid field name length");
      }
      left -= 4;
      const std::uint64_t padding = std::min<std::uint64_t>(4, left);
      if (!source->Skip(padding))
        return Corrupt(what, "invalid field name length");
      left -= padding;
      name_length = U32At(value, big_endian_);
    }
    NRSFM_RETURN_IF_ERROR(ReadTag(source, what, &left, &tag));
    if (tag.size > 0 && name_length == 0)
      return Corrupt(what, "field names of length 0");
    const std::uint64_t fields = name_length == 0 ? 0 : tag.size / name_length;
    NRSFM_RETURN_IF_ERROR(SkipPayload(source, what, tag, &left));
    return Children(source, what, SaturatingProduct(count, fields), "fields",
                    left, depth);
  }

 private:
  const std::string& path_;
  bool big_endian_;
  bool compressed_ = false;
};

// True when the 128-byte header marks a v5 or v7.3 file, as matio decides:
// bytes 126..127 "IM" or "MI", version 0x0100 or 0x0200 at bytes 124..125.
// matio treats every other file as v4. Sets the version and byte order.
bool HasV5Header(const unsigned char* header, int* version, bool* big_endian) {
  const bool little = header[126] == 'I' && header[127] == 'M';
  *big_endian = header[126] == 'M' && header[127] == 'I';
  if (!little && !*big_endian) return false;
  *version = little ? header[124] | (header[125] << 8)
                    : (header[124] << 8) | header[125];
  return *version == 0x0100 || *version == 0x0200;
}

// The variables of a v5 file, one element after the other from byte 128.
Status WalkV5(const std::string& path, std::ifstream* in,
              std::uint64_t file_size, bool big_endian, MatFileClaims* claims) {
  V5Walker walker(path, big_endian);
  std::uint64_t offset = 128;
  for (int index = 1; file_size - offset >= 8; ++index) {
    const std::string what = "variable " + std::to_string(index) + " at byte " +
                             std::to_string(offset);
    unsigned char bytes[8];
    in->clear();
    in->seekg(static_cast<std::streamoff>(offset));
    if (!in->read(reinterpret_cast<char*>(bytes), 8)) break;
    const std::uint32_t type = U32At(bytes, big_endian);
    const std::uint64_t size = U32At(bytes + 4, big_endian);
    // matio reads no further than an element it does not know.
    if (type != kMiMatrix && type != kMiCompressed) break;
    const std::uint64_t in_file = file_size - offset - 8;
    if (size > in_file) {
      return walker.Corrupt(
          what, "it claims " + std::to_string(size) + " bytes, more than the " +
                    std::to_string(in_file) + " left in the file");
    }
    std::string name;
    std::uint64_t max_elements = 0;
    bool numeric = false;
    walker.SetCompressed(type == kMiCompressed);
    if (type == kMiMatrix) {
      FileSource source(in, offset + 8);
      NRSFM_RETURN_IF_ERROR(
          walker.Array(&source, what, size, 0, &name, &max_elements, &numeric));
    } else {
      InflateSource source(in, offset + 8, size);
      std::uint64_t left = kU64Max;
      Tag tag;
      const std::string inflated = what + " (compressed)";
      const Status tagged = walker.ReadTag(&source, inflated, &left, &tag);
      if (!tagged.ok() && source.Corrupted()) {
        return walker.Corrupt(inflated,
                              "its compressed data cannot be inflated");
      }
      NRSFM_RETURN_IF_ERROR(tagged);
      if (tag.small || tag.type != kMiMatrix) {
        return walker.Corrupt(inflated, "it does not hold an array");
      }
      if (tag.size > kMaxDeflateRatio * size) {
        return walker.Corrupt(
            inflated, "it claims " + std::to_string(tag.size) +
                          " bytes inflated from " + std::to_string(size) +
                          ", more than deflate can give (" +
                          std::to_string(kMaxDeflateRatio) + ":1)");
      }
      const Status walked = walker.Array(&source, inflated, tag.size, 0, &name,
                                         &max_elements, &numeric);
      if (!walked.ok() && source.Corrupted()) {
        return walker.Corrupt(inflated,
                              "its compressed data cannot be inflated");
      }
      NRSFM_RETURN_IF_ERROR(walked);
    }
    if (numeric) claims->max_elements.emplace(name, max_elements);
    offset += 8 + size;
  }
  return Status::OK();
}

// The records of a v4 file, as matio reads them (see the header).
Status WalkV4(const std::string& path, std::ifstream* in,
              std::uint64_t file_size, MatFileClaims* claims) {
  const std::string not_mat =
      path + ": not a MATLAB .mat file (v4, v5 or v7.3)";
  const std::string corrupt =
      path + ": the .mat file is truncated or corrupt (";
  std::uint64_t offset = 0;
  for (int record = 1; offset < file_size; ++record) {
    const std::string at = "variable " + std::to_string(record) +
                           " of a v4 file at byte " + std::to_string(offset);
    unsigned char h[20];
    in->clear();
    in->seekg(static_cast<std::streamoff>(offset));
    if (file_size - offset < sizeof(h) ||
        !in->read(reinterpret_cast<char*>(h), sizeof(h))) {
      return Status::Error(
          record == 1 ? not_mat : corrupt + "truncated header of " + at + ")");
    }
    // matio: the type MOPT as stored, byte-swapped when it is not in
    // 0..4052; then the thousands digit M says the byte order of the other
    // fields (0 little-endian, 1 big-endian) and imagf is read as stored.
    std::int32_t type = I32At(h, false);
    if (type < 0 || type > 4052) type = I32At(h, true);
    const int m = type / 1000, o = type / 100 % 10, p = type / 10 % 10,
              t = type % 10;
    const bool big_endian = m == 1;
    const std::int32_t rows = I32At(h + 4, big_endian);
    const std::int32_t cols = I32At(h + 8, big_endian);
    const bool complex = I32At(h + 12, false) != 0;
    const std::int32_t name_length = I32At(h + 16, big_endian);
    if (type < 0 || type > 4052 || m > 1 || o != 0 || p > 5 || t > 2 ||
        rows < 0 || cols < 0 || (complex && t == 1) || name_length < 1) {
      return Status::Error(
          record == 1 ? not_mat : corrupt + "invalid header of " + at + ")");
    }
    static constexpr std::uint64_t kElementSize[] = {8, 4, 4, 2, 2, 1};
    const std::uint64_t left = file_size - offset - sizeof(h);
    if (std::uint64_t(name_length) > left) {
      return Status::Error(corrupt + "the name of " + at +
                           " runs past the end of the file)");
    }
    std::string name(static_cast<std::size_t>(name_length), '\0');
    if (!in->read(name.data(), name_length)) {
      return Status::Error(corrupt + "the name of " + at + " cannot be read)");
    }
    name = name.substr(0, name.find('\0'));
    const std::uint64_t element = kElementSize[p] * (complex ? 2 : 1);
    const std::uint64_t data = SaturatingProduct(
        SaturatingProduct(std::uint64_t(rows), std::uint64_t(cols)), element);
    // Data that run past the end are an error of the whole file: matio
    // seeks past them to the next record, and when that seek fails (an
    // offset beyond what the file system allows) it reads the next record
    // from within the data instead.
    if (data > left - name_length) {
      return Status::Error(corrupt + "variable '" + name +
                           "' claims a size of " + std::to_string(rows) +
                           " x " + std::to_string(cols) + ", more than the " +
                           std::to_string(left - name_length) +
                           " bytes after its name hold)");
    }
    claims->max_elements.emplace(name, data / element);
    offset += sizeof(h) + name_length + data;
  }
  return Status::OK();
}

}  // namespace

Status CheckMatFileClaims(const std::string& path, std::uint64_t file_size,
                          MatFileClaims* claims) {
  claims->max_elements.clear();
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path + ": cannot open the file for reading");
  unsigned char header[128];
  int version = 0;
  bool big_endian = false;
  if (file_size >= 128 &&
      in.read(reinterpret_cast<char*>(header), sizeof(header)) &&
      HasV5Header(header, &version, &big_endian)) {
    if (version == 0x0200) return Status::OK();  // v7.3: HDF5
    return WalkV5(path, &in, file_size, big_endian, claims);
  }
  return WalkV4(path, &in, file_size, claims);
}

}  // namespace nrsfm
