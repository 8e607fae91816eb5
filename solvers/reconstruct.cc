#include "solvers/reconstruct.h"

#include <chrono>

#include <glog/logging.h>

#include "core/option_checker.h"

namespace nrsfm {

Status ReconstructOptions::Check() const {
  OptionChecker check("reconstruct");
  check.Nested(start.Check());
  check.Nested(problem.Check());
  check.Nested(solver.Check());
  return check.status();
}

namespace {

// One start followed by its refinement.
Status StartAndRefine(const ReconstructOptions& options, StartMethod method,
                      const Measurements& measurements, ReconstructResult* result) {
  StartOptions start = options.start;
  start.method = method;
  NRSFM_RETURN_IF_ERROR(
      Initialize(start, measurements, &result->model, &result->start));
  return Refine(options.problem, options.solver, measurements, &result->model,
                &result->refine);
}

// Whether refined result `a` is better than `b`: a usable solution beats an
// unusable one; then the lower final cost wins.
bool IsBetter(const ReconstructResult& a, const ReconstructResult& b) {
  if (a.refine.usable != b.refine.usable) return a.refine.usable;
  return a.refine.final_cost < b.refine.final_cost;
}

}  // namespace

Status Reconstruct(const ReconstructOptions& options,
                   const Measurements& measurements, ReconstructResult* result) {
  CHECK(result != nullptr);
  const auto start = std::chrono::steady_clock::now();
  *result = ReconstructResult();
  NRSFM_RETURN_IF_ERROR(options.Check());
  if (options.start.method != StartMethod::kAuto) {
    NRSFM_RETURN_IF_ERROR(
        StartAndRefine(options, options.start.method, measurements, result));
  } else {
    // Both starts are refined and the lower refined cost is kept: a start's
    // own reprojection error does not tell which basin it is in (the rigid
    // start can fit the tracks better than the factorisation start and still
    // converge to a depth-degenerate solution).
    ReconstructResult factorization, rigid;
    const Status factorization_status = StartAndRefine(
        options, StartMethod::kFactorization, measurements, &factorization);
    const Status rigid_status =
        StartAndRefine(options, StartMethod::kRigid, measurements, &rigid);
    if (!factorization_status.ok() && !rigid_status.ok()) {
      return Status::Error("both starts failed: factorization: " +
                           factorization_status.message() +
                           "; rigid: " + rigid_status.message());
    }
    const bool keep_rigid =
        !factorization_status.ok() ||
        (rigid_status.ok() && IsBetter(rigid, factorization));
    *result = keep_rigid ? std::move(rigid) : std::move(factorization);
    const Status& other = keep_rigid ? factorization_status : rigid_status;
    if (!other.ok()) {
      result->start.warnings.push_back(
          std::string(keep_rigid ? "factorization" : "rigid") +
          " start failed: " + other.message());
    }
  }
  result->total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return Status::OK();
}

}  // namespace nrsfm
