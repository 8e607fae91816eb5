// Writes a reconstruction into one directory (docs/guide.md, "Outputs").
//
// Files (indices 0-based; numbers in the shortest form that reads back to
// the same double, core/io/text_io.h TextWriter):
//   points_camera.csv  frame,camera,point,x,y,z   X_tc = s_tc R_tc S_t
//                      (perspective: R_tc S_t + [T_tc; t_z,tc]), for
//                      every frame, camera and point (missing ones too);
//                      F·M·P rows, frame-major, then camera, then point.
//   points_object.csv  frame,point,x,y,z          S_t (object frame).
//   rotations.csv      frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33
//                      R_tc row by row (rotation_cam_from_object).
//   translations.csv   frame,camera,tx,ty,scale   T_tc and s_tc, so that
//                      w_tcp = Π X_tc[:,p] + T_tc reproduces W;
//                      perspective: frame,camera,tx,ty,tz, and W is
//                      (fx x / z + cx, fy y / z + cy) of X_tc with
//                      result.json's "intrinsics" (core/model/model.h).
//   weights.csv        frame,l1..lK               l_t (column l(k+1) weighs
//                                                 basis shape k).
//   basis.csv          k,point,x,y,z              S_k, k = 0..K-1.
//   result.json        the report below plus F, M, P, K, the number of
//                      visible entries and library versions (NaN → null);
//                      "input_frames" / "input_points" when the measurements
//                      have frame_ids / point_ids (the input's index of each
//                      frame and point; every index in the files is the
//                      result's, 0…F−1 and 0…P−1).
// Points and frames left out of a reconstruction (report.dropped_points /
// dropped_frames) are NaN in the model and written as "nan" in the CSV and
// PLY files; any other NaN in the model is an error.
//   ply/frame_00000.ply …  with WriteOptions::write_ply: ASCII PLY of each
//                      frame's points in camera 0's frame (P vertices).
//
// The files are written into a fresh hidden sibling directory
// (".<name>.tmp-XXXXXX") that is renamed to DIR only when everything has
// been written, so a failure never leaves a partial DIR that looks complete.
#ifndef NRSFM_CORE_IO_RESULT_WRITER_H_
#define NRSFM_CORE_IO_RESULT_WRITER_H_

#include <string>
#include <utility>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

// One optimisation stage (e.g. a Ceres solve) as reported in result.json.
struct StageReport {
  std::string name;
  double initial_cost = 0;  // cost before the stage (solver units)
  double final_cost = 0;    // cost after the stage
  int iterations = 0;
  double seconds = 0;  // wall time
};

struct ReconstructionReport {
  std::string input;  // input path
  std::vector<std::pair<std::string, std::string>>
      options;  // options used, key/value
  std::string
      start_used;  // the start kept: "factorization" | "rigid" | "triple"
  double start_reprojection_rms = 0;  // of the start, input units
  std::vector<StageReport> stages;
  double reprojection_rms = 0;  // final, input units
  bool solution_usable = true;
  std::vector<std::string> warnings;
  // Points and frames left out of the solve
  // (solvers/pipeline/drop_unobserved.h), written as "dropped_points" and
  // "dropped_frames" (0-based indices).
  std::vector<int> dropped_points;
  std::vector<int> dropped_frames;
  // The extra terms' weights the refinement used, e.g. {"temporal_shape", 1}
  // (chosen by the prior rule or given), and what the data measured for the
  // rule and the warnings, e.g. {"track_step", 0.08}
  // (solvers/pipeline/prior_rule.h).
  std::vector<std::pair<std::string, double>> term_weights;
  std::vector<std::pair<std::string, double>> diagnostics;
  std::vector<std::pair<std::string, double>> metrics;  // e.g. {"e3d", 0.03}
  std::string
      e3d_frame;  // "object" | "camera" (core/eval/metrics.h), "" = no metrics
  // Versions of the caller's libraries, e.g. {"nrsfm", "0.1.0"},
  // {"ceres", CERES_VERSION_STRING}; the writer adds eigen, matio and
  // nlohmann_json itself.
  std::vector<std::pair<std::string, std::string>> versions;
};

struct WriteOptions {
  bool write_ply = false;  // also write ply/frame_NNNNN.ply
  // Replace an existing non-empty DIR. Only a directory that holds a
  // result.json (an earlier result) is replaced, never another directory.
  bool overwrite = true;
  // With 2 or more, the two points files are written side by side (the
  // same bytes as with 1).
  int num_threads = 1;
};

// The text of result.json (indented JSON, NaN → null) for a model of
// `measurements` and its report: what WriteReconstruction writes.
std::string ReconstructionJson(const Measurements& measurements,
                               const Model& model,
                               const ReconstructionReport& report);

// Fails (writing nothing) when the model is invalid or its sizes differ from
// the measurements', when DIR is a file, when DIR is non-empty and overwrite
// is false or DIR holds no result.json, and when the parent of DIR cannot be
// created or written.
Status WriteReconstruction(const std::string& dir,
                           const Measurements& measurements, const Model& model,
                           const ReconstructionReport& report,
                           const WriteOptions& options);

// Adds the covariances of --uncertainty to the result directory DIR (written
// by WriteReconstruction): points_covariance.csv, header
// frame,camera,point,xx,xy,xz,yy,yz,zz, the 3 × 3 covariance of each point
// of points_camera.csv (its units², frame centred), and
// rotations_covariance.csv, frame,camera,xx,…,zz, of each rotation's
// body-frame perturbation (radians²). points[(t · M + c) · P + p],
// rotations[t · M + c]; NaN for what was left out. CHECKs the sizes.
Status WriteCovariances(const std::string& dir, int num_frames, int num_cameras,
                        int num_points,
                        const std::vector<Eigen::Matrix3d>& points,
                        const std::vector<Eigen::Matrix3d>& rotations);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_RESULT_WRITER_H_
