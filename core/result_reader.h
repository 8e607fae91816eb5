// Reads back what core/result_writer.h writes, so that a result directory
// can serve as ground truth or as the estimate (`nrsfm evaluate`).
#ifndef NRSFM_CORE_RESULT_READER_H_
#define NRSFM_CORE_RESULT_READER_H_

#include <string>

#include "core/ground_truth.h"
#include "core/status.h"

namespace nrsfm {

// Reads the camera-frame points of camera `camera` from points_camera.csv
// (header frame,camera,point,x,y,z). `path` is the CSV file or a result
// directory that holds it. F and P are the largest frame and point index + 1;
// every (frame, point) of that camera must appear exactly once. Sets
// truth->source to "points_camera.csv". Fails on a missing file, a wrong
// header or field, non-integer or negative indices, a duplicate or missing
// (frame, point), non-finite coordinates, or no row for `camera`.
Status ReadPointsCameraCsv(const std::string& path, int camera,
                           GroundTruth* truth);

}  // namespace nrsfm

#endif  // NRSFM_CORE_RESULT_READER_H_
