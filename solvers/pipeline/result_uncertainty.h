// The uncertainty of a Reconstruct() result (solvers/uncertainty/
// uncertainty.h): the problem its last refinement solved — the options'
// data term and blocks, the term weights the result reports
// (result.priors.term_weights), every block free — on the frames and points
// it kept, the covariances put back on the full index with NaN for the
// left-out ones.
#ifndef NRSFM_SOLVERS_PIPELINE_RESULT_UNCERTAINTY_H_
#define NRSFM_SOLVERS_PIPELINE_RESULT_UNCERTAINTY_H_

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "solvers/pipeline/reconstruct.h"
#include "solvers/uncertainty/uncertainty.h"

namespace nrsfm {

// For the rigid answer put in place of the K-basis one (repair_strength 0),
// the covariance of that rigid model (K = 1, no term). Errors as
// ComputeUncertainty, and on a result whose refinement was not usable.
Status ComputeResultUncertainty(const UncertaintyOptions& options,
                                const ReconstructOptions& reconstruct,
                                const Measurements& measurements,
                                const ReconstructResult& result,
                                Uncertainty* uncertainty);

// A summary for result.json and the warnings: the median and largest point
// standard deviation (PointStd) over every kept frame, camera and point, the
// frame with the largest RMS point standard deviation, and the median
// standard deviation along camera 0's depth axis (input units), also
// relative to the shape's extent (the largest side of camera 0's bounding
// box of each frame's shape, median over frames).
struct UncertaintySummary {
  double median_point_std = 0, max_point_std = 0;
  int worst_frame = -1;
  double worst_frame_std = 0;
  double median_depth_std = 0;
  double relative_depth_std = 0;
};
UncertaintySummary SummariseUncertainty(const Uncertainty& uncertainty,
                                        const Model& model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_RESULT_UNCERTAINTY_H_
