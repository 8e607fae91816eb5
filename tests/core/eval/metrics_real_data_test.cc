// e3D against the published PTA numbers (Akhter et al. 2008), from the
// reconstruction `Shat` that ships with the Akhter sequences: e3D(S · scale,
// Shat) with the world-frame S (../shared/datasets/README.md).
#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/mat_io.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

// Frames of a 3F × P matrix with rows x_t, y_t, z_t interleaved.
std::vector<Eigen::Matrix3Xd> InterleavedFrames(const Eigen::MatrixXd& s) {
  std::vector<Eigen::Matrix3Xd> frames;
  for (Eigen::Index t = 0; t < s.rows() / 3; ++t)
    frames.push_back(s.middleRows(3 * t, 3));
  return frames;
}

struct PublishedE3D {
  const char* sequence;
  int num_frames;
  double pta_e3d;
};

class RealDataE3D : public ::testing::TestWithParam<PublishedE3D> {};

TEST_P(RealDataE3D, ReproducesPublishedPTA) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  const PublishedE3D& published = GetParam();
  const std::string path = dir + "/" + published.sequence + ".mat";
  Eigen::MatrixXd s, s_hat, scale;
  ASSERT_TRUE(ReadMatVariable(path, "S", &s).ok());
  ASSERT_TRUE(ReadMatVariable(path, "Shat", &s_hat).ok());
  ASSERT_TRUE(ReadMatVariable(path, "scale", &scale).ok());
  ASSERT_EQ(scale.size(), 1);
  ASSERT_EQ(s.rows(), 3 * published.num_frames);
  ASSERT_EQ(s.rows(), s_hat.rows());
  ASSERT_EQ(s.cols(), s_hat.cols());

  const std::vector<Eigen::Matrix3Xd> truth =
      InterleavedFrames(s * scale(0, 0));
  const std::vector<Eigen::Matrix3Xd> estimate = InterleavedFrames(s_hat);
  // Both are world-frame (object-frame) shapes: the published protocol.
  const double e3d = ComputeE3D(truth, estimate);
  std::cout << published.sequence << ": e3D " << e3d << " (PTA "
            << published.pta_e3d << ")" << std::endl;
  EXPECT_EQ(truth.size(), static_cast<std::size_t>(published.num_frames));
  EXPECT_EQ(truth[0].cols(), 41);
  EXPECT_NEAR(e3d, published.pta_e3d, 0.00005);
  // Scaling the estimate is not aligned away by e3D (no similarity fit).
  std::vector<Eigen::Matrix3Xd> doubled = estimate;
  for (Eigen::Matrix3Xd& x : doubled) x *= 2.0;
  EXPECT_GT(ComputeE3D(truth, doubled), 0.5);
}

INSTANTIATE_TEST_SUITE_P(
    Akhter, RealDataE3D,
    ::testing::Values(PublishedE3D{"drink", 1102, 0.0250},
                      PublishedE3D{"pickup", 357, 0.2369},
                      PublishedE3D{"yoga", 307, 0.1625}),
    [](const ::testing::TestParamInfo<PublishedE3D>& info) {
      return std::string(info.param.sequence);
    });

}  // namespace
}  // namespace nrsfm
