// Reads back what core/io/result_writer.h writes, so that a result directory
// can serve as ground truth or as the estimate (`nrsfm evaluate`).
#ifndef NRSFM_CORE_IO_RESULT_READER_H_
#define NRSFM_CORE_IO_RESULT_READER_H_

#include <Eigen/Core>
#include <string>

#include "core/io/ground_truth.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

// Reads the camera-frame points of camera `camera` from points_camera.csv
// (header frame,camera,point,x,y,z). `path` is the CSV file or a result
// directory that holds it. F and P are the largest frame and point index + 1;
// every (frame, point) of that camera must appear exactly once. Sets
// truth->source to "points_camera.csv". Fails on a missing file, a wrong
// header or field, non-integer or negative indices, a duplicate or missing
// (frame, point), coordinates of which some but not all are NaN (all three
// NaN: a point or frame left out of the reconstruction, kept as NaN), or no
// row for `camera`.
Status ReadPointsCameraCsv(const std::string& path, int camera,
                           GroundTruth* truth);

// Reads a whole result directory `dir` as the estimate of an evaluation:
// camera `camera`'s points (ReadPointsCameraCsv), the object-frame shapes
// S_t of points_object.csv (header frame,point,x,y,z; every (frame, point)
// of the camera's F and P exactly once) and camera `camera`'s rotations of
// rotations.csv (header frame,camera,r11..r33; every frame once; each a
// rotation to 1e-6, or all NaN for a left-out frame). Sets shapes->source
// to "result". Fails, naming the file and row, like ReadPointsCameraCsv.
Status ReadResultShapes(const std::string& dir, int camera,
                        GroundTruth* shapes);

// Reads camera `camera`'s point covariances of points_covariance.csv in
// result directory `dir` (header frame,camera,point,xx,xy,xz,yy,yz,zz;
// core/io/result_writer.h WriteCovariances) for F frames and P points:
// covariances[t · P + p]. Fails, naming the file and row, on a wrong header
// or field, an index outside F × P, a duplicate or missing (frame, point).
Status ReadPointsCovarianceCsv(const std::string& dir, int camera,
                               int num_frames, int num_points,
                               std::vector<Eigen::Matrix3d>* covariances);

// The number of basis shapes K of a result directory: result.json's
// "num_bases". Fails, naming the file, when it is missing, not JSON, or has
// no integer num_bases ≥ 1.
Status ReadResultNumBases(const std::string& dir, int* num_bases);

// The camera model of a result directory's result.json ("camera"; weak
// perspective when the file or the key is absent) and, for a perspective
// result, its "intrinsics": M rows [fx, fy, cx, cy] in pixels, fx, fy > 0,
// as 4 × M. Fails, naming the file, on JSON that is not an object or a
// perspective result without valid intrinsics.
Status ReadResultCamera(const std::string& dir, CameraModel* camera,
                        Eigen::Matrix4Xd* intrinsics);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_RESULT_READER_H_
