#include "track/synthetic_video.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/math/random.h"

namespace nrsfm {
namespace track {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kTextureSize = 512;  // texels per side of a texture
constexpr int kMeshCells = 32;     // the sheet's mesh: cells per side
// The rest shape's depth at the corners, relative to bending (z of a bowl).
constexpr double kRestCurvature = 2.0;

// Sum of Gaussian blobs of random sign, size and place about grey 128.
cv::Mat BlobTexture(Random* random, int count) {
  cv::Mat texture(kTextureSize, kTextureSize, CV_32F, cv::Scalar(128));
  for (int b = 0; b < count; ++b) {
    const double cx = random->Uniform(0, kTextureSize);
    const double cy = random->Uniform(0, kTextureSize);
    const double sigma = random->Uniform(3.0, 9.0);
    const double amplitude = random->Uniform(-90.0, 90.0);
    const int r = static_cast<int>(3 * sigma);
    for (int y = std::max(0, static_cast<int>(cy) - r);
         y < std::min(kTextureSize, static_cast<int>(cy) + r); ++y) {
      float* row = texture.ptr<float>(y);
      for (int x = std::max(0, static_cast<int>(cx) - r);
           x < std::min(kTextureSize, static_cast<int>(cx) + r); ++x) {
        const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        row[x] +=
            static_cast<float>(amplitude * std::exp(-d2 / (2 * sigma * sigma)));
      }
    }
  }
  return texture;
}

// The sheet's texture in (u, v) ∈ [0, 1]²: blobs, stripes (constant along
// u), weak noise, in three bands of u.
cv::Mat SheetTexture(Random* random) {
  cv::Mat blobs = BlobTexture(random, 900);
  cv::Mat weak(kTextureSize, kTextureSize, CV_32F);
  for (int y = 0; y < kTextureSize; ++y) {
    for (int x = 0; x < kTextureSize; ++x) {
      weak.at<float>(y, x) = static_cast<float>(random->Normal());
    }
  }
  cv::GaussianBlur(weak, weak, cv::Size(0, 0), 3.0);
  cv::Scalar mean, stddev;
  cv::meanStdDev(weak, mean, stddev);
  weak = 128.0 + (weak - mean[0]) * (6.0 / stddev[0]);
  cv::Mat texture(kTextureSize, kTextureSize, CV_32F);
  for (int y = 0; y < kTextureSize; ++y) {
    const double v = (y + 0.5) / kTextureSize;
    const float stripe =
        static_cast<float>(128 + 70 * std::tanh(3 * std::sin(2 * kPi * 9 * v)));
    for (int x = 0; x < kTextureSize; ++x) {
      const double u = (x + 0.5) / kTextureSize;
      texture.at<float>(y, x) = u < 1.0 / 3   ? blobs.at<float>(y, x)
                                : u < 2.0 / 3 ? stripe
                                              : weak.at<float>(y, x);
    }
  }
  return texture;
}

float Bilinear(const cv::Mat& texture, double u, double v) {
  const double x =
      std::clamp(u * kTextureSize - 0.5, 0.0, kTextureSize - 1.001);
  const double y =
      std::clamp(v * kTextureSize - 0.5, 0.0, kTextureSize - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  return static_cast<float>((1 - fy) * ((1 - fx) * texture.at<float>(y0, x0) +
                                        fx * texture.at<float>(y0, x0 + 1)) +
                            fy * ((1 - fx) * texture.at<float>(y0 + 1, x0) +
                                  fx * texture.at<float>(y0 + 1, x0 + 1)));
}

}  // namespace

Status SyntheticVideoOptions::Check() const {
  if (frames < 2) return Status::Error("frames: expected at least 2");
  if (width < 64 || height < 64 || width > 8192 || height > 8192) {
    return Status::Error("width, height: expected 64 to 8192 pixels");
  }
  if (points_per_side < 2 || points_per_side > 64) {
    return Status::Error("points_per_side: expected 2 to 64");
  }
  if (num_bases < 0 || num_bases > 3) {
    return Status::Error("num_bases: expected 0 to 3 bending modes");
  }
  if (!(bending >= 0.0 && bending <= 1.0)) {
    return Status::Error("bending: expected 0 to 1");
  }
  if (!(std::abs(rotation_deg) <= 120.0)) {
    return Status::Error("rotation_deg: expected at most 120 degrees");
  }
  if (!(noise_grey >= 0.0 && noise_grey <= 50.0)) {
    return Status::Error("noise_grey: expected 0 to 50");
  }
  return Status::OK();
}

Status RenderSyntheticVideo(const SyntheticVideoOptions& options,
                            SyntheticVideo* video) {
  NRSFM_RETURN_IF_ERROR(options.Check());
  Random texture_random(options.seed, 0), motion_random(options.seed, 1),
      noise_random(options.seed, 2);
  const cv::Mat sheet_texture = SheetTexture(&texture_random);
  const cv::Mat disc_texture = BlobTexture(&texture_random, 600);
  const int num_frames = options.frames;
  const double w = options.width, h = options.height;
  const double side = 0.55 * w;  // the sheet's width, pixels
  const double aspect = std::min(0.75, 0.6 * h / side);
  double phase[3];
  for (double& p : phase) p = motion_random.Uniform(0, 2 * kPi);

  // Point (u, v) of the sheet at frame t in the camera frame (pixels).
  auto sheet_point = [&](double u, double v, int t) {
    const double time = static_cast<double>(t) / num_frames;
    const double modes[3] = {std::sin(kPi * u) * std::sin(kPi * v),
                             std::sin(2 * kPi * u) * std::sin(kPi * v),
                             std::sin(kPi * u) * std::sin(2 * kPi * v)};
    // The rest shape is curved (a saddle-free bowl), so that its depth is
    // seen as it turns.
    double z = kRestCurvature * ((u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5));
    for (int k = 0; k < options.num_bases; ++k) {
      z += std::sin(2 * kPi * (0.7 * k + 0.6) * time + phase[k]) * modes[k];
    }
    const Eigen::Vector3d rest((u - 0.5) * side, (v - 0.5) * side * aspect,
                               options.bending * side * z);
    const double yaw =
        0.5 * options.rotation_deg * kPi / 180 * std::sin(2 * kPi * time);
    const double pitch = 10.0 * kPi / 180 * std::sin(2 * kPi * time + 1.0);
    const Eigen::Matrix3d r =
        (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Vector3d centre(w / 2 + 0.08 * w * std::sin(2 * kPi * time),
                                 h / 2 + 0.05 * h * std::cos(2 * kPi * time),
                                 0.0);
    return Eigen::Vector3d(r * rest + centre);
  };

  const int n = options.points_per_side;
  const int num_points = n * n;
  SyntheticVideo result;
  result.x.resize(num_frames, num_points);
  result.y.resize(num_frames, num_points);
  result.visible = Eigen::MatrixXi::Zero(num_frames, num_points);
  result.shape.resize(num_frames, 3 * num_points);
  std::vector<Eigen::Vector2d> uv(num_points);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int p = j * n + i;
      uv[p] =
          Eigen::Vector2d(0.06 + 0.88 * i / (n - 1), 0.08 + 0.84 * j / (n - 1));
      result.texture.push_back(uv[p].x() < 1.0 / 3   ? Texture::kCorners
                               : uv[p].x() < 2.0 / 3 ? Texture::kEdges
                                                     : Texture::kWeak);
    }
  }

  const int g = kMeshCells + 1;
  const double disc_radius = 0.14 * h;
  for (int t = 0; t < num_frames; ++t) {
    // The sheet's mesh, projected.
    std::vector<Eigen::Vector3d> vertex(g * g);
    for (int j = 0; j < g; ++j) {
      for (int i = 0; i < g; ++i) {
        vertex[j * g + i] = sheet_point(static_cast<double>(i) / kMeshCells,
                                        static_cast<double>(j) / kMeshCells, t);
      }
    }
    cv::Mat depth(options.height, options.width, CV_64F,
                  cv::Scalar(std::numeric_limits<double>::infinity()));
    cv::Mat image(options.height, options.width, CV_32F, cv::Scalar(70));
    for (int j = 0; j < kMeshCells; ++j) {
      for (int i = 0; i < kMeshCells; ++i) {
        const int corners[2][3] = {
            {j * g + i, j * g + i + 1, (j + 1) * g + i},
            {j * g + i + 1, (j + 1) * g + i + 1, (j + 1) * g + i}};
        for (const auto& tri : corners) {
          const Eigen::Vector3d& a = vertex[tri[0]];
          const Eigen::Vector3d& b = vertex[tri[1]];
          const Eigen::Vector3d& c = vertex[tri[2]];
          const Eigen::Vector3d normal = (b - a).cross(c - a);
          const float shade = static_cast<float>(
              0.8 + 0.2 * std::abs(normal.z()) / (normal.norm() + 1e-12));
          const double area = (b.x() - a.x()) * (c.y() - a.y()) -
                              (c.x() - a.x()) * (b.y() - a.y());
          if (std::abs(area) < 1e-12) continue;
          auto tex = [&](int k) {
            const int idx = tri[k];
            return Eigen::Vector2d(static_cast<double>(idx % g) / kMeshCells,
                                   static_cast<double>(idx / g) / kMeshCells);
          };
          const Eigen::Vector2d ta = tex(0), tb = tex(1), tc = tex(2);
          const int x0 = std::max(
              0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
          const int x1 = std::min(
              options.width - 1,
              static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
          const int y0 = std::max(
              0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
          const int y1 = std::min(
              options.height - 1,
              static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
          for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
              const double wa =
                  ((b.x() - x) * (c.y() - y) - (c.x() - x) * (b.y() - y)) /
                  area;
              const double wb =
                  ((c.x() - x) * (a.y() - y) - (a.x() - x) * (c.y() - y)) /
                  area;
              const double wc = 1.0 - wa - wb;
              if (wa < -1e-9 || wb < -1e-9 || wc < -1e-9) continue;
              const double z = wa * a.z() + wb * b.z() + wc * c.z();
              if (z >= depth.at<double>(y, x)) continue;
              depth.at<double>(y, x) = z;
              const Eigen::Vector2d st = wa * ta + wb * tb + wc * tc;
              image.at<float>(y, x) =
                  shade * Bilinear(sheet_texture, st.x(), st.y());
            }
          }
        }
      }
    }
    // The disc, in front of everything, across the middle of the sequence.
    const double start = 0.25 * num_frames, end = 0.75 * num_frames;
    bool disc = options.occluder && t >= start && t <= end;
    const double disc_x =
        -disc_radius + (w + 2 * disc_radius) * (t - start) / (end - start);
    const double disc_y = 0.5 * h;
    if (disc) {
      for (int y = 0; y < options.height; ++y) {
        for (int x = 0; x < options.width; ++x) {
          const double dx = x - disc_x, dy = y - disc_y;
          if (dx * dx + dy * dy > disc_radius * disc_radius) continue;
          image.at<float>(y, x) =
              Bilinear(disc_texture, 0.5 + dx / (4 * disc_radius),
                       0.5 + dy / (4 * disc_radius));
          depth.at<double>(y, x) = -std::numeric_limits<double>::infinity();
        }
      }
    }
    for (int p = 0; p < num_points; ++p) {
      const Eigen::Vector3d point = sheet_point(uv[p].x(), uv[p].y(), t);
      result.x(t, p) = point.x();
      result.y(t, p) = point.y();
      result.shape.block<1, 3>(t, 3 * p) = point.transpose();
      const int px = static_cast<int>(std::lround(point.x()));
      const int py = static_cast<int>(std::lround(point.y()));
      bool seen =
          px >= 0 && py >= 0 && px < options.width && py < options.height;
      if (seen) seen = point.z() <= depth.at<double>(py, px) + 0.02 * side;
      if (seen && disc) {
        seen = std::hypot(point.x() - disc_x, point.y() - disc_y) >
               disc_radius + 1.0;
      }
      result.visible(t, p) = seen ? 1 : 0;
    }
    cv::Mat noisy(image.size(), CV_32F);
    for (int y = 0; y < options.height; ++y) {
      for (int x = 0; x < options.width; ++x) {
        noisy.at<float>(y, x) =
            image.at<float>(y, x) +
            static_cast<float>(options.noise_grey * noise_random.Normal());
      }
    }
    cv::Mat grey;
    noisy.convertTo(grey, CV_8U);  // rounds and saturates
    result.frames.push_back(grey);
  }
  *video = std::move(result);
  return Status::OK();
}

void QueriesAndTruth(const SyntheticVideo& video, std::vector<Query>* queries,
                     TrackTruth* truth) {
  queries->clear();
  for (Eigen::Index p = 0; p < video.x.cols(); ++p) {
    if (video.visible(0, p)) {
      queries->push_back(
          {static_cast<int>(p), 0, video.x(0, p), video.y(0, p)});
    }
  }
  const Eigen::Index frames = video.x.rows();
  const Eigen::Index points = static_cast<Eigen::Index>(queries->size());
  truth->x.resize(frames, points);
  truth->y.resize(frames, points);
  truth->visible.resize(frames, points);
  truth->labelled = Eigen::MatrixXi::Ones(frames, points);
  for (Eigen::Index k = 0; k < points; ++k) {
    const int p = (*queries)[k].point;
    truth->x.col(k) = video.x.col(p);
    truth->y.col(k) = video.y.col(p);
    truth->visible.col(k) = video.visible.col(p);
  }
}

}  // namespace track
}  // namespace nrsfm
