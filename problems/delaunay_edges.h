// Neighbour edges for the basis smoothness term (docs/problem.md):
// a 2D Delaunay triangulation (Qhull, libqhull_r) of the points seen in one
// reference view.
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
//
// Edge weights: α_ij = d̄ / max(d_ij, 1e-3 d̄), d_ij = the edge's length
// (input units) and d̄ = the mean length of the triangulation's edges, so
// α ∝ 1/|x_i − x_j| (Torresani et al. 2001: "inversely proportional to the
// distance"), dimensionless, ~1 for a typical edge; the clamp bounds α for
// coincident points.
#ifndef NRSFM_PROBLEMS_DELAUNAY_EDGES_H_
#define NRSFM_PROBLEMS_DELAUNAY_EDGES_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/measurements.h"
#include "core/status.h"

namespace nrsfm {

struct NeighbourEdge {
  int i = 0;           // point index, i < j
  int j = 0;           // point index
  double alpha = 0.0;  // α_ij > 0, dimensionless (see above)
};

struct DelaunayEdgesOptions {
  int reference_frame = -1;  // frame whose camera-0 view is triangulated; -1 =
                             // most visible points
  int num_hidden_neighbours =
      3;  // vertices each non-vertex point is joined to, ≥ 1

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

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_DELAUNAY_EDGES_H_
