#include "problems/delaunay_edges.h"

#include <glog/logging.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>
#include <vector>

namespace nrsfm {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::set<std::pair<int, int>> EdgesOf(
    const std::vector<std::array<int, 3>>& triangles) {
  std::set<std::pair<int, int>> edges;
  for (const auto& t : triangles) {
    for (int e = 0; e < 3; ++e) {
      edges.insert(
          {std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3])});
    }
  }
  return edges;
}

TEST(DelaunayTriangulation, SquareWithCentreGivesFourTriangles) {
  Eigen::Matrix2Xd points(2, 5);
  points << 0, 1, 1, 0, 0.5,  //
      0, 0, 1, 1, 0.5;
  std::vector<std::array<int, 3>> triangles;
  ASSERT_TRUE(DelaunayTriangulation(points, &triangles).ok());
  ASSERT_EQ(triangles.size(), 4u);
  for (const auto& t : triangles) {
    EXPECT_TRUE(std::count(t.begin(), t.end(), 4) == 1);
    // Counter-clockwise: positive signed area.
    const Eigen::Vector2d a = points.col(t[1]) - points.col(t[0]);
    const Eigen::Vector2d b = points.col(t[2]) - points.col(t[0]);
    EXPECT_NEAR(a.x() * b.y() - a.y() * b.x(), 0.5, 1e-12);
  }
  EXPECT_EQ(
      EdgesOf(triangles),
      (std::set<std::pair<int, int>>{
          {0, 1}, {1, 2}, {2, 3}, {0, 3}, {0, 4}, {1, 4}, {2, 4}, {3, 4}}));
}

// A(0,0), B(4,0), C(2,1), D(2,-1): the angles at C and D opposite AB are
// 126.9° each (sum > 180°), so the Delaunay diagonal is CD, not AB.
TEST(DelaunayTriangulation, PicksTheDelaunayDiagonal) {
  Eigen::Matrix2Xd points(2, 4);
  points << 0, 4, 2, 2,  //
      0, 0, 1, -1;
  std::vector<std::array<int, 3>> triangles;
  ASSERT_TRUE(DelaunayTriangulation(points, &triangles).ok());
  EXPECT_EQ(EdgesOf(triangles), (std::set<std::pair<int, int>>{
                                    {0, 2}, {1, 2}, {1, 3}, {0, 3}, {2, 3}}));
}

TEST(DelaunayTriangulation, DuplicatePointIsInNoTriangle) {
  Eigen::Matrix2Xd points(2, 5);
  points << 0, 2, 0, 1.5, 2,  //
      0, 0, 2, 1.7, 0;
  std::vector<std::array<int, 3>> triangles;
  ASSERT_TRUE(DelaunayTriangulation(points, &triangles).ok());
  ASSERT_EQ(triangles.size(), 2u);
  // One of the two copies of (2, 0), points 1 and 4, is a vertex.
  int copies = 0;
  for (const int p : {1, 4}) {
    bool used = false;
    for (const auto& t : triangles)
      used |= std::count(t.begin(), t.end(), p) > 0;
    copies += used;
  }
  EXPECT_EQ(copies, 1);
}

TEST(DelaunayTriangulation, RejectsDegenerateInput) {
  std::vector<std::array<int, 3>> triangles;
  Eigen::Matrix2Xd two(2, 2);
  two << 0, 1, 0, 1;
  EXPECT_FALSE(DelaunayTriangulation(two, &triangles).ok());
  Eigen::Matrix2Xd collinear(2, 4);
  collinear << 0, 1, 2, 3,  //
      0, 1, 2, 3;
  const Status status = DelaunayTriangulation(collinear, &triangles);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("collinear"), std::string::npos)
      << status.message();
  Eigen::Matrix2Xd not_finite(2, 3);
  not_finite << 0, 1, kNaN, 0, 0, 1;
  EXPECT_FALSE(DelaunayTriangulation(not_finite, &triangles).ok());
}

// Frame 0 sees the unit square's corners 0-3 and its centre 4; frame 1 sees
// 0, 1, 2 at the same places and point 5 at (1.1, 1), which frame 0 misses.
Measurements SquareMeasurements() {
  Eigen::MatrixXd w(4, 6);
  w << 0, 1, 1, 0, 0.5, kNaN,    //
      0, 0, 1, 1, 0.5, kNaN,     //
      0, 1, 1, kNaN, kNaN, 1.1,  //
      0, 0, 1, kNaN, kNaN, 1.0;
  Measurements m;
  CHECK(Measurements::FromMatrixWithNaN(w, 1, "test", &m).ok());
  return m;
}

TEST(ComputeDelaunayEdges, HandComputedEdges) {
  const Measurements m = SquareMeasurements();
  DelaunayEdgesOptions options;
  options.num_hidden_neighbours = 2;
  std::vector<NeighbourEdge> edges;
  int frame = -1;
  ASSERT_TRUE(ComputeDelaunayEdges(m, options, &edges, &frame).ok());
  EXPECT_EQ(frame, 0);
  // 4 sides, 4 spokes; point 5 joins its two nearest vertices in frame 1:
  // 2 (distance 0.1) and 1 (√1.01).
  const std::vector<std::pair<int, int>> expected = {
      {0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 4},
      {1, 5}, {2, 3}, {2, 4}, {2, 5}, {3, 4}};
  ASSERT_EQ(edges.size(), expected.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    EXPECT_EQ(edges[e].i, expected[e].first) << e;
    EXPECT_EQ(edges[e].j, expected[e].second) << e;
  }
}

TEST(ComputeSmoothnessStencils, HandComputedWeights) {
  const Measurements m = SquareMeasurements();
  DelaunayEdgesOptions options;
  options.num_hidden_neighbours = 2;
  std::vector<SmoothnessStencil> stencils;
  ASSERT_TRUE(ComputeSmoothnessStencils(m, options, &stencils).ok());
  ASSERT_EQ(stencils.size(), 6u);
  // Point 0 = (0, 0) from 1 = (1, 0), 3 = (0, 1), 4 = (0.5, 0.5): they lie
  // on one line, so no affine combination gives (0, 0); the nearest is
  // (0.5, 0.5), and its smallest weights are 1/3 each.
  EXPECT_EQ(stencils[0].neighbours, (std::vector<int>{1, 3, 4}));
  for (double w : stencils[0].weights) EXPECT_NEAR(w, 1.0 / 3.0, 1e-5);
  // Point 1: frame 0 sees 0, 2, 4 of its neighbours, frame 1 sees 0, 2, 5:
  // as many, so the reference view, again a line (1/3 each); 5 left out.
  EXPECT_EQ(stencils[1].neighbours, (std::vector<int>{0, 2, 4}));
  for (double w : stencils[1].weights) EXPECT_NEAR(w, 1.0 / 3.0, 1e-5);
  // The centre: the four corners, 1/4 each (exact).
  EXPECT_EQ(stencils[4].point, 4);
  EXPECT_EQ(stencils[4].neighbours, (std::vector<int>{0, 1, 2, 3}));
  for (double w : stencils[4].weights) EXPECT_NEAR(w, 0.25, 1e-9);
  // Point 5 = (1.1, 1), seen in frame 1 only, with 1 = (1, 0) and
  // 2 = (1, 1): the combinations are (1, w_2); the nearest to (1.1, 1) is
  // point 2 alone.
  EXPECT_EQ(stencils[5].neighbours, (std::vector<int>{1, 2}));
  EXPECT_NEAR(stencils[5].weights[0], 0.0, 1e-5);
  EXPECT_NEAR(stencils[5].weights[1], 1.0, 1e-5);
}

TEST(ComputeDelaunayEdges, ExplicitReferenceFrameAndErrors) {
  const Measurements m = SquareMeasurements();
  DelaunayEdgesOptions options;
  options.reference_frame = 1;
  options.num_hidden_neighbours = 1;
  std::vector<NeighbourEdge> edges;
  ASSERT_TRUE(ComputeDelaunayEdges(m, options, &edges).ok());
  // Frame 1: triangle {0, 1, 5}, {1, 2, 5}... of 0, 1, 2, 5 plus hidden 3, 4
  // joined to one vertex each (3 → 0 or 2 at distance 1; 4 → at √0.5).
  int edges_of_3 = 0;
  int edges_of_4 = 0;
  for (const NeighbourEdge& e : edges) {
    EXPECT_LT(e.i, e.j);
    edges_of_3 += (e.i == 3 || e.j == 3);
    edges_of_4 += (e.i == 4 || e.j == 4);
  }
  EXPECT_EQ(edges_of_3, 1);
  EXPECT_EQ(edges_of_4, 1);

  options.reference_frame = 2;
  EXPECT_FALSE(ComputeDelaunayEdges(m, options, &edges).ok());
  options.reference_frame = -2;
  EXPECT_FALSE(ComputeDelaunayEdges(m, options, &edges).ok());
  options.reference_frame = -1;
  options.num_hidden_neighbours = 0;
  EXPECT_FALSE(ComputeDelaunayEdges(m, options, &edges).ok());
}

}  // namespace
}  // namespace nrsfm
