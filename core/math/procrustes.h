// Alignment of 3D point sets (Procrustes problems), used by the metrics and by
// every test that compares a reconstruction with ground truth.
//
// Conventions: `target` and `source` are 3 × P with corresponding columns (or
// lists of such frames, all with the same P per pair); every function returns
// the transform that maps `source` onto `target`. Nothing here centres the
// points unless it says so: centre them first when translation is not part of
// the fit.
#ifndef NRSFM_CORE_MATH_PROCRUSTES_H_
#define NRSFM_CORE_MATH_PROCRUSTES_H_

#include <Eigen/Core>
#include <vector>

namespace nrsfm {

// The orthogonal matrix nearest to `m` in the Frobenius norm: U Vᵀ for
// m = U Σ Vᵀ (det = ±1; the sign follows m). See core/math/rotation.h
// NearestRotation for the det = +1 version.
Eigen::Matrix3d NearestOrthogonal(const Eigen::Matrix3d& m);

// Orthogonal Procrustes from the cross-covariance C = Σ_p y_p x_pᵀ (y in the
// target, x in the source): the Q that minimises Σ_p ||y_p − Q x_p||², i.e.
// maximises tr(Qᵀ C). With `allow_reflection` Q = NearestOrthogonal(C)
// (det ±1), otherwise Q = NearestRotation(C) (det +1).
Eigen::Matrix3d OrthogonalFromCrossCovariance(
    const Eigen::Matrix3d& cross_covariance, bool allow_reflection);

// argmin_Q ||target − Q source||_F over orthogonal Q (det +1 only unless
// `allow_reflection`). No centring. CHECKs equal column counts.
Eigen::Matrix3d AlignOrthogonal(const Eigen::Matrix3Xd& target,
                                const Eigen::Matrix3Xd& source,
                                bool allow_reflection);

// One Q for a whole sequence: argmin_Q Σ_t ||target_t − Q source_t||_F², from
// the summed cross-covariance Σ_t target_t source_tᵀ. No centring. CHECKs that
// the lists have the same length and each pair the same P.
Eigen::Matrix3d AlignOrthogonal(const std::vector<Eigen::Matrix3Xd>& target,
                                const std::vector<Eigen::Matrix3Xd>& source,
                                bool allow_reflection);

// Akhter et al.'s alignment for e3D (their `findRotation`): first the
// unconstrained least-squares linear map
//   A = argmin_A Σ_t ||target_t − A source_t||_F² = C M⁺,
//   C = Σ_t target_t source_tᵀ,  M = Σ_t source_t source_tᵀ
// (M⁺ the pseudo-inverse, so a flat source is handled), then
// NearestOrthogonal(A) (reflection allowed). This is NOT the orthogonal
// Procrustes solution unless M ∝ I; it is the one that reproduces the
// published e3D numbers (see core/eval/metrics.h). No centring; CHECKs sizes.
Eigen::Matrix3d AlignLeastSquaresThenOrthogonal(
    const std::vector<Eigen::Matrix3Xd>& target,
    const std::vector<Eigen::Matrix3Xd>& source);

// y = scale · rotation · x + translation.
struct SimilarityTransform {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // orthogonal
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Matrix3Xd Apply(const Eigen::Matrix3Xd& points) const;
};

// argmin over (s, Q, t) of Σ_p ||target_p − (s Q source_p + t)||² (Umeyama
// 1991), translation included (the points need not be centred). Without
// `allow_reflection` this is Eigen::umeyama (det Q = +1); with it, Q may be a
// reflection (det −1) when that fits better. `with_scaling` = false fixes
// s = 1. CHECKs equal column counts, P ≥ 1, and (with scaling) that the
// source points do not all coincide.
SimilarityTransform AlignSimilarity(const Eigen::Matrix3Xd& target,
                                    const Eigen::Matrix3Xd& source,
                                    bool with_scaling, bool allow_reflection);

}  // namespace nrsfm

#endif  // NRSFM_CORE_MATH_PROCRUSTES_H_
