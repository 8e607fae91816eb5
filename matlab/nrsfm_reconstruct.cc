// nrsfm_reconstruct: the reconstruction of `nrsfm reconstruct` as a MEX
// function for Octave (mkoctfile --mex) and MATLAB (mex); docs/matlab.md.
//
//   [model, info] = nrsfm_reconstruct(W, K, 'Name', value, ...)
//
// W      2FM x P double, rows 2(tM + c) + 1, 2(tM + c) + 2 (1-based) = u, v
//        of frame t, camera c (t, c 0-based); NaN = missing (both
//        coordinates). The layout of the Akhter et al. files' W.
// K      the number of basis shapes, a positive integer, or 'auto'.
// Names  (case-insensitive) every option of the Python module's
//        nrsfm.reconstruct, which are the tool's flags (init, priors,
//        robust, robust_scale, max_iterations, threads, linear_solver,
//        seed, K_max, K_threshold and the extra terms' weights:
//        temporal_shape, ...), with a char value for a text option, a
//        numeric or logical scalar otherwise; and
//          'mask'                FM x P or 2FM x P, nonzero = visible;
//          'cameras'             M, the number of synchronised cameras (1);
//          'observation_weights' FM x P relative weights of the
//                                observations' residuals (scaled to average
//                                1 over the visible ones, as the tool's
//                                --confidence_weights scales the scores).
//
// model  a struct with the arrays of the Python module's Reconstruction, in
//        MATLAB's order (first index fastest):
//          rotations     3 x 3 x F x M   R_tc, camera from object
//          translations  2 x F x M       T_tc
//          scales        F x M           s_tc (camera 1: 1)
//          weights       F x K           l_tk
//          basis         3 x P x K       S_k
//          points_object 3 x P x F       S_t = sum_k l_tk S_k
//          points_camera 3 x P x F x M   X_tc = s_tc R_tc S_t (no translation)
//          rig_rotations 3 x 3 x (M - 1), rig_scales (M - 1) x 1
//          dropped_points, dropped_frames  1-based indices of what was left
//                        out for too few observations (NaN in the arrays)
//          points_covariance     3 x 3 x P x F x M  with 'uncertainty', true:
//                        the covariance of each centred point of
//                        points_camera (docs/uncertainty.md); else []
//          rotations_covariance  3 x 3 x F x M  of each rotation's body-frame
//                        perturbation, rad^2; else []
//        so that W(2(tM + c) + (1:2), :) = points_camera(1:2, :, t, c) +
//        translations(:, t, c) for t, c 1-based.
// info   the summary: result.json of the tool as a struct (jsondecode),
//        plus K_selection with K = 'auto'.
//
// Bad input and failures are errors (identifier nrsfm:error) with the
// tool's message; warnings (points left out, little rotation) are warnings
// with identifier nrsfm:warning. A refinement that is not usable is an
// error. Only the C MEX API that MATLAB and Octave share is used, and no
// C++ object is alive when an error is raised (MATLAB's mexErrMsgIdAndTxt
// does not unwind C++ frames).
#include <glog/logging.h>

#include <Eigen/Core>
#include <cctype>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/io/result_writer.h"
#include "core/math/rotation.h"
#include "matlab/mex_util.h"
#include "mex.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"

namespace {

namespace mex = ::nrsfm::mex;
using nrsfm::Model;
using nrsfm::Status;
using nrsfm::tools::CommandFlags;

// What one call leaves for mexFunction to raise or return once every C++
// object is gone.
struct Outcome {
  std::string error;                  // "" = success
  std::vector<std::string> warnings;  // nrsfm:warning
  mxArray* model = nullptr;
  mxArray* summary_json = nullptr;  // a char array, decoded by jsondecode
};

mxArray* IndexRow(const std::vector<int>& indices) {
  mxArray* a = mxCreateDoubleMatrix(1, indices.size(), mxREAL);
  for (std::size_t i = 0; i < indices.size(); ++i)
    mxGetPr(a)[i] = indices[i] + 1.0;
  return a;
}

// 3 x 3 x n x F x M (3 x 3 x F x M for n = 1) from covariances in
// Uncertainty's order (view t·M + c, then n per view), or [] when there are
// none.
mxArray* CovarianceArray(const std::vector<Eigen::Matrix3d>& covariances,
                         mwSize n, mwSize f, mwSize m) {
  if (covariances.empty()) return mxCreateDoubleMatrix(0, 0, mxREAL);
  CHECK_EQ(covariances.size(), n * f * m);
  mxArray* a =
      n == 1 ? mex::NewArray({3, 3, f, m}) : mex::NewArray({3, 3, n, f, m});
  for (mwSize t = 0; t < f; ++t) {
    for (mwSize c = 0; c < m; ++c) {
      for (mwSize i = 0; i < n; ++i) {
        Eigen::Map<Eigen::Matrix3d>(mxGetPr(a) + 9 * (i + n * (t + f * c))) =
            covariances[(t * m + c) * n + i];
      }
    }
  }
  return a;
}

// The model struct of the header; `uncertainty` null when not computed.
mxArray* ModelStruct(const Model& model, const std::vector<int>& dropped_points,
                     const std::vector<int>& dropped_frames,
                     const nrsfm::Uncertainty* uncertainty) {
  const nrsfm::Uncertainty none;
  if (uncertainty == nullptr) uncertainty = &none;
  const mwSize f = model.num_frames, m = model.num_cameras,
               p = model.num_points, k = model.num_bases;
  mxArray* rotations = mex::NewArray({3, 3, f, m});
  mxArray* translations = mex::NewArray({2, f, m});
  mxArray* scales = mex::NewArray({f, m});
  mxArray* weights = mex::NewArray({f, k});
  mxArray* basis = mex::NewArray({3, p, k});
  mxArray* points_object = mex::NewArray({3, p, f});
  mxArray* points_camera = mex::NewArray({3, p, f, m});
  mxArray* rig_rotations = mex::NewArray({3, 3, m - 1});
  mxArray* rig_scales = mex::NewArray({m - 1, 1});
  for (mwSize t = 0; t < f; ++t) {
    for (mwSize c = 0; c < m; ++c) {
      const int view = model.View(static_cast<int>(t), static_cast<int>(c));
      Eigen::Map<Eigen::Matrix3d>(mxGetPr(rotations) + 9 * (t + f * c)) =
          model.Rotation(static_cast<int>(t), static_cast<int>(c));
      Eigen::Map<Eigen::Vector2d>(mxGetPr(translations) + 2 * (t + f * c)) =
          model.translations.col(view);
      mxGetPr(scales)[t + f * c] = model.scales(view);
      Eigen::Map<Eigen::Matrix3Xd>(mxGetPr(points_camera) + 3 * p * (t + f * c),
                                   3, p) =
          model.ShapeInCamera(static_cast<int>(t), static_cast<int>(c));
    }
    Eigen::Map<Eigen::Matrix3Xd>(mxGetPr(points_object) + 3 * p * t, 3, p) =
        model.ShapeInObject(static_cast<int>(t));
    for (mwSize b = 0; b < k; ++b)
      mxGetPr(weights)[t + f * b] = model.weights(b, t);
  }
  for (mwSize b = 0; b < k; ++b) {
    Eigen::Map<Eigen::Matrix3Xd>(mxGetPr(basis) + 3 * p * b, 3, p) =
        model.basis.middleRows(3 * b, 3);
  }
  for (mwSize c = 0; c + 1 < m; ++c) {
    Eigen::Map<Eigen::Matrix3d>(mxGetPr(rig_rotations) + 9 * c) =
        nrsfm::AngleAxisToRotation(model.rig_rotations.col(c));
    mxGetPr(rig_scales)[c] = model.rig_scales(c);
  }
  const char* fields[] = {"rotations",
                          "translations",
                          "scales",
                          "weights",
                          "basis",
                          "points_object",
                          "points_camera",
                          "rig_rotations",
                          "rig_scales",
                          "dropped_points",
                          "dropped_frames",
                          "points_covariance",
                          "rotations_covariance"};
  mxArray* out =
      mxCreateStructMatrix(1, 1, sizeof(fields) / sizeof(fields[0]), fields);
  mxArray* values[] = {rotations,
                       translations,
                       scales,
                       weights,
                       basis,
                       points_object,
                       points_camera,
                       rig_rotations,
                       rig_scales,
                       IndexRow(dropped_points),
                       IndexRow(dropped_frames),
                       CovarianceArray(uncertainty->points, p, f, m),
                       CovarianceArray(uncertainty->rotations, 1, f, m)};
  for (std::size_t i = 0; i < sizeof(fields) / sizeof(fields[0]); ++i) {
    mxSetField(out, 0, fields[i], values[i]);
  }
  return out;
}

// The call, with every C++ object in this scope; errors go to
// outcome->error.
Status Run(int nlhs, int nrhs, const mxArray* prhs[], Outcome* outcome) {
  if (nrhs < 2 || nrhs % 2 != 0) {
    return Status::Error(
        "usage: [model, info] = nrsfm_reconstruct(W, K, 'Name', value, ...)");
  }
  if (nlhs > 2)
    return Status::Error("nrsfm_reconstruct returns at most two outputs");
  CommandFlags flags;
  if (mxIsLogical(prhs[1]))
    return Status::Error("K must be a positive integer or 'auto'");
  NRSFM_RETURN_IF_ERROR(mex::ValueText(prhs[1], "K", &flags.K));
  nrsfm::tools::NumBasesFlag num_bases;
  NRSFM_RETURN_IF_ERROR(
      nrsfm::tools::ParseNumBasesFlag(flags.K, &num_bases).WithContext("--K"));

  Eigen::MatrixXd w, mask, observation_weights;
  NRSFM_RETURN_IF_ERROR(mex::ToMatrix(prhs[0], "W", &w));
  int cameras = 1;
  const std::vector<std::pair<std::string, std::string>> names =
      mex::OptionNames(
          {nrsfm::tools::FlagRole::kStart, nrsfm::tools::FlagRole::kOption});
  for (int i = 2; i < nrhs; i += 2) {
    if (!mxIsChar(prhs[i])) {
      return Status::Error("argument " + std::to_string(i + 1) +
                           " must be an option name (a char row)");
    }
    std::string name;
    NRSFM_RETURN_IF_ERROR(mex::ValueText(prhs[i], "an option name", &name));
    const std::string lower = mex::Lower(name);
    const mxArray* value = prhs[i + 1];
    if (lower == "mask") {
      NRSFM_RETURN_IF_ERROR(mex::ToMatrix(value, "mask", &mask));
      continue;
    }
    if (lower == "observation_weights") {
      NRSFM_RETURN_IF_ERROR(
          mex::ToMatrix(value, "observation_weights", &observation_weights));
      continue;
    }
    if (lower == "cameras") {
      std::string text;
      NRSFM_RETURN_IF_ERROR(mex::ValueText(value, "cameras", &text));
      NRSFM_RETURN_IF_ERROR(
          nrsfm::tools::SetFlagFromText("cameras", text, &flags));
      cameras = flags.cameras;
      continue;
    }
    NRSFM_RETURN_IF_ERROR(mex::SetOption(
        names, name, value, "mask, cameras, observation_weights", &flags));
  }

  flags.cameras = cameras;
  nrsfm::tools::FlagTargets targets;
  NRSFM_RETURN_IF_ERROR(nrsfm::tools::ApplyFlags(flags, &targets));
  nrsfm::Measurements measurements;
  NRSFM_RETURN_IF_ERROR(
      nrsfm::tools::MeasurementsFromArrays(w, mask, cameras, &measurements));
  NRSFM_RETURN_IF_ERROR(nrsfm::tools::ArrayReconstructOptions(
      measurements, observation_weights.array(), &flags, &targets));
  nrsfm::tools::ReconstructionRun run;
  NRSFM_RETURN_IF_ERROR(
      nrsfm::tools::RunReconstruction(targets, measurements, "", &run));
  const nrsfm::ReconstructionReport report =
      nrsfm::tools::MakeReport(flags, "", run, nullptr);
  if (!run.result.refine.usable) {
    return Status::Error("the refinement did not give a usable solution (" +
                         run.result.refine.message + ")");
  }
  nlohmann::ordered_json summary = nlohmann::ordered_json::parse(
      nrsfm::ReconstructionJson(measurements, run.result.model, report));
  if (run.auto_k) {
    nlohmann::ordered_json curve = nlohmann::ordered_json::array();
    for (const nrsfm::NumBasesCandidate& c : run.selection.curve) {
      curve.push_back({{"K", c.num_bases},
                       {"ok", c.ok},
                       {"message", c.message},
                       {"reprojection_rms", c.reprojection_rms},
                       {"expected_rms", c.expected_rms},
                       {"seconds", c.seconds}});
    }
    summary["K_selection"] = {{"noise_stddev", run.selection.noise_stddev},
                              {"curve", curve}};
  }
  outcome->warnings = report.warnings;
  outcome->model = ModelStruct(
      run.result.model, run.result.dropped_points, run.result.dropped_frames,
      run.uncertainty_status.ok() ? &run.uncertainty : nullptr);
  outcome->summary_json = mxCreateString(summary.dump().c_str());
  return Status::OK();
}

}  // namespace

void mexFunction(int nlhs, mxArray* plhs[], int nrhs, const mxArray* prhs[]) {
  // Kept across calls, so that no C++ object of this call is alive when
  // mexErrMsgIdAndTxt leaves it.
  static Outcome outcome;
  outcome = Outcome();
  outcome.error = mex::ErrorOf([&] { return Run(nlhs, nrhs, prhs, &outcome); });
  if (!outcome.error.empty()) {
    mexErrMsgIdAndTxt("nrsfm:error", "%s", outcome.error.c_str());
  }
  for (const std::string& warning : outcome.warnings) {
    mexWarnMsgIdAndTxt("nrsfm:warning", "%s", warning.c_str());
  }
  plhs[0] = outcome.model;
  if (nlhs > 1) {
    mexCallMATLAB(1, &plhs[1], 1, &outcome.summary_json, "jsondecode");
  }
  mxDestroyArray(outcome.summary_json);
}
