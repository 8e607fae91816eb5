#include "tools/view_frame_images.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "track/tracks.h"

namespace nrsfm {
namespace tools {
namespace {

namespace fs = std::filesystem;

std::string Str(int value) { return std::to_string(value); }

// RFC 4648 base64 of `bytes`, with padding.
std::string Base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size())
      v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace

Status AddFrameImages(const ViewDataOptions& options, ViewData* data) {
  const std::string& dir = options.frames_dir;
  if (data->num_cameras != 1) {
    return Status::Error("--frames_dir '" + dir + "': the result has " +
                         Str(data->num_cameras) +
                         " cameras; frames are drawn for one camera");
  }
  std::vector<track::FrameFile> files;
  NRSFM_RETURN_IF_ERROR(
      track::ListFrameFiles(dir, &files).WithContext("--frames_dir"));
  if (static_cast<int>(files.size()) != data->num_frames) {
    return Status::Error(
        "--frames_dir '" + dir + "' holds " +
        Str(static_cast<int>(files.size())) +
        " frames but the result has F = " + Str(data->num_frames));
  }
  for (const track::FrameFile& file : files) {
    std::string ext = fs::path(file.path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    const char* mime = ext == ".png"                     ? "image/png"
                       : ext == ".jpg" || ext == ".jpeg" ? "image/jpeg"
                       : ext == ".bmp"                   ? "image/bmp"
                       : ext == ".webp"                  ? "image/webp"
                                                         : nullptr;
    if (mime == nullptr) {
      return Status::Error("--frames_dir: " + file.path +
                           ": a page shows PNG, JPEG, BMP or WebP frames");
    }
    std::ifstream in(file.path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)),
                            std::istreambuf_iterator<char>());
    if (!in && !in.eof()) {
      return Status::Error("--frames_dir: " + file.path + ": cannot read it");
    }
    data->frame_images.push_back(std::string("data:") + mime + ";base64," +
                                 Base64(bytes));
  }
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
