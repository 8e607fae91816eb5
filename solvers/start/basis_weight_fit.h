// The linear least-squares steps of the alternation
// (solvers/start/alternation.h, docs/factorization.md), monocular, on centred
// measurements:
//   w̃_tp = Π R_t Σ_k l_tk S_k[:, p] + δT_t
// where w̃ is W with a first estimate of the per-frame translation removed
// and δT_t = model.translations.col(t) a correction of it (zero when the
// first estimate is kept). Only visible entries enter the fits (the rows of
// missing measurements are dropped). Each normal matrix N gets
// `damping · tr(N) / n` on its diagonal so that an under-determined point or
// frame yields a finite answer instead of NaN. The fits run their points
// (frames) on up to `num_threads` threads; each is solved on its own, so the
// result does not depend on the thread count.
#ifndef NRSFM_SOLVERS_START_BASIS_WEIGHT_FIT_H_
#define NRSFM_SOLVERS_START_BASIS_WEIGHT_FIT_H_

#include "core/model/measurements.h"
#include "core/model/model.h"

namespace nrsfm {

// Step 1: every basis column b_p (3K) given the rotations, weights and δT of
// `model`, over the frames that see point p. Overwrites model->basis.
void FitBasisGivenMotion(const Measurements& centered, double damping,
                         Model* model, int num_threads = 1);

// W and the visibility of a one-camera input frame by frame: a frame's
// observations of every point contiguous in memory (W's rows are strided by
// 2F), for the steps that go frame by frame.
struct FrameMajorTracks {
  explicit FrameMajorTracks(const Measurements& centered, int num_threads = 1);

  Eigen::MatrixXd w;  // 2P × F: column t holds x_t0, y_t0, x_t1, …
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> seen;  // P × F
};

// Step 2: every weight vector l_t (K) given the basis and rotations, over
// the points frame t sees; with `fit_translations` jointly with δT_t
// (K + 2 unknowns). Overwrites model->weights (and model->translations).
// `tracks` (FrameMajorTracks of `centered`) when the caller keeps one.
void FitWeightsGivenBasis(const Measurements& centered, double damping,
                          bool fit_translations, Model* model,
                          int num_threads = 1);
void FitWeightsGivenBasis(const FrameMajorTracks& tracks, double damping,
                          bool fit_translations, Model* model,
                          int num_threads = 1);

// Subtracts from every basis shape its mean over the points and moves the
// shift into δT_t (δT_t += Π R_t Σ_k l_tk c_k), so the projections do not
// change. With centred bases a frame that sees every point has the
// least-squares δT_t = 0: its translation is the 2D mean of the frame.
void CentreBasisKeepingProjections(Model* model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_BASIS_WEIGHT_FIT_H_
