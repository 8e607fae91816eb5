// reconstruct --uncertainty through the real binary: the two covariance
// files (headers, one row per frame, camera and point or view, symmetric
// positive semi-definite entries), the summary in result.json, evaluate's
// calibration keys against the truth, and one-line errors for bad values.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_util.h"
#include "tests/tools/tool_test.h"

namespace nrsfm {
namespace {

class UncertaintyCliTest : public ToolTest {
 protected:
  UncertaintyCliTest() : ToolTest("nrsfm_uncertainty_cli") {}
};

std::vector<std::vector<double>> ReadCsv(const std::string& path,
                                         std::string* header) {
  std::ifstream in(path);
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    rows.push_back(row);
  }
  return rows;
}

TEST_F(UncertaintyCliTest, WritesCovariancesAndEvaluateScoresThem) {
  // F 60, P 25, K 2, noise 0.01, 10 % missing.
  ASSERT_EQ(Run("synth --dataset random --frames 60 --points 25 --K 2 "
                "--noise 0.01 --missing 0.1 --seed 4 --output s.mat")
                .exit_code,
            0);
  const auto run =
      Run("reconstruct --input s.mat --K 2 --output out --uncertainty --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("uncertainty: point std median"), std::string::npos);
  std::string header;
  const auto points = ReadCsv(Path("out/points_covariance.csv"), &header);
  EXPECT_EQ(header, "frame,camera,point,xx,xy,xz,yy,yz,zz");
  ASSERT_EQ(points.size(), 60u * 25u);
  for (const auto& row : points) {
    ASSERT_EQ(row.size(), 9u);
    Eigen::Matrix3d c;
    c << row[3], row[4], row[5], row[4], row[6], row[7], row[5], row[7], row[8];
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c)
                  .eigenvalues()
                  .minCoeff(),
              0.0);
  }
  const auto rotations = ReadCsv(Path("out/rotations_covariance.csv"), &header);
  EXPECT_EQ(header, "frame,camera,xx,xy,xz,yy,yz,zz");
  EXPECT_EQ(rotations.size(), 60u);
  std::ifstream json_file(Path("out/result.json"));
  const nlohmann::json json = nlohmann::json::parse(json_file);
  const auto& d = json["diagnostics"];
  // The noise was 0.01 per coordinate: its estimate from the fit.
  EXPECT_NEAR(d["uncertainty_noise_std"].get<double>(), 0.01, 0.001);
  EXPECT_GT(d["uncertainty_max_point_std"].get<double>(),
            d["uncertainty_median_point_std"].get<double>());
  const auto evaluate = Run("evaluate --truth s.mat --result out");
  ASSERT_EQ(evaluate.exit_code, 0) << evaluate.err;
  const nlohmann::json line = nlohmann::json::parse(evaluate.out);
  // Calibrated on this kind of data (bench suite uncertainty: 0.93-0.95).
  EXPECT_GT(line["uncertainty_inside_95"].get<double>(), 0.9);
  EXPECT_LT(line["uncertainty_inside_95"].get<double>(), 0.99);
}

TEST_F(UncertaintyCliTest, BadNoiseStdIsOneLine) {
  ASSERT_EQ(Run("synth --dataset random --frames 20 --points 15 --K 1 "
                "--output s.mat")
                .exit_code,
            0);
  const auto run =
      Run("reconstruct --input s.mat --K 1 --output out --uncertainty "
          "--noise_std -1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("noise_std"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(std::filesystem::exists(Path("out")));
}

}  // namespace
}  // namespace nrsfm
