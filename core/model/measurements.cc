#include "core/model/measurements.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>
#include <vector>

namespace nrsfm {

int Measurements::NumVisible() const {
  return static_cast<int>(visible.count());
}

Eigen::VectorXi Measurements::VisiblePerView() const {
  return visible.rowwise().count().cast<int>().matrix();
}

Eigen::VectorXi Measurements::VisiblePerPoint() const {
  return visible.colwise().count().cast<int>().matrix().transpose();
}

double Measurements::ImageSpreadRms() const {
  // The sums run view by view, point by point; W and `visible` are read
  // point by point (column by column: a view's entries are 2·F·M values
  // apart), the squared distances kept and then added in that order.
  const int views = NumViews();
  Eigen::Matrix2Xd centroid = Eigen::Matrix2Xd::Zero(2, views);
  std::vector<int> n(views, 0);
  for (int p = 0; p < num_points; ++p) {
    for (int view = 0; view < views; ++view) {
      if (!visible(view, p)) continue;
      centroid.col(view) += W.block<2, 1>(2 * view, p);
      ++n[view];
    }
  }
  for (int view = 0; view < views; ++view) {
    if (n[view] > 0) centroid.col(view) /= n[view];
  }
  Eigen::MatrixXd squared(num_points, views);  // column: a view
  for (int p = 0; p < num_points; ++p) {
    for (int view = 0; view < views; ++view) {
      if (visible(view, p)) {
        squared(p, view) =
            (W.block<2, 1>(2 * view, p) - centroid.col(view)).squaredNorm();
      }
    }
  }
  double sum = 0.0;
  int count = 0;
  for (int view = 0; view < views; ++view) {
    for (int p = 0; p < num_points; ++p) {
      if (!visible(view, p)) continue;
      sum += squared(p, view);
      ++count;
    }
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

Status Measurements::FromMatrixWithNaN(const Eigen::MatrixXd& w,
                                       int num_cameras, const std::string& name,
                                       Measurements* measurements) {
  if (num_cameras < 1) {
    return Status::Error(name + ": number of cameras must be >= 1, got " +
                         std::to_string(num_cameras));
  }
  if (w.rows() == 0 || w.cols() == 0) {
    return Status::Error(name + ": matrix is empty (" +
                         std::to_string(w.rows()) + " x " +
                         std::to_string(w.cols()) + ")");
  }
  if (w.rows() % (2 * num_cameras) != 0) {
    std::ostringstream msg;
    msg << name << ": " << w.rows() << " rows is not a multiple of 2";
    if (num_cameras > 1) msg << " x " << num_cameras << " cameras";
    msg << " (expected rows u, v per frame"
        << (num_cameras > 1 ? " and camera" : "") << ")";
    return Status::Error(msg.str());
  }
  Measurements m;
  m.num_cameras = num_cameras;
  m.num_points = static_cast<int>(w.cols());
  m.num_frames = static_cast<int>(w.rows() / (2 * num_cameras));
  m.W = w;
  m.visible.resize(m.NumViews(), m.num_points);
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      const double u = w(2 * view, p);
      const double v = w(2 * view + 1, p);
      if (std::isinf(u) || std::isinf(v)) {
        std::ostringstream msg;
        msg << name << ": infinite value at row "
            << (std::isinf(u) ? 2 * view + 1 : 2 * view + 2) << ", column "
            << p + 1 << " (1-based); use NaN to mark a missing entry";
        return Status::Error(msg.str());
      }
      const bool u_missing = std::isnan(u);
      const bool v_missing = std::isnan(v);
      if (u_missing != v_missing) {
        std::ostringstream msg;
        msg << name << ": only one coordinate of the observation at rows "
            << 2 * view + 1 << "-" << 2 * view + 2 << ", column " << p + 1
            << " (1-based) is NaN; mark a missing point with NaN in both";
        return Status::Error(msg.str());
      }
      m.visible(view, p) = !u_missing;
    }
  }
  *measurements = std::move(m);
  return Status::OK();
}

Status Measurements::Validate() const {
  std::ostringstream msg;
  if (num_frames < 1 || num_cameras < 1 || num_points < 1) {
    msg << "measurements: need F >= 1, M >= 1, P >= 1; got F = " << num_frames
        << ", M = " << num_cameras << ", P = " << num_points;
    return Status::Error(msg.str());
  }
  if (W.rows() != 2 * NumViews() || W.cols() != num_points) {
    msg << "measurements: W is " << W.rows() << " x " << W.cols()
        << ", expected " << 2 * NumViews() << " x " << num_points;
    return Status::Error(msg.str());
  }
  if (visible.rows() != NumViews() || visible.cols() != num_points) {
    msg << "measurements: visibility mask is " << visible.rows() << " x "
        << visible.cols() << ", expected " << NumViews() << " x " << num_points;
    return Status::Error(msg.str());
  }
  for (const auto& [ids, count, what] :
       {std::make_tuple(&frame_ids, num_frames, "frame_ids"),
        std::make_tuple(&point_ids, num_points, "point_ids")}) {
    bool increasing = ids->empty() || (*ids)[0] >= 0;
    for (std::size_t i = 1; i < ids->size(); ++i)
      increasing = increasing && (*ids)[i - 1] < (*ids)[i];
    if ((!ids->empty() && static_cast<int>(ids->size()) != count) ||
        !increasing) {
      msg << "measurements: " << what << " has " << ids->size()
          << " entries, expected none or " << count
          << " strictly increasing from 0 up";
      return Status::Error(msg.str());
    }
  }
  for (int view = 0; view < NumViews(); ++view) {
    for (int p = 0; p < num_points; ++p) {
      if (!visible(view, p)) continue;
      if (!std::isfinite(W(2 * view, p)) ||
          !std::isfinite(W(2 * view + 1, p))) {
        msg << "measurements: visible entry of frame " << view / num_cameras
            << ", camera " << view % num_cameras << ", point " << p
            << " is not finite";
        return Status::Error(msg.str());
      }
    }
  }
  if (intrinsics.cols() != 0) {
    if (intrinsics.cols() != num_cameras) {
      msg << "measurements: intrinsics for " << intrinsics.cols()
          << " cameras, but the data have " << num_cameras;
      return Status::Error(msg.str());
    }
    for (int c = 0; c < num_cameras; ++c) {
      if (!intrinsics.col(c).allFinite() || !(intrinsics(0, c) > 0.0) ||
          !(intrinsics(1, c) > 0.0)) {
        msg << "measurements: intrinsics of camera " << c
            << " need finite values and fx, fy > 0 (got "
            << intrinsics.col(c).transpose() << ")";
        return Status::Error(msg.str());
      }
    }
  }
  return Status::OK();
}

}  // namespace nrsfm
