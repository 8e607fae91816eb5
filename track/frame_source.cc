#include "track/frame_source.h"

#include <glog/logging.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <utility>

namespace nrsfm {
namespace track {
namespace {

namespace fs = std::filesystem;

std::string SizeString(const cv::Size& size) {
  return std::to_string(size.width) + " x " + std::to_string(size.height);
}

Status ToGrey(const cv::Mat& image, const std::string& name, cv::Mat* grey) {
  if (image.empty()) return Status::Error(name + ": cannot decode the image");
  if (image.depth() != CV_8U ||
      (image.channels() != 1 && image.channels() != 3 &&
       image.channels() != 4)) {
    return Status::Error(name + ": expected an 8-bit grey, BGR or BGRA image");
  }
  if (image.channels() == 1) {
    *grey = image;
  } else {
    cv::cvtColor(
        image, *grey,
        image.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  }
  return Status::OK();
}

// A file decoded as 8-bit grey; empty when it does not decode (OpenCV throws
// on some malformed files).
cv::Mat DecodeGrey(const std::string& file) {
  try {
    return cv::imread(file, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    return cv::Mat();
  }
}

}  // namespace

void QuietOpenCvLog() {
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  // FFmpeg's own messages ("moov atom not found"): panics only (OpenCV
  // reads the variable when it first opens a video; a caller's value stays).
  setenv("OPENCV_FFMPEG_LOGLEVEL", "0", /*overwrite=*/0);
}

struct FrameSource::Video {
  std::string path;
  cv::VideoCapture capture;
  int next = 0;  // the index the next read() returns

  Status Reopen() {
    capture.release();
    // FFmpeg only (Debian's backend: .mp4, .avi, .mkv, .mov, …): the others
    // OpenCV would try (GStreamer, cameras) probe devices and leak.
    if (!capture.open(path, cv::CAP_FFMPEG)) {
      return Status::Error(path + ": cannot open the video (no decoder?)");
    }
    next = 0;
    return Status::OK();
  }
};

FrameSource::FrameSource() = default;
FrameSource::~FrameSource() = default;
FrameSource::FrameSource(FrameSource&&) noexcept = default;
FrameSource& FrameSource::operator=(FrameSource&&) noexcept = default;

Status FrameSource::OpenFolder(const std::string& path, FrameSource* source) {
  std::vector<FrameFile> listed;
  NRSFM_RETURN_IF_ERROR(ListFrameFiles(path, &listed));
  FrameSource result;
  result.name_ = path;
  for (const FrameFile& frame : listed) {
    result.numbers_.push_back(frame.number);
    result.files_.push_back(frame.path);
  }
  cv::Mat first;
  NRSFM_RETURN_IF_ERROR(
      ToGrey(DecodeGrey(result.files_[0]), result.files_[0], &first));
  result.size_ = first.size();
  *source = std::move(result);
  return Status::OK();
}

Status FrameSource::OpenVideo(const std::string& path, FrameSource* source) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    return Status::Error(path + ": no such video file");
  }
  FrameSource result;
  result.name_ = path;
  result.video_ = std::make_unique<Video>();
  result.video_->path = path;
  NRSFM_RETURN_IF_ERROR(result.video_->Reopen());
  cv::Mat frame;
  int count = 0;
  while (result.video_->capture.read(frame)) {
    if (count == 0) result.size_ = frame.size();
    ++count;
  }
  if (count == 0) return Status::Error(path + ": the video holds no frame");
  for (int i = 0; i < count; ++i) result.numbers_.push_back(i);
  NRSFM_RETURN_IF_ERROR(result.video_->Reopen());
  *source = std::move(result);
  return Status::OK();
}

Status FrameSource::FromImages(std::vector<cv::Mat> images,
                               FrameSource* source) {
  if (images.empty()) return Status::Error("frames: no image given");
  FrameSource result;
  result.name_ = "frames";
  for (std::size_t i = 0; i < images.size(); ++i) {
    cv::Mat grey;
    NRSFM_RETURN_IF_ERROR(
        ToGrey(images[i], "frames[" + std::to_string(i) + "]", &grey));
    if (i > 0 && grey.size() != result.size_) {
      return Status::Error(
          "frames[" + std::to_string(i) + "]: " + SizeString(grey.size()) +
          ", but the first frame is " + SizeString(result.size_));
    }
    result.size_ = grey.size();
    result.images_.push_back(grey);
    result.numbers_.push_back(static_cast<int>(i));
  }
  *source = std::move(result);
  return Status::OK();
}

std::string FrameSource::FrameName(int index) const {
  if (!files_.empty()) return files_[index];
  return name_ + " frame " + std::to_string(index);
}

Status FrameSource::Read(int index, cv::Mat* grey) {
  CHECK(index >= 0 && index < num_frames()) << "frame index " << index;
  cv::Mat image;
  if (!images_.empty()) {
    *grey = images_[index];
    return Status::OK();
  }
  if (video_ != nullptr) {
    if (index < video_->next) NRSFM_RETURN_IF_ERROR(video_->Reopen());
    while (video_->next <= index) {
      if (!video_->capture.read(image)) {
        return Status::Error(FrameName(video_->next) +
                             ": cannot decode the frame");
      }
      ++video_->next;
    }
  } else {
    image = DecodeGrey(files_[index]);
  }
  NRSFM_RETURN_IF_ERROR(ToGrey(image, FrameName(index), grey));
  if (grey->size() != size_) {
    return Status::Error(FrameName(index) + ": " + SizeString(grey->size()) +
                         ", but the first frame is " + SizeString(size_));
  }
  return Status::OK();
}

}  // namespace track
}  // namespace nrsfm
