#include "problems/delaunay_edges.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "core/model/option_checker.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace nrsfm {
namespace {

// Qhull's messages go to a FILE*; this one collects them in memory so the
// library prints nothing and the error can carry them.
class MemoryStream {
 public:
  MemoryStream() : file_(open_memstream(&buffer_, &size_)) {}
  ~MemoryStream() {
    if (file_ != nullptr) std::fclose(file_);
    std::free(buffer_);
  }
  MemoryStream(const MemoryStream&) = delete;
  MemoryStream& operator=(const MemoryStream&) = delete;
  FILE* file() { return file_; }
  std::string Text() {
    if (file_ == nullptr) return "";
    std::fflush(file_);
    return buffer_ == nullptr ? "" : std::string(buffer_, size_);
  }

 private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  FILE* file_;
};

}  // namespace

Status DelaunayEdgesOptions::Check() const {
  OptionChecker check("delaunay edges options");
  check.Require(reference_frame >= -1,
                "reference_frame must be -1 (auto) or a frame index, got " +
                    std::to_string(reference_frame));
  check.AtLeast("num_hidden_neighbours", num_hidden_neighbours, 1);
  return check.status();
}

Status DelaunayTriangulation(const Eigen::Matrix2Xd& points,
                             std::vector<std::array<int, 3>>* triangles) {
  CHECK(triangles != nullptr);
  triangles->clear();
  const int n = static_cast<int>(points.cols());
  if (n < 3) {
    return Status::Error(
        "Delaunay triangulation needs at least 3 points, got " +
        std::to_string(n));
  }
  if (!points.allFinite()) {
    return Status::Error("Delaunay triangulation: a point is not finite");
  }
  std::vector<coordT> coordinates(points.data(), points.data() + 2 * n);
  MemoryStream messages;
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, messages.file());
  // d: Delaunay; Qt: triangulated output; Qbb: scale the lifted coordinate
  // (precision); Qc: keep duplicates as coplanar points (not vertices).
  char command[] = "qhull d Qt Qbb Qc";
  const int exit_code = qh_new_qhull(qh, 2, n, coordinates.data(), False,
                                     command, nullptr, messages.file());
  if (exit_code == 0) {
    facetT* facet;
    vertexT* vertex;
    vertexT** vertexp;
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      std::array<int, 3> triangle{};
      int count = 0;
      FOREACHvertex_(facet->vertices) {
        if (count < 3) triangle[count] = qh_pointid(qh, vertex->point);
        ++count;
      }
      if (count != 3) continue;
      const Eigen::Vector2d a =
          points.col(triangle[1]) - points.col(triangle[0]);
      const Eigen::Vector2d b =
          points.col(triangle[2]) - points.col(triangle[0]);
      if (a.x() * b.y() - a.y() * b.x() < 0.0)
        std::swap(triangle[1], triangle[2]);
      triangles->push_back(triangle);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int current_long = 0;
  int total_long = 0;
  qh_memfreeshort(qh, &current_long, &total_long);
  if (exit_code != 0 || triangles->empty()) {
    std::string detail = messages.Text();
    const std::size_t end = detail.find('\n');
    if (end != std::string::npos) detail.resize(end);
    return Status::Error("Delaunay triangulation of " + std::to_string(n) +
                         " points failed (are they all collinear?)" +
                         (detail.empty() ? "" : ": qhull: " + detail));
  }
  std::sort(triangles->begin(), triangles->end());
  return Status::OK();
}

Status ComputeDelaunayEdges(const Measurements& measurements,
                            const DelaunayEdgesOptions& options,
                            std::vector<NeighbourEdge>* edges,
                            int* reference_frame_used) {
  CHECK(edges != nullptr);
  edges->clear();
  NRSFM_RETURN_IF_ERROR(options.Check());
  NRSFM_RETURN_IF_ERROR(measurements.Validate());
  const Measurements& m = measurements;
  int frame = options.reference_frame;
  if (frame >= m.num_frames) {
    return Status::Error(
        "delaunay edges: reference_frame " + std::to_string(frame) +
        " is out of range (F = " + std::to_string(m.num_frames) + ")");
  }
  if (frame < 0) {
    int best = -1;
    for (int t = 0; t < m.num_frames; ++t) {
      const int count = static_cast<int>(m.visible.row(m.View(t, 0)).count());
      if (count > best) {
        best = count;
        frame = t;
      }
    }
  }
  if (reference_frame_used != nullptr) *reference_frame_used = frame;

  const int reference_view = m.View(frame, 0);
  std::vector<int> visible_points;
  for (int p = 0; p < m.num_points; ++p) {
    if (m.visible(reference_view, p)) visible_points.push_back(p);
  }
  Eigen::Matrix2Xd positions(2, visible_points.size());
  for (std::size_t i = 0; i < visible_points.size(); ++i) {
    positions.col(i) = m.Observation(frame, 0, visible_points[i]);
  }
  std::vector<std::array<int, 3>> triangles;
  const Status triangulated = DelaunayTriangulation(positions, &triangles);
  if (!triangulated.ok()) {
    return Status::Error("delaunay edges: reference frame " +
                         std::to_string(frame) + ": " + triangulated.message());
  }

  // Edges of the triangulation.
  std::set<std::pair<int, int>> pairs;
  std::vector<bool> is_vertex(m.num_points, false);
  for (const std::array<int, 3>& triangle : triangles) {
    for (int e = 0; e < 3; ++e) {
      const int a = triangle[e];
      const int b = triangle[(e + 1) % 3];
      const int i = std::min(visible_points[a], visible_points[b]);
      const int j = std::max(visible_points[a], visible_points[b]);
      pairs.insert({i, j});
      is_vertex[i] = is_vertex[j] = true;
    }
  }
  // Non-vertex points: mean distance to every vertex over the shared views.
  std::vector<int> vertices;
  std::vector<int> others;
  for (int p = 0; p < m.num_points; ++p) {
    (is_vertex[p] ? vertices : others).push_back(p);
  }
  if (!others.empty()) {
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(others.size(), vertices.size());
    Eigen::MatrixXi count =
        Eigen::MatrixXi::Zero(others.size(), vertices.size());
    for (int t = 0; t < m.num_frames; ++t) {
      for (int c = 0; c < m.num_cameras; ++c) {
        const int view = m.View(t, c);
        for (std::size_t o = 0; o < others.size(); ++o) {
          if (!m.visible(view, others[o])) continue;
          const Eigen::Vector2d x = m.Observation(t, c, others[o]);
          for (std::size_t v = 0; v < vertices.size(); ++v) {
            if (!m.visible(view, vertices[v])) continue;
            sum(o, v) += (m.Observation(t, c, vertices[v]) - x).norm();
            ++count(o, v);
          }
        }
      }
    }
    for (std::size_t o = 0; o < others.size(); ++o) {
      std::vector<std::pair<double, int>> candidates;
      for (std::size_t v = 0; v < vertices.size(); ++v) {
        if (count(o, v) > 0) {
          candidates.emplace_back(sum(o, v) / count(o, v), vertices[v]);
        }
      }
      const std::size_t keep = std::min<std::size_t>(
          candidates.size(), options.num_hidden_neighbours);
      std::partial_sort(candidates.begin(), candidates.begin() + keep,
                        candidates.end());
      for (std::size_t k = 0; k < keep; ++k) {
        const int i = std::min(others[o], candidates[k].second);
        const int j = std::max(others[o], candidates[k].second);
        pairs.insert({i, j});
      }
    }
  }

  for (const auto& [i, j] : pairs) edges->push_back({i, j});
  return Status::OK();
}

Status ComputeSmoothnessStencils(const Measurements& measurements,
                                 const DelaunayEdgesOptions& options,
                                 std::vector<SmoothnessStencil>* stencils,
                                 int* reference_frame_used) {
  CHECK(stencils != nullptr);
  stencils->clear();
  std::vector<NeighbourEdge> edges;
  int frame = -1;
  NRSFM_RETURN_IF_ERROR(
      ComputeDelaunayEdges(measurements, options, &edges, &frame));
  if (reference_frame_used != nullptr) *reference_frame_used = frame;
  const Measurements& m = measurements;
  std::vector<std::vector<int>> neighbours(m.num_points);
  for (const NeighbourEdge& e : edges) {
    neighbours[e.i].push_back(e.j);
    neighbours[e.j].push_back(e.i);
  }
  constexpr double kEpsilon = 1e-6;
  const int reference_view = m.View(frame, 0);
  for (int i = 0; i < m.num_points; ++i) {
    std::vector<int>& n = neighbours[i];
    if (n.empty()) continue;
    std::sort(n.begin(), n.end());
    // The view that sees i and the most of its neighbours.
    auto seen = [&](int view) {
      if (!m.visible(view, i)) return -1;
      int count = 0;
      for (int j : n) count += m.visible(view, j) ? 1 : 0;
      return count;
    };
    int best_view = reference_view;
    int best = seen(reference_view);
    for (int view = 0; view < m.NumViews() && best < static_cast<int>(n.size());
         ++view) {
      const int count = seen(view);
      if (count > best) {
        best = count;
        best_view = view;
      }
    }
    // A vertex is seen with its triangles' vertices in the reference view;
    // another point is joined only to vertices it shares a view with.
    CHECK_GT(best, 0) << "point " << i << " shares no view with a neighbour";
    SmoothnessStencil stencil;
    stencil.point = i;
    const int t = best_view / m.num_cameras, c = best_view % m.num_cameras;
    const Eigen::Vector2d x_i = m.Observation(t, c, i);
    for (int j : n) {
      if (m.visible(best_view, j)) stencil.neighbours.push_back(j);
    }
    const int count = static_cast<int>(stencil.neighbours.size());
    Eigen::Matrix2Xd d(2, count);
    for (int q = 0; q < count; ++q) {
      d.col(q) = m.Observation(t, c, stencil.neighbours[q]) - x_i;
    }
    const double rho = std::sqrt(d.squaredNorm() / count);
    if (rho > 0.0) d /= rho;
    const Eigen::MatrixXd gram =
        Eigen::MatrixXd::Identity(count, count) + d.transpose() * d / kEpsilon;
    const Eigen::VectorXd w = gram.ldlt().solve(Eigen::VectorXd::Ones(count));
    const double sum = w.sum();
    for (int q = 0; q < count; ++q) stencil.weights.push_back(w(q) / sum);
    stencils->push_back(std::move(stencil));
  }
  return Status::OK();
}

}  // namespace nrsfm
