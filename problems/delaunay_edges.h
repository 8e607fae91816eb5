// Neighbours for the smoothness term (docs/problem.md,
// problems/smoothness_error.h): a 2D Delaunay triangulation (Qhull,
// libqhull_r) of the points seen in one reference view.
//
// Reference view: the (frame, camera 0) with the most visible points unless
// the options name a frame. Its visible points are triangulated at their 2D
// image positions x_i; every edge of a triangle is one neighbour pair (i, j).
// A point that is not a vertex of the triangulation — not visible in the
// reference view, or a duplicate of another point's position there — is
// joined to its `num_hidden_neighbours` nearest vertices, where the distance
// between two points is the mean of |x_i − x_j| over the views that see both
// (the reference view included). A point that shares no view with any
// vertex gets no edge.
#ifndef NRSFM_PROBLEMS_DELAUNAY_EDGES_H_
#define NRSFM_PROBLEMS_DELAUNAY_EDGES_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/status.h"

namespace nrsfm {

struct NeighbourEdge {
  int i = 0;  // point index, i < j
  int j = 0;  // point index
};

struct DelaunayEdgesOptions {
  int reference_frame = -1;  // frame whose camera-0 view is triangulated; -1 =
                             // most visible points
  // vertices each non-vertex point is joined to, ≥ 1
  int num_hidden_neighbours = 3;

  // Errors on reference_frame < -1 or num_hidden_neighbours < 1 (the frame
  // range is checked against the measurements by ComputeDelaunayEdges).
  Status Check() const;
};

// Delaunay triangles of 2D points (columns of `points`, any units) as triples
// of column indices, counter-clockwise. Duplicate points appear in no
// triangle. Errors (naming the reason) on fewer than 3 points, non-finite
// values, or points that are all collinear.
Status DelaunayTriangulation(const Eigen::Matrix2Xd& points,
                             std::vector<std::array<int, 3>>* triangles);

// The neighbour edges of the measurements, sorted by (i, j), each pair once.
// `reference_frame_used` (optional) receives the frame that was triangulated.
// Errors on invalid options or measurements, a reference frame out of range,
// or a reference view whose visible points cannot be triangulated.
Status ComputeDelaunayEdges(const Measurements& measurements,
                            const DelaunayEdgesOptions& options,
                            std::vector<NeighbourEdge>* edges,
                            int* reference_frame_used = nullptr);

// A point and its neighbours with the weights of the smoothness term
// (problems/smoothness_error.h): S_i is compared with Σ_j w_ij S_j.
struct SmoothnessStencil {
  int point = 0;                // i
  std::vector<int> neighbours;  // j, ascending
  std::vector<double> weights;  // w_ij, summing to 1
};

// One stencil per point that has a neighbour edge, in point order. The
// weights come from the image positions in one view: the view that sees i
// and the most of its neighbours (the reference view of
// ComputeDelaunayEdges when it sees as many); neighbours that view does not
// see are left out. With d_j = (x_j − x_i) / ρ (ρ the neighbours' RMS
// distance, so the weights do not depend on the units)
//   w = argmin ||w||² + (1/ε) ||Σ_j w_j d_j||²  subject to  Σ_j w_j = 1,
//   w = M⁻¹ 1 / (1ᵀ M⁻¹ 1),  M = I + DᵀD / ε,  ε = 1e-6:
// the smallest weights whose affine combination of the neighbours'
// positions is x_i (exact up to ε when some affine combination is, the
// nearest otherwise), so a shape that is an affine function of the image
// gives a zero residual. One neighbour: w = 1 (the difference S_i − S_j).
// Errors as ComputeDelaunayEdges.
Status ComputeSmoothnessStencils(const Measurements& measurements,
                                 const DelaunayEdgesOptions& options,
                                 std::vector<SmoothnessStencil>* stencils,
                                 int* reference_frame_used = nullptr);

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_DELAUNAY_EDGES_H_
