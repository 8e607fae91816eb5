#include "solvers/start/start.h"

#include <glog/logging.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/eval/metrics.h"
#include "core/math/random.h"
#include "core/math/svd.h"
#include "core/model/enum_names.h"
#include "core/model/option_checker.h"
#include "solvers/start/factorization_start.h"
#include "solvers/start/low_rank_completion.h"
#include "solvers/start/metric_upgrade.h"
#include "solvers/start/multi_camera_start.h"
#include "solvers/start/rigid_start.h"
#include "solvers/start/triple_start.h"

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
  // 64 bits: K comes from the user and 3K + 1 may not fit an int.
  const long long needed = 3LL * options.num_bases + 1;
  std::ostringstream msg;
  msg << "start: ";
  if (f < 2) {
    msg << "needs at least 2 frames, got F = " << f;
    return Status::Error(msg.str());
  }
  if (p < needed || 2LL * f < needed) {
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

// The largest K' ≤ K the start can be computed with: with missing entries
// the completion of rank 3K' needs every view to see 3K' + 1 points and
// every point to be seen in ⌈3K' / 2⌉ views
// (solvers/start/low_rank_completion.h); complete data allow K. At least 1 (the
// completion then reports what is missing for K' = 1).
int StartBases(int num_bases, const Measurements& data) {
  if (data.IsComplete()) return num_bases;
  const int fewest_points = data.VisiblePerView().minCoeff();
  const int fewest_views = data.VisiblePerPoint().minCoeff();
  int k = num_bases;
  while (k > 1 && (fewest_points < 3 * k + 1 || 2 * fewest_views < 3 * k)) --k;
  return k;
}

// Extends a start of K' bases to `num_bases`: the new basis shapes are zero
// and their weights small (1 % of the RMS weight of the start, seeded), so
// the refinement's Jacobian reaches them and grows the ones the data need.
void ExtendBases(int num_bases, std::uint64_t seed, Model* model) {
  const int k = model->num_bases;
  const double scale =
      0.01 * std::sqrt(model->weights.squaredNorm() /
                       std::max<Eigen::Index>(1, model->weights.size()));
  Model extended = *model;
  extended.num_bases = num_bases;
  extended.weights.resize(num_bases, model->num_frames);
  extended.weights.topRows(k) = model->weights;
  Random random(seed, /*stream=*/0xB45E5);
  for (int t = 0; t < model->num_frames; ++t) {
    for (int b = k; b < num_bases; ++b)
      extended.weights(b, t) = scale * random.NormalUnpaired();
  }
  extended.basis = Eigen::MatrixXd::Zero(3 * num_bases, model->num_points);
  extended.basis.topRows(3 * k) = model->basis;
  *model = std::move(extended);
}

Status CenterData(const StartOptions& options, const Measurements& data,
                  int num_threads, StartCache* cache, CenteredData* centered,
                  StartSummary* summary) {
  const int m = data.num_cameras;
  Eigen::MatrixXd filled;
  Eigen::VectorXd row_translations;
  if (data.IsComplete()) {
    filled = data.W;
    row_translations = data.W.rowwise().mean();
  } else {
    LowRankCompletion completion;
    const int rank = 3 * options.num_bases;
    NRSFM_RETURN_IF_ERROR(
        (cache != nullptr
             ? cache->completions().Complete(rank, options.completion,
                                             &completion)
             : CompleteLowRankAffine(data, rank, options.completion,
                                     &completion, num_threads))
            .WithContext("start"));
    summary->completion_rms = completion.residual_rms;
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
  centered->translations = Eigen::Map<const Eigen::Matrix2Xd>(
      row_translations.data(), 2, data.NumViews());
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

// The start on camera 0 (step 3 of the header) for a named method.
struct CameraZeroStart {
  Model model;
  bool indefinite = false;              // the metric upgrade's H was clamped
  double subblock_rank1_defect = -1.0;  // factorization start only
  double rigid_rms = -1.0;              // rigid and triple starts only
  int sign_segments = -1;               // triple start only
};

// The key of camera 0's centred tracks in a StartCache: the completion they
// came from (none for complete data).
std::string CenteredKey(const StartOptions& options, const Measurements& data) {
  if (data.IsComplete()) return "complete";
  std::ostringstream key;
  key << std::setprecision(17) << "rank " << 3 * options.num_bases
      << ", ridge floor " << options.completion.ridge_floor
      << ", max iterations " << options.completion.max_iterations;
  return key.str();
}

// The key of their top-3K SVD: the tracks' key and the count (ComputeTopSvd's
// vectors depend on how many are asked for).
std::string SvdKey(const StartOptions& options, const Measurements& data) {
  return CenteredKey(options, data) + ", top " +
         std::to_string(3 * options.num_bases);
}

// The SVD the factorization and rigid starts begin with (StartSvd), from
// `cache` when there is one, else null (the start computes it).
std::shared_ptr<const ThinSvd> CameraZeroSvd(const StartOptions& options,
                                             const Measurements& data,
                                             const Measurements& camera0,
                                             StartCache* cache) {
  if (cache == nullptr) return nullptr;
  const int num_bases = options.num_bases;
  return cache->Svd(SvdKey(options, data), [&camera0, num_bases] {
    return StartSvd(camera0.W, num_bases);
  });
}

Status StartOnCameraZero(const StartOptions& options, const Measurements& data,
                         const Measurements& camera0, int num_threads,
                         StartCache* cache, CameraZeroStart* start) {
  switch (options.method) {
    case StartMethod::kFactorization: {
      FactorizationStartSummary summary;
      const std::shared_ptr<const ThinSvd> svd =
          CameraZeroSvd(options, data, camera0, cache);
      NRSFM_RETURN_IF_ERROR(FactorizationStart(
          camera0, options.num_bases, &start->model, &summary, svd.get()));
      start->indefinite = summary.metric_upgrade_was_indefinite;
      start->subblock_rank1_defect = summary.mean_subblock_rank1_defect;
      return Status::OK();
    }
    case StartMethod::kRigid: {
      RigidStartSummary summary;
      const std::shared_ptr<const ThinSvd> svd =
          CameraZeroSvd(options, data, camera0, cache);
      NRSFM_RETURN_IF_ERROR(RigidStart(
          camera0, options.num_bases, options.alternation, options.seed,
          &start->model, &summary, svd.get(), num_threads));
      start->indefinite = summary.metric_upgrade_was_indefinite;
      start->rigid_rms = summary.alternation.rigid_rms;
      return Status::OK();
    }
    case StartMethod::kTriple: {
      TripleStartSummary summary;
      NRSFM_RETURN_IF_ERROR(TripleStart(camera0, options.num_bases,
                                        options.alternation, options.seed,
                                        num_threads, &start->model, &summary));
      start->rigid_rms = summary.alternation.rigid_rms;
      start->sign_segments = summary.triple.sign_segments;
      return Status::OK();
    }
    case StartMethod::kAuto:
      break;
  }
  LOG(FATAL) << "not a start: " << StartMethodName(options.method);
  return Status::OK();
}

}  // namespace

const char* StartMethodName(StartMethod m) {
  return NameOf(kStartMethodNames, m);
}

Status ParseStartMethod(const std::string& s, StartMethod* m) {
  CHECK(m != nullptr);
  return ParseName(kStartMethodNames, s, "start", m);
}

Status StartOptions::Check() const {
  OptionChecker check("start options");
  check.Require(NameOf(kStartMethodNames, method) != std::string("unknown"),
                "invalid method " + std::to_string(static_cast<int>(method)));
  check.AtLeast("num_bases", num_bases, 1);
  check.Nested(completion.Check());
  check.Nested(alternation.Check());
  return check.status();
}

std::shared_ptr<const ThinSvd> StartCache::Svd(
    const std::string& key, const std::function<ThinSvd()>& compute) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [stored_key, svd] : svds_) {
    if (stored_key == key) return svd;
  }
  svds_.emplace_back(key, std::make_shared<const ThinSvd>(compute()));
  return svds_.back().second;
}

Status ComputeStart(const StartOptions& options,
                    const Measurements& measurements, Model* model,
                    StartSummary* summary, int num_threads, StartCache* cache) {
  CHECK(model != nullptr && summary != nullptr);
  CHECK(cache == nullptr || &cache->measurements() == &measurements)
      << "a StartCache is for the measurements it was made with";
  const auto start_time = std::chrono::steady_clock::now();
  *summary = StartSummary();
  NRSFM_RETURN_IF_ERROR(options.Check());
  if (options.method == StartMethod::kAuto) {
    return Status::Error(
        "start: the start must be named (factorization, rigid or triple); "
        "auto is Reconstruct()'s choice between starts");
  }
  NRSFM_RETURN_IF_ERROR(measurements.Validate().WithContext("start"));
  NRSFM_RETURN_IF_ERROR(CheckData(options, measurements));

  // Missing entries may allow the start fewer bases than K (StartBases).
  StartOptions reduced = options;
  reduced.num_bases = StartBases(options.num_bases, measurements);
  if (reduced.num_bases < options.num_bases) {
    std::ostringstream msg;
    msg << "the missing entries allow a start with at most K = "
        << reduced.num_bases << " (a view sees only "
        << measurements.VisiblePerView().minCoeff()
        << " points, a point is seen in only "
        << measurements.VisiblePerPoint().minCoeff()
        << " views; K = " << options.num_bases << " needs "
        << 3 * options.num_bases + 1 << " and "
        << (3 * options.num_bases + 1) / 2
        << "): the start has K = " << reduced.num_bases << " and "
        << options.num_bases - reduced.num_bases
        << " more bases, zero at first, that the refinement fits";
    summary->warnings.push_back(msg.str());
  }
  CenteredData centered;
  NRSFM_RETURN_IF_ERROR(CenterData(reduced, measurements,
                                   std::max(1, num_threads), cache, &centered,
                                   summary));
  CameraZeroStart start;
  NRSFM_RETURN_IF_ERROR(
      StartOnCameraZero(reduced, measurements, centered.camera0,
                        std::max(1, num_threads), cache, &start)
          .WithContext("start"));
  if (reduced.num_bases < options.num_bases) {
    ExtendBases(options.num_bases, options.seed, &start.model);
  }
  Model& result = start.model;
  const Eigen::Matrix2Xd camera0_translations = result.translations;
  if (measurements.num_cameras > 1) {
    Model cameras;
    NRSFM_RETURN_IF_ERROR(
        ExtendToCameras(centered.all_cameras, result, &cameras)
            .WithContext("start"));
    result = std::move(cameras);
  }
  // The start's translations correct the centring of camera 0 (the
  // alternation's δT; zero for the factorisation start).
  result.translations = centered.translations;
  for (int t = 0; t < measurements.num_frames; ++t) {
    result.translations.col(measurements.View(t, 0)) +=
        camera0_translations.col(t);
  }
  NRSFM_RETURN_IF_ERROR(result.Validate().WithContext("start"));

  summary->method = options.method;
  summary->reprojection_rms =
      ReprojectionRms(measurements, result, std::max(1, num_threads));
  summary->subblock_rank1_defect = start.subblock_rank1_defect;
  summary->rigid_rms = start.rigid_rms;
  summary->triple_sign_segments = start.sign_segments;
  if (start.sign_segments > 1 &&
      start.sign_segments < measurements.num_frames) {
    summary->warnings.push_back("triple start: the frames link into " +
                                std::to_string(start.sign_segments) +
                                " time segments whose rotation signs were "
                                "chosen separately; the depth of a "
                                "segment may be reversed relative to the "
                                "others (solvers/start/corrective_triple.h)");
  }
  if (start.indefinite) {
    summary->warnings.push_back(
        std::string("metric upgrade of the ") +
        StartMethodName(options.method) +
        " start: H was (nearly) indefinite and was clamped to positive "
        "definite; the depth of the start is unreliable");
  }
  *model = std::move(result);
  summary->seconds = std::chrono::duration<double>(
                         std::chrono::steady_clock::now() - start_time)
                         .count();
  VLOG(1) << "start: " << StartMethodName(options.method)
          << " start, reprojection RMS " << summary->reprojection_rms;
  return Status::OK();
}

}  // namespace nrsfm
