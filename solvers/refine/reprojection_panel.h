// The reprojection residuals of a structured layout
// (solvers/refine/structured_layout.h) as one dense panel: the products with
// the Jacobian that the structured solver forms in every step and conjugate-
// gradient iteration (the two passes of a product with the Schur complement,
// solvers/refine/schur_elimination.h; the gradient; the Gram blocks J_pᵀ J_p;
// the views' J_fᵀ J_f for the preconditioner; diag(JᵀJ); the linear model's
// decrease) as matrix products instead of one small product per residual
// block, so that these residuals' Jacobians are never stored.
//
// A residual of the panel is a reprojection residual with a basis factor
// (problems/reprojection_cost_function.h: no robust loss, its basis block
// eliminated, in no grid). Its view v is its rotation block (with the
// translation, weights and scale blocks that go with it), its column p its
// basis block, and its weight w_vp = sqrt(w_obs) (0 where nothing is
// observed). With the view's a_v = s Π R, d_vi = s ∂(Π R)/∂ω_i, l_v its
// weights and s_p the point's basis values (3K):
//   J_f δ = w (C_v(δ) s_p + δT_v),  C_v = [l_vk E_v + δl_vk a_v]_k,
//   E_v = Σ_i δω_i d_vi + δs Π R,   J_p δb = w N_v δb, N_v = [l_vk a_v]_k,
//   J_pᵀ J_p (point p) = Σ_v w_vp² (l_v l_vᵀ) ⊗ (a_vᵀ a_v),
// so over all views and points these are products of (2V × 3K) and
// (3K × P) matrices, masked by w or w² (every entry of the panel costs the
// same, observed or not; Build() declines a panel where that does not pay). The
// products are cut into column pieces fixed by P, so the results are the same
// bits for any thread count.
//
// Everything uses the blocks' values of the last Update(); not thread-safe
// (the passes keep J_f v between them).
#ifndef NRSFM_SOLVERS_REFINE_REPROJECTION_PANEL_H_
#define NRSFM_SOLVERS_REFINE_REPROJECTION_PANEL_H_

#include <Eigen/Core>
#include <vector>

#include "problems/reprojection_cost_function.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {
namespace structured {

// Adds (l lᵀ) ⊗ (Aᵀ A) summed over residuals to the lower triangle of the
// 3K × 3K block `c` (and the upper entries of its off-diagonal 3 × 3 blocks
// that the lower triangle does not hold): `sums` (6 × K(K+1)/2, column-major)
// holds Σ (Aᵀ A)_(i,j) l_a l_b with (i, j), i ≥ j, in the order
// (0,0) (1,0) (2,0) (1,1) (2,1) (2,2) and (a, b), a ≥ b, in the order b = 0,
// a = 0 … K−1, then b = 1, ….
void AddKroneckerGram(const double* sums, int num_bases, Eigen::MatrixXd* c);

class ReprojectionPanel {
 public:
  // The panel of `blocks`' reprojection residuals with a basis factor, or
  // false (it holds none) when there are none, when they have different K,
  // when a translation, weights or scale block has a manifold,
  // when two of them share a view and a point, when their views disagree on
  // the blocks that go with a rotation block, or when fewer than a fifth of
  // the panel's entries are observed (the residual blocks one by one then
  // cost less; the rule in the .cc). `blocks` must outlive this.
  bool Build(const StructuredBlocks& blocks);

  int num_views() const { return static_cast<int>(views_.size()); }
  int num_points() const { return static_cast<int>(points_.size()); }
  // Observed entries (residuals) of the panel.
  long long num_entries() const { return num_entries_; }

  // The views' derivatives and the points' values at the blocks' current
  // values.
  void Update(int num_threads);

  // Adds the panel's part of Jᵀ r to `reduced` and `eliminated`, r the
  // residual vector (rows of solvers/refine/structured_layout.h) at the values
  // of the last Update().
  void AddGradient(const Eigen::VectorXd& residuals, int num_threads,
                   Eigen::VectorXd* reduced, Eigen::VectorXd* eliminated) const;

  // J δ of the panel's residuals (δ = [reduced; eliminated]): adds
  // Σ (J δ)·r to *dot and Σ (J δ)² to *squared, r the residual vector.
  void AddStepProducts(const Eigen::VectorXd& reduced,
                       const Eigen::VectorXd& eliminated,
                       const Eigen::VectorXd& residuals, int num_threads,
                       double* dot, double* squared) const;

  // Whether `residual` (index into blocks.residuals) is in the panel.
  bool Holds(int residual) const { return members_[residual] != 0; }
  // Adds the panel's part of J_pᵀ J_p for eliminated block `block` (a Block
  // index) to `c` as AddKroneckerGram does, at the values of the last
  // Update(); nothing for a block the panel does not hold.
  void AddGram(int block, Eigen::MatrixXd* c) const;
  // The free reduced blocks of view `view` (Block indices: its rotation,
  // translation, weights and scale blocks that are free, in that order), and
  // its residuals' J_fᵀ J_f over their columns in that order, at the last
  // Update():
  //   Σ_p w_vp² J̃_vpᵀ J̃_vp,  J̃_vp = [d_vi X_vp, I₂, a_v b_pk, Π R X_vp],
  // X_vp = Σ_k l_vk b_pk (the rotation's columns mapped to its tangent
  // space). Formed in Update() the cheaper way for P and K
  // (ViewGramsFromMoments()): from M_v = Σ_p w_vp² [s_p − c; 1] [s_p − c; 1]ᵀ
  // (c the points' mean), one product of the V × P matrix of w² with the
  // points' (3K + 1)(3K + 2)/2 products, then Φ_v M_v Φ_vᵀ per view (J̃ = Φ_v
  // [s_p − c; 1]); or per view from J̃ formed for every point.
  static bool ViewGramsFromMoments(int num_points, int num_bases);
  const std::vector<int>& ViewBlocks(int view) const {
    return views_[view].blocks;
  }
  const Eigen::MatrixXd& ViewGram(int view) const { return view_gram_[view]; }
  // Adds diag(JᵀJ) of the panel's residuals: the reduced columns from the
  // views' Grams, the eliminated ones from the Gram sums of AddGram().
  void AddColumnSquaredNorms(Eigen::VectorXd* reduced,
                             Eigen::VectorXd* eliminated) const;

  // The first pass: keeps J_f v (v: reduced columns) and adds J_pᵀ J_f v to
  // `projected` (eliminated columns).
  void ProjectReduced(const Eigen::VectorXd& v, int num_threads,
                      Eigen::VectorXd* projected) const;
  // The second pass: adds J_fᵀ (J_f v − J_p e) to `out` (reduced columns),
  // J_f v from the last ProjectReduced(), or J_fᵀ (−J_p e) when not
  // with_reduced.
  void AddReduced(const Eigen::VectorXd& e, bool with_reduced, int num_threads,
                  Eigen::VectorXd* out) const;

 private:
  // Items per thread at least in the loops over the views and the points.
  static constexpr int kViewGrain = 64;
  struct View {
    int rotation = -1, translation = -1, weights = -1, scale = -1;  // Block
    std::vector<int> blocks;  // the free ones of the four, in that order
    const double* rotation_values = nullptr;
    const double* weights_values = nullptr;
    const double* scale_value = nullptr;  // null: s = 1
  };
  // Adds to `out` the views' gradients from Z = Σ_pieces G Sᵀ and the row
  // sums of G (G: 2V × P, per piece), as J_fᵀ y with G = w ⊙ y.
  void AddViewGradients(const std::vector<Eigen::MatrixXd>& z,
                        const std::vector<Eigen::VectorXd>& t,
                        Eigen::VectorXd* out) const;
  // Holds nothing; returns false (Build's failure).
  bool Clear();
  // ViewGram() of every view from the moments M_v, or from J̃ formed for
  // every point.
  void ViewGramsByMoments(int num_threads);
  void ViewGramsDirect(int num_threads);
  // w² of column piece [begin, begin + width) (V × width).
  void SquaredWeights(int begin, int width, Eigen::MatrixXd* w2) const;
  // The number of columns of a view's Gram (its free blocks' sizes).
  int ViewColumns(const View& view) const;
  // Column pieces [piece_begin(i), piece_begin(i + 1)).
  int NumPieces() const { return static_cast<int>(piece_begin_.size()) - 1; }
  // C (2V × 3K) and δT (2V, zero for a constant translation) for the
  // reduced vector v.
  void FormC(const Eigen::VectorXd& v, Eigen::MatrixXd* c,
             Eigen::VectorXd* translation) const;

  const StructuredBlocks* blocks_ = nullptr;
  int num_bases_ = 0;
  long long num_entries_ = 0;
  std::vector<View> views_;
  std::vector<char> members_;     // per residual of blocks
  std::vector<int> points_;       // eliminated Block per column
  std::vector<int> column_of_;    // column per Block, −1 = none
  std::vector<int> piece_begin_;  // fixed by the number of points
  Eigen::MatrixXd w_;             // 2V × P: w for both rows of a view
  Eigen::MatrixXi rows_;          // V × P: first row of r, −1 = none
  // At the last Update(): a_v, d_vi (ambient), Π R, the tangent map of ω
  // (3 × size, identity without a manifold), l_v per view; s_p per column.
  std::vector<Eigen::Matrix<double, 2, 3>> a_, projection_;
  std::vector<Eigen::Matrix<double, 2, 3>> d_;  // 3 per view
  std::vector<Eigen::MatrixXd> tangent_;
  Eigen::MatrixXd n_;  // 2V × 3K: N_v
  // The sums of AddKroneckerGram per column (6 K(K+1)/2 × P).
  Eigen::MatrixXd gram_;
  std::vector<Eigen::MatrixXd> view_gram_;  // per view, ViewGram()
  Eigen::MatrixXd basis_;                   // 3K × P: s_p
  mutable Eigen::MatrixXd jfv_;  // 2V × P: J_f v / w, from ProjectReduced()
};

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_REPROJECTION_PANEL_H_
