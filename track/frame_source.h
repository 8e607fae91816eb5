// The frames of a video or of a folder of images, read one at a time, so a
// long sequence never sits in memory at once (OpenCV's imgcodecs and videoio
// decode; its types appear in no header outside track/).
//
// A folder (ListFrameFiles, track/tracks.h): every file with an image
// extension (.png .jpg .jpeg .bmp .tif .tiff .pgm .ppm .webp, any case);
// each file's frame number is the last run of digits in its name, and the
// frames are in the order of that number (by name for zero-padded names).
// A video: frames 0, 1, … in decoding order.
// Frames are returned as 8-bit grey, all of the size of the first frame.
// Errors (one line naming the file): a missing or empty folder, a file name
// without a number or a number twice, a file that does not decode, frames of
// another size, a video OpenCV cannot open or that holds no frame.
#ifndef NRSFM_TRACK_FRAME_SOURCE_H_
#define NRSFM_TRACK_FRAME_SOURCE_H_

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/model/status.h"
#include "track/tracks.h"  // ListFrameFiles

namespace nrsfm {
namespace track {

// OpenCV and FFmpeg log their own failures (a file that does not decode, …)
// to stderr; the errors here say what matters. A main() calls this, before
// any video is opened, to keep both quiet (the library never does: logging
// is the program's choice).
void QuietOpenCvLog();

class FrameSource {
 public:
  // A folder of images: `path` names it. The frames are listed, and the
  // first one decoded for its size.
  static Status OpenFolder(const std::string& path, FrameSource* source);
  // A video file, through OpenCV's FFmpeg backend; the whole file is read
  // once to count its frames (a container's frame count is not to be
  // trusted).
  static Status OpenVideo(const std::string& path, FrameSource* source);
  // Images held by the caller (the Python module, tests): all of one size,
  // 8-bit grey or BGR; frame numbers 0, 1, ….
  static Status FromImages(std::vector<cv::Mat> images, FrameSource* source);

  FrameSource();
  ~FrameSource();
  FrameSource(FrameSource&&) noexcept;
  FrameSource& operator=(FrameSource&&) noexcept;

  int num_frames() const { return static_cast<int>(numbers_.size()); }
  // The frame number of each index (the outputs' `frame`).
  const std::vector<int>& frame_numbers() const { return numbers_; }
  // Width and height in pixels.
  cv::Size size() const { return size_; }
  // Where the frames come from, for messages.
  const std::string& name() const { return name_; }
  // The name of frame `index` for messages (the file, or "<video> frame i").
  std::string FrameName(int index) const;

  // Frame `index` (0 ≤ index < num_frames()) as 8-bit grey. Reading in
  // increasing order is the fast path (a video is decoded forward; going
  // back reopens it).
  Status Read(int index, cv::Mat* grey);

 private:
  struct Video;
  std::string name_;
  std::vector<std::string> files_;  // a folder's files, in frame order
  std::vector<cv::Mat> images_;     // FromImages
  std::unique_ptr<Video> video_;
  std::vector<int> numbers_;
  cv::Size size_;
};

}  // namespace track
}  // namespace nrsfm

#endif  // NRSFM_TRACK_FRAME_SOURCE_H_
