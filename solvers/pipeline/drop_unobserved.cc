#include "solvers/pipeline/drop_unobserved.h"

#include <glog/logging.h>

#include <algorithm>
#include <limits>
#include <sstream>

namespace nrsfm {
namespace {

constexpr int kMaxListed = 20;

// The least number of kept points a view of frame t sees, and that view's
// camera.
int FewestPointsOfFrame(const Measurements& m,
                        const std::vector<bool>& point_kept, int t,
                        int* camera) {
  int fewest = std::numeric_limits<int>::max();
  for (int c = 0; c < m.num_cameras; ++c) {
    int count = 0;
    for (int p = 0; p < m.num_points; ++p) {
      count += point_kept[p] && m.visible(m.View(t, c), p);
    }
    if (count < fewest) {
      fewest = count;
      *camera = c;
    }
  }
  return fewest;
}

}  // namespace

std::vector<int> KeptIndices(int count, const std::vector<int>& left_out) {
  std::vector<int> kept;
  for (int index = 0, i = 0; index < count; ++index) {
    if (i < static_cast<int>(left_out.size()) && left_out[i] == index) {
      ++i;
    } else {
      kept.push_back(index);
    }
  }
  return kept;
}

int MinViewsPerPoint(int num_bases) {
  return std::max(2, (3 * num_bases + 1) / 2);
}

int MinPointsPerView(int num_bases) { return std::max(4, (num_bases + 6) / 2); }

Status FindUnobserved(const Measurements& measurements, int num_bases,
                      Unobserved* unobserved) {
  CHECK(unobserved != nullptr);
  CHECK_GE(num_bases, 1);
  *unobserved = Unobserved();
  unobserved->num_bases = num_bases;
  const Measurements& m = measurements;
  // Too small for K (also keeps 3K + 1 below the int range).
  if (m.IsComplete() || m.num_frames < 2 ||
      static_cast<long long>(num_bases) * 3 + 1 >
          std::min(2LL * m.num_frames, static_cast<long long>(m.num_points))) {
    return Status::OK();
  }
  // What the model with K bases needs (header): per view, per point.
  const int needed_points = MinPointsPerView(num_bases);
  const int needed_views = MinViewsPerPoint(num_bases);
  const int needed_for_k = 3 * num_bases + 1;
  std::vector<bool> point_kept(m.num_points, true),
      frame_kept(m.num_frames, true);
  for (bool changed = true; changed;) {
    changed = false;
    for (int p = 0; p < m.num_points; ++p) {
      if (!point_kept[p]) continue;
      int views = 0;
      for (int t = 0; t < m.num_frames; ++t) {
        if (!frame_kept[t]) continue;
        for (int c = 0; c < m.num_cameras; ++c)
          views += m.visible(m.View(t, c), p);
      }
      if (views < needed_views) point_kept[p] = false, changed = true;
    }
    for (int t = 0; t < m.num_frames; ++t) {
      if (!frame_kept[t]) continue;
      int camera = 0;
      if (FewestPointsOfFrame(m, point_kept, t, &camera) < needed_points) {
        frame_kept[t] = false;
        changed = true;
      }
    }
  }
  for (int p = 0; p < m.num_points; ++p) {
    if (!point_kept[p]) unobserved->points.push_back(p);
  }
  for (int t = 0; t < m.num_frames; ++t) {
    if (!frame_kept[t]) unobserved->frames.push_back(t);
  }
  const int kept_frames =
      m.num_frames - static_cast<int>(unobserved->frames.size());
  const int kept_points =
      m.num_points - static_cast<int>(unobserved->points.size());
  if (kept_frames < 2 || 2 * kept_frames < needed_for_k ||
      kept_points < needed_for_k) {
    std::ostringstream msg;
    msg << "start: too few observations for K = " << num_bases
        << ": leaving out the " << unobserved->points.size()
        << " points seen in fewer than " << needed_views << " views and the "
        << unobserved->frames.size() << " frames whose views see fewer than "
        << needed_points << " points leaves F = " << kept_frames
        << ", P = " << kept_points << " (K = " << num_bases
        << " needs F >= 2, 2F >= " << needed_for_k
        << " and P >= " << needed_for_k << ")";
    return Status::Error(msg.str());
  }
  return Status::OK();
}

Measurements WithoutUnobserved(const Measurements& measurements,
                               const Unobserved& unobserved) {
  const Measurements& m = measurements;
  const std::vector<int> frames = KeptIndices(m.num_frames, unobserved.frames);
  const std::vector<int> points = KeptIndices(m.num_points, unobserved.points);
  Measurements kept;
  kept.num_frames = static_cast<int>(frames.size());
  kept.num_cameras = m.num_cameras;
  kept.num_points = static_cast<int>(points.size());
  kept.intrinsics = m.intrinsics;
  kept.W.resize(2 * kept.NumViews(), kept.num_points);
  kept.visible.resize(kept.NumViews(), kept.num_points);
  for (int i = 0; i < kept.num_frames; ++i) {
    for (int c = 0; c < m.num_cameras; ++c) {
      for (int j = 0; j < kept.num_points; ++j) {
        kept.W.block<2, 1>(kept.Row(i, c), j) =
            m.W.block<2, 1>(m.Row(frames[i], c), points[j]);
        kept.visible(kept.View(i, c), j) =
            m.visible(m.View(frames[i], c), points[j]);
      }
    }
  }
  return kept;
}

Eigen::ArrayXXd WithoutUnobserved(const Eigen::ArrayXXd& per_observation,
                                  const Measurements& measurements,
                                  const Unobserved& unobserved) {
  const Measurements& m = measurements;
  if (per_observation.rows() != m.NumViews() ||
      per_observation.cols() != m.num_points) {
    return per_observation;
  }
  const std::vector<int> frames = KeptIndices(m.num_frames, unobserved.frames);
  const std::vector<int> points = KeptIndices(m.num_points, unobserved.points);
  const int num_cameras = m.num_cameras;
  Eigen::ArrayXXd kept(static_cast<int>(frames.size()) * num_cameras,
                       points.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    for (int c = 0; c < num_cameras; ++c) {
      for (std::size_t j = 0; j < points.size(); ++j) {
        kept(i * num_cameras + c, j) =
            per_observation(m.View(frames[i], c), points[j]);
      }
    }
  }
  return kept;
}

ProblemOptions WithoutUnobserved(const ProblemOptions& options,
                                 const Measurements& measurements,
                                 const Unobserved& unobserved) {
  ProblemOptions kept = options;
  kept.observation_weights =
      WithoutUnobserved(options.observation_weights, measurements, unobserved);
  int& reference = kept.smoothness_edges.reference_frame;
  if (reference >= 0) {
    const auto& dropped = unobserved.frames;
    if (std::binary_search(dropped.begin(), dropped.end(), reference)) {
      reference = -1;  // a left-out frame: the default choice among the kept
    } else {
      reference -= static_cast<int>(
          std::lower_bound(dropped.begin(), dropped.end(), reference) -
          dropped.begin());
    }
  }
  return kept;
}

Model WithoutUnobserved(const Model& model, const Unobserved& unobserved) {
  const std::vector<int> frames =
      KeptIndices(model.num_frames, unobserved.frames);
  const std::vector<int> points =
      KeptIndices(model.num_points, unobserved.points);
  Model kept;
  kept.Resize(static_cast<int>(frames.size()), model.num_cameras,
              static_cast<int>(points.size()), model.num_bases);
  kept.camera = model.camera;
  kept.intrinsics = model.intrinsics;
  kept.rig_rotations = model.rig_rotations;
  kept.rig_scales = model.rig_scales;
  for (size_t k = 0; k < frames.size(); ++k) {
    for (int c = 0; c < model.num_cameras; ++c) {
      const int from = model.View(frames[k], c), to = kept.View(k, c);
      kept.rotations.col(to) = model.rotations.col(from);
      kept.translations.col(to) = model.translations.col(from);
      kept.scales(to) = model.scales(from);
      kept.depths(to) = model.depths(from);
    }
    kept.weights.col(k) = model.weights.col(frames[k]);
  }
  for (size_t k = 0; k < points.size(); ++k) {
    kept.basis.col(k) = model.basis.col(points[k]);
  }
  return kept;
}

Model ExpandModel(const Model& kept, const Measurements& measurements,
                  const Unobserved& unobserved) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Measurements& m = measurements;
  Model model;
  model.Resize(m.num_frames, m.num_cameras, m.num_points, kept.num_bases);
  model.rotations.setConstant(nan);
  model.translations.setConstant(nan);
  model.scales.setConstant(nan);
  model.depths.setConstant(nan);
  model.camera = kept.camera;
  model.intrinsics = kept.intrinsics;
  model.weights.setConstant(nan);
  model.basis.setConstant(nan);
  model.rig_rotations = kept.rig_rotations;
  model.rig_scales = kept.rig_scales;
  for (int t = 0, i = 0, k = 0; t < m.num_frames; ++t) {
    if (i < static_cast<int>(unobserved.frames.size()) &&
        unobserved.frames[i] == t) {
      ++i;
      continue;
    }
    for (int c = 0; c < m.num_cameras; ++c) {
      model.rotations.col(model.View(t, c)) =
          kept.rotations.col(kept.View(k, c));
      model.translations.col(model.View(t, c)) =
          kept.translations.col(kept.View(k, c));
      model.scales(model.View(t, c)) = kept.scales(kept.View(k, c));
      model.depths(model.View(t, c)) = kept.depths(kept.View(k, c));
    }
    model.weights.col(t) = kept.weights.col(k);
    ++k;
  }
  for (int p = 0, i = 0, k = 0; p < m.num_points; ++p) {
    if (i < static_cast<int>(unobserved.points.size()) &&
        unobserved.points[i] == p) {
      ++i;
      continue;
    }
    model.basis.col(p) = kept.basis.col(k++);
  }
  return model;
}

std::string UnobservedWarning(const Measurements& measurements,
                              const Unobserved& unobserved) {
  const Measurements& m = measurements;
  std::ostringstream out;
  out << "left out of the reconstruction (K = " << unobserved.num_bases
      << " needs every point seen in at least "
      << MinViewsPerPoint(unobserved.num_bases)
      << " views and every frame's views to see at least "
      << MinPointsPerView(unobserved.num_bases)
      << " points), NaN in the result:";
  const Eigen::VectorXi per_point = m.VisiblePerPoint();
  const int num_points = static_cast<int>(unobserved.points.size());
  for (int i = 0; i < num_points && i < kMaxListed; ++i) {
    const int p = unobserved.points[i];
    out << (i == 0 ? " " : ", ") << "point " << p << " (seen in "
        << per_point(p) << (per_point(p) == 1 ? " view)" : " views)");
  }
  if (num_points > kMaxListed)
    out << " and " << num_points - kMaxListed << " more points";
  if (num_points > 0 && !unobserved.frames.empty()) out << ";";
  std::vector<bool> point_kept(m.num_points, true);
  for (int p : unobserved.points) point_kept[p] = false;
  const int num_frames = static_cast<int>(unobserved.frames.size());
  for (int i = 0; i < num_frames && i < kMaxListed; ++i) {
    const int t = unobserved.frames[i];
    int camera = 0;
    const int fewest = FewestPointsOfFrame(m, point_kept, t, &camera);
    out << (i == 0 ? " " : ", ") << "frame " << t << " (";
    if (m.num_cameras > 1) out << "camera " << camera << " ";
    out << "sees " << fewest << (fewest == 1 ? " point" : " points");
    if (!unobserved.points.empty()) out << " of those kept";
    out << ")";
  }
  if (num_frames > kMaxListed)
    out << " and " << num_frames - kMaxListed << " more frames";
  return out.str();
}

}  // namespace nrsfm
