#include "solvers/initialize.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include <glog/logging.h>

#include "core/enum_names.h"
#include "core/metrics.h"
#include "core/option_checker.h"
#include "solvers/factorization_start.h"
#include "solvers/low_rank_completion.h"
#include "solvers/multi_camera_start.h"
#include "solvers/rigid_start.h"

namespace nrsfm {
namespace {

constexpr EnumName<StartMethod> kStartMethodNames[] = {
    {StartMethod::kAuto, "auto"},
    {StartMethod::kFactorization, "factorization"},
    {StartMethod::kRigid, "rigid"},
    {StartMethod::kTriple, "triple"},
};

// The data every start works on.
struct CenteredData {
  Measurements all_cameras;  // W − T with missing entries filled, all cameras
  Measurements camera0;      // the rows and mask of camera 0 of the above
  Eigen::Matrix2Xd translations;  // 2 × FM
};

Status CheckData(const StartOptions& options, const Measurements& data) {
  const int f = data.num_frames;
  const int p = data.num_points;
  const int needed = 3 * options.num_bases + 1;
  std::ostringstream msg;
  msg << "initialize: ";
  if (f < 2) {
    msg << "needs at least 2 frames, got F = " << f;
    return Status::Error(msg.str());
  }
  if (p < needed || 2 * f < needed) {
    msg << "K = " << options.num_bases << " needs 3K + 1 = " << needed
        << " points and 2F >= " << needed << "; got P = " << p << ", F = " << f;
    return Status::Error(msg.str());
  }
  const Eigen::VectorXi per_view = data.VisiblePerView();
  for (int v = 0; v < data.NumViews(); ++v) {
    if (per_view(v) > 0) continue;
    msg << "frame " << v / data.num_cameras;
    if (data.num_cameras > 1) msg << ", camera " << v % data.num_cameras;
    msg << " has no visible point";
    return Status::Error(msg.str());
  }
  const Eigen::VectorXi per_point = data.VisiblePerPoint();
  for (int q = 0; q < p; ++q) {
    if (per_point(q) > 0) continue;
    msg << "point " << q << " is not visible in any frame";
    return Status::Error(msg.str());
  }
  return Status::OK();
}

Status CenterData(const StartOptions& options, const Measurements& data,
                  CenteredData* centered, StartSummary* summary) {
  const int m = data.num_cameras;
  Eigen::MatrixXd filled;
  Eigen::VectorXd row_translations;
  if (data.IsComplete()) {
    filled = data.W;
    row_translations = data.W.rowwise().mean();
  } else {
    LowRankCompletionOptions completion_options;
    completion_options.rank = 3 * options.num_bases;
    completion_options.max_iterations = options.completion_max_iterations;
    completion_options.tolerance = options.completion_tolerance;
    LowRankCompletion completion;
    NRSFM_RETURN_IF_ERROR(CompleteLowRankAffine(data, completion_options,
                                                &completion)
                              .WithContext("initialize"));
    summary->completion_rms = completion.residual_rms;
    summary->completion_iterations = completion.iterations;
    if (!completion.converged) {
      std::ostringstream msg;
      msg << "low-rank completion stopped at the iteration limit ("
          << completion.iterations << ") with residual RMS "
          << completion.residual_rms;
      summary->warnings.push_back(msg.str());
    }
    filled = std::move(completion.completed);
    row_translations = std::move(completion.translations);
  }
  centered->translations =
      Eigen::Map<const Eigen::Matrix2Xd>(row_translations.data(), 2, data.NumViews());
  centered->all_cameras = data;
  centered->all_cameras.W = filled.colwise() - row_translations;

  Measurements& camera0 = centered->camera0;
  camera0.num_frames = data.num_frames;
  camera0.num_cameras = 1;
  camera0.num_points = data.num_points;
  camera0.W.resize(2 * data.num_frames, data.num_points);
  camera0.visible.resize(data.num_frames, data.num_points);
  for (int t = 0; t < data.num_frames; ++t) {
    camera0.W.middleRows<2>(2 * t) =
        centered->all_cameras.W.middleRows<2>(data.Row(t, 0));
    camera0.visible.row(t) = data.visible.row(t * m);
  }
  return Status::OK();
}

struct StartOutcome {
  Status status;
  Model model;
  double rms = -1.0;
  bool indefinite = false;
  int sign_segments = -1;  // triple start only
};

StartOutcome RunStart(StartMethod method, const StartOptions& options,
                      const Measurements& data, const CenteredData& centered) {
  StartOutcome outcome;
  Model camera0;
  if (method == StartMethod::kFactorization) {
    FactorizationStartSummary start_summary;
    outcome.status = FactorizationStart(centered.camera0, options.num_bases,
                                        &camera0, &start_summary);
    outcome.indefinite = start_summary.metric_upgrade_was_indefinite;
  } else {
    RigidStartOptions rigid_options;
    rigid_options.refine_iterations = options.rigid_refine_iterations;
    rigid_options.initial_deformation = options.rigid_initial_deformation;
    rigid_options.seed = options.seed;
    rigid_options.rotations_from_triple = method == StartMethod::kTriple;
    rigid_options.triple.seed = options.seed;
    RigidStartSummary start_summary;
    outcome.status = RigidStart(centered.camera0, options.num_bases,
                                rigid_options, &camera0, &start_summary);
    outcome.indefinite = start_summary.metric_upgrade_was_indefinite;
    if (method == StartMethod::kTriple) {
      outcome.sign_segments = start_summary.triple.sign_segments;
    }
  }
  if (!outcome.status.ok()) return outcome;
  const Eigen::Matrix2Xd camera0_translations = camera0.translations;
  if (data.num_cameras > 1) {
    MultiCameraStartSummary camera_summary;
    outcome.status = ExtendToCameras(centered.all_cameras, camera0,
                                     &outcome.model, &camera_summary);
    if (!outcome.status.ok()) return outcome;
  } else {
    outcome.model = std::move(camera0);
  }
  // A start's translations correct the centring of camera 0 (the rigid
  // start's δT; zero for the factorisation start).
  outcome.model.translations = centered.translations;
  for (int t = 0; t < data.num_frames; ++t) {
    outcome.model.translations.col(data.View(t, 0)) +=
        camera0_translations.col(t);
  }
  outcome.status = outcome.model.Validate();
  if (outcome.status.ok()) outcome.rms = ReprojectionRms(data, outcome.model);
  return outcome;
}

}  // namespace

const char* StartMethodName(StartMethod m) { return NameOf(kStartMethodNames, m); }

Status ParseStartMethod(const std::string& s, StartMethod* m) {
  CHECK(m != nullptr);
  return ParseName(kStartMethodNames, s, "start", m);
}

Status StartOptions::Check() const {
  OptionChecker check("start options");
  check.Require(NameOf(kStartMethodNames, method) != std::string("unknown"),
                "invalid method " + std::to_string(static_cast<int>(method)));
  check.AtLeast("num_bases", num_bases, 1);
  check.AtLeast("completion_max_iterations", completion_max_iterations, 1);
  check.AtLeast("completion_tolerance", completion_tolerance, 0.0);
  check.AtLeast("rigid_refine_iterations", rigid_refine_iterations, 0);
  check.FiniteAtLeast("rigid_initial_deformation", rigid_initial_deformation, 0.0);
  return check.status();
}

Status Initialize(const StartOptions& options,
                  const Measurements& measurements, Model* model,
                  StartSummary* summary) {
  CHECK(model != nullptr && summary != nullptr);
  const auto start_time = std::chrono::steady_clock::now();
  *summary = StartSummary();
  NRSFM_RETURN_IF_ERROR(options.Check());
  NRSFM_RETURN_IF_ERROR(measurements.Validate().WithContext("initialize"));
  NRSFM_RETURN_IF_ERROR(CheckData(options, measurements));

  CenteredData centered;
  NRSFM_RETURN_IF_ERROR(CenterData(options, measurements, &centered, summary));

  const bool run_factorization = options.method == StartMethod::kAuto ||
                                 options.method == StartMethod::kFactorization;
  const bool run_rigid = options.method != StartMethod::kFactorization;
  const StartMethod rigid_method =
      options.method == StartMethod::kTriple ? StartMethod::kTriple : StartMethod::kRigid;
  StartOutcome factorization, rigid;
  if (run_factorization) {
    factorization =
        RunStart(StartMethod::kFactorization, options, measurements, centered);
    if (factorization.status.ok()) summary->factorization_rms = factorization.rms;
  }
  if (run_rigid) {
    rigid = RunStart(rigid_method, options, measurements, centered);
    if (rigid.status.ok()) summary->rigid_rms = rigid.rms;
  }
  const bool factorization_ok = run_factorization && factorization.status.ok();
  const bool rigid_ok = run_rigid && rigid.status.ok();
  if (!factorization_ok && !rigid_ok) {
    return (run_factorization ? factorization.status : rigid.status)
        .WithContext("initialize");
  }
  if (options.method == StartMethod::kAuto) {
    if (!factorization_ok) {
      summary->warnings.push_back("factorization start failed: " +
                                  factorization.status.message());
    }
    if (!rigid_ok) {
      summary->warnings.push_back("rigid start failed: " + rigid.status.message());
    }
  }
  const bool keep_rigid =
      rigid_ok && (!factorization_ok || rigid.rms < factorization.rms);
  StartOutcome& kept = keep_rigid ? rigid : factorization;
  summary->used = keep_rigid ? rigid_method : StartMethod::kFactorization;
  summary->reprojection_rms = kept.rms;
  summary->metric_upgrade_was_indefinite = kept.indefinite;
  summary->triple_sign_segments = kept.sign_segments;
  if (kept.sign_segments > 1 && kept.sign_segments < measurements.num_frames) {
    summary->warnings.push_back(
        "triple start: the frames link into " + std::to_string(kept.sign_segments) +
        " time segments whose rotation signs were chosen separately; the depth of a "
        "segment may be reversed relative to the others (solvers/corrective_triple.h)");
  }
  if (kept.indefinite) {
    summary->warnings.push_back(
        std::string("metric upgrade of the ") + StartMethodName(summary->used) +
        " start: H was (nearly) indefinite and was clamped to positive "
        "definite; the depth of the start is unreliable");
  }
  *model = std::move(kept.model);
  summary->seconds = std::chrono::duration<double>(
                         std::chrono::steady_clock::now() - start_time)
                         .count();
  VLOG(1) << "initialize: kept the " << StartMethodName(summary->used)
          << " start, reprojection RMS " << summary->reprojection_rms;
  return Status::OK();
}

}  // namespace nrsfm
