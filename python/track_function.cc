// nrsfm.track() (python/functions.h): frames, queries and mask from Python
// objects, the tracker (track/tracker.h), the tracks as arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "python/convert.h"
#include "python/functions.h"
#include "python/keywords.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"
#include "track/tracker.h"

namespace nrsfm {
namespace python {

using tools::CommandFlags;

namespace {

// Frames from an (F, H, W) or (F, H, W, 3) uint8 array (BGR, as OpenCV's).
track::FrameSource FramesOfArray(py::handle object, const char* what) {
  const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>
      array =
          py::array_t<std::uint8_t, py::array::c_style |
                                        py::array::forcecast>::ensure(object);
  if (!array ||
      (array.ndim() != 3 && !(array.ndim() == 4 && array.shape(3) == 3))) {
    ThrowValueError(std::string(what) +
                    ": expected a folder, a video file or an (F, H, W) or "
                    "(F, H, W, 3) uint8 array");
  }
  std::vector<cv::Mat> images;
  const int height = static_cast<int>(array.shape(1));
  const int width = static_cast<int>(array.shape(2));
  const int channels = array.ndim() == 4 ? 3 : 1;
  const std::size_t frame_bytes =
      static_cast<std::size_t>(height) * width * channels;
  for (py::ssize_t f = 0; f < array.shape(0); ++f) {
    cv::Mat image(height, width, channels == 3 ? CV_8UC3 : CV_8UC1,
                  const_cast<std::uint8_t*>(array.data()) + f * frame_bytes);
    images.push_back(image.clone());
  }
  track::FrameSource source;
  Check(track::FrameSource::FromImages(std::move(images), &source)
            .WithContext(what));
  return source;
}

track::FrameSource FramesOf(py::handle object, const char* what) {
  if (!IsPath(object)) return FramesOfArray(object, what);
  const std::string path = PathOf(object, what);
  track::FrameSource source;
  std::error_code ec;
  const Status status = std::filesystem::is_directory(path, ec)
                            ? track::FrameSource::OpenFolder(path, &source)
                            : track::FrameSource::OpenVideo(path, &source);
  if (!status.ok()) ThrowFileError(path, status, /*directory_allowed=*/true);
  return source;
}

}  // namespace

Tracks Track(py::handle frames_object, py::handle queries_object,
             py::handle mask_object, const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(TrackOptionsOf(), "track", kwargs, &flags);
  tools::FlagTargets targets;
  Check(tools::ApplyFlags(flags, &targets));
  track::FrameSource frames = FramesOf(frames_object, "frames");
  track::FrameSource mask;
  const bool has_mask = !mask_object.is_none();
  if (has_mask) mask = FramesOf(mask_object, "mask");
  std::vector<track::Query> queries;
  if (IsPath(queries_object)) {
    const std::string path = PathOf(queries_object, "queries");
    const Status status = track::ReadQueries(path, &queries);
    if (!status.ok()) ThrowFileError(path, status);
  } else if (!queries_object.is_none()) {
    const Eigen::MatrixXd table = ToMatrix(queries_object, "queries");
    if (table.cols() != 4) {
      ThrowValueError(
          "queries: expected an (N, 4) array of point, frame, x, "
          "y, got " +
          std::to_string(table.cols()) + " columns");
    }
    for (Eigen::Index r = 0; r < table.rows(); ++r) {
      if (table(r, 0) != std::floor(table(r, 0)) ||
          table(r, 1) != std::floor(table(r, 1)) || table(r, 0) < 0) {
        ThrowValueError("queries: row " + std::to_string(r) +
                        ": point and frame must be integers, point >= 0");
      }
      queries.push_back({static_cast<int>(table(r, 0)),
                         static_cast<int>(table(r, 1)), table(r, 2),
                         table(r, 3)});
    }
  }
  track::Tracks result;
  {
    py::gil_scoped_release release;
    const Status status =
        track::TrackPoints(&frames, has_mask ? &mask : nullptr, queries,
                           targets.track, nullptr, &result);
    py::gil_scoped_acquire acquire;
    Check(status);
  }
  const Eigen::Index num_frames = result.x.rows(), num_points = result.x.cols();
  Array w = NewArray({2 * num_frames, num_points});
  Array positions = NewArray({num_frames, num_points, 2});
  py::array_t<bool> visible({num_frames, num_points});
  auto wa = w.mutable_unchecked<2>();
  auto pa = positions.mutable_unchecked<3>();
  auto va = visible.mutable_unchecked<2>();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Eigen::Index f = 0; f < num_frames; ++f) {
    for (Eigen::Index p = 0; p < num_points; ++p) {
      const bool seen = result.visible(f, p) != 0;
      va(f, p) = seen;
      wa(2 * f, p) = seen ? result.x(f, p) : nan;
      wa(2 * f + 1, p) = seen ? result.y(f, p) : nan;
      pa(f, p, 0) = result.x(f, p);
      pa(f, p, 1) = result.y(f, p);
    }
  }
  Tracks tracks;
  tracks.W = w;
  tracks.mask = visible;
  tracks.positions = positions;
  tracks.frame_ids = py::cast(result.frame_numbers);
  tracks.point_ids = py::cast(result.point_ids);
  return tracks;
}

}  // namespace python
}  // namespace nrsfm
