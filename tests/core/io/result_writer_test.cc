#include "core/io/result_writer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/result_reader.h"
#include "core/io/text_io.h"
#include "core/math/rotation.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;
using testing_util::MakeTempDir;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// F = 3 frames, M = 2 cameras, P = 4 points, K = 2 bases, random values.
void MakeSmallProblem(Model* model, Measurements* measurements) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal(0.0, 1.0);
  model->Resize(3, 2, 4, 2);
  for (int t = 0; t < 3; ++t) {
    for (int c = 0; c < 2; ++c) {
      model->SetRotation(t, c,
                         AngleAxisToRotation(Eigen::Vector3d(
                             normal(rng), normal(rng), normal(rng))));
      model->translations.col(model->View(t, c)) << normal(rng), normal(rng);
      if (c == 1) model->scales(model->View(t, c)) = 1.0 + 0.1 * normal(rng);
    }
    model->weights.col(t) << 1.0, normal(rng);
  }
  for (Eigen::Index i = 0; i < model->basis.size(); ++i)
    model->basis.data()[i] = normal(rng);
  measurements->num_frames = 3;
  measurements->num_cameras = 2;
  measurements->num_points = 4;
  measurements->W.resize(12, 4);
  measurements->visible.setConstant(6, 4, true);
  for (int t = 0; t < 3; ++t) {
    for (int c = 0; c < 2; ++c) {
      measurements->W.middleRows(measurements->Row(t, c), 2) =
          model->Project(t, c);
    }
  }
  measurements->visible(5, 3) = false;  // one missing entry
}

ReconstructionReport SmallReport() {
  ReconstructionReport report;
  report.input = "synthetic.mat";
  report.options = {{"num_bases", "2"}, {"loss", "huber"}};
  report.start_used = "factorization";
  report.start_reprojection_rms = 0.25;
  report.stages = {{"refine", 10.0, 0.5, 12, 0.125}};
  report.reprojection_rms = 1e-3;
  report.solution_usable = true;
  report.warnings = {"frame 2 has few points"};
  report.metrics = {{"e3d", 0.0303}};
  report.versions = {{"nrsfm", "0.1.0"}, {"ceres", "2.1.0"}};
  return report;
}

Eigen::MatrixXd Table(const std::string& path,
                      const std::vector<std::string>& header) {
  Eigen::MatrixXd table;
  const Status s = ReadCsvTable(path, header, &table);
  EXPECT_TRUE(s.ok()) << s.message();
  return table;
}

TEST(ResultWriter, WritesEveryFileWithExactValues) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  const std::string parent = MakeTempDir("result_writer_files");
  const std::string dir = parent + "/out";
  WriteOptions options;
  options.write_ply = true;
  ASSERT_TRUE(
      WriteReconstruction(dir, measurements, model, SmallReport(), options)
          .ok());

  const Eigen::MatrixXd points = Table(
      dir + "/points_camera.csv", {"frame", "camera", "point", "x", "y", "z"});
  ASSERT_EQ(points.rows(), 3 * 2 * 4);  // every frame, camera and point
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    const int t = static_cast<int>(points(r, 0)),
              c = static_cast<int>(points(r, 1)),
              p = static_cast<int>(points(r, 2));
    EXPECT_EQ(r, (t * 2 + c) * 4 + p);
    // The shortest form round-trips exactly.
    EXPECT_EQ(Eigen::Vector3d(points.block(r, 3, 1, 3).transpose()),
              model.ShapeInCamera(t, c).col(p));
  }
  const Eigen::MatrixXd object =
      Table(dir + "/points_object.csv", {"frame", "point", "x", "y", "z"});
  ASSERT_EQ(object.rows(), 3 * 4);
  EXPECT_EQ(Eigen::Vector3d(object.block(5, 2, 1, 3).transpose()),
            model.ShapeInObject(1).col(1));
  const Eigen::MatrixXd rotations =
      Table(dir + "/rotations.csv", {"frame", "camera", "r11", "r12", "r13",
                                     "r21", "r22", "r23", "r31", "r32", "r33"});
  ASSERT_EQ(rotations.rows(), 6);
  const Eigen::Matrix3d r21 = model.Rotation(2, 1);
  EXPECT_EQ(rotations(5, 0), 2);
  EXPECT_EQ(rotations(5, 1), 1);
  EXPECT_EQ(rotations(5, 3), r21(0, 1));
  EXPECT_EQ(rotations(5, 8), r21(2, 0));
  const Eigen::MatrixXd translations = Table(
      dir + "/translations.csv", {"frame", "camera", "tx", "ty", "scale"});
  ASSERT_EQ(translations.rows(), 6);
  EXPECT_EQ(translations(3, 2), model.translations(0, 3));
  EXPECT_EQ(translations(3, 4), model.scales(3));
  // Π X_tc + T_tc reproduces the measurements from the files alone (view 3
  // is frame 1, camera 1; X_tc already holds the scale s_tc).
  EXPECT_LT(std::abs(points(3 * 4 + 2, 3) + translations(3, 2) -
                     measurements.W(2 * 3, 2)),
            1e-12);
  const Eigen::MatrixXd weights =
      Table(dir + "/weights.csv", {"frame", "l1", "l2"});
  ASSERT_EQ(weights.rows(), 3);
  EXPECT_EQ(weights(2, 2), model.weights(1, 2));
  const Eigen::MatrixXd basis =
      Table(dir + "/basis.csv", {"k", "point", "x", "y", "z"});
  ASSERT_EQ(basis.rows(), 2 * 4);
  EXPECT_EQ(Eigen::Vector3d(basis.block(6, 2, 1, 3).transpose()),
            model.BasisShape(1).col(2));

  std::ifstream json_file(dir + "/result.json");
  const nlohmann::json json = nlohmann::json::parse(json_file, nullptr, false);
  ASSERT_FALSE(json.is_discarded());
  EXPECT_EQ(json["input"], "synthetic.mat");
  EXPECT_EQ(json["num_frames"], 3);
  EXPECT_EQ(json["num_cameras"], 2);
  EXPECT_EQ(json["num_points"], 4);
  EXPECT_EQ(json["num_bases"], 2);
  EXPECT_EQ(json["num_visible"], 23);
  EXPECT_EQ(json["options"]["loss"], "huber");
  EXPECT_EQ(json["start_used"], "factorization");
  EXPECT_EQ(json["start_reprojection_rms"], 0.25);
  ASSERT_EQ(json["stages"].size(), 1u);
  EXPECT_EQ(json["stages"][0]["name"], "refine");
  EXPECT_EQ(json["stages"][0]["iterations"], 12);
  EXPECT_EQ(json["stages"][0]["final_cost"], 0.5);
  EXPECT_EQ(json["reprojection_rms"], 1e-3);
  EXPECT_EQ(json["solution_usable"], true);
  EXPECT_EQ(json["warnings"][0], "frame 2 has few points");
  EXPECT_EQ(json["metrics"]["e3d"], 0.0303);
  EXPECT_EQ(json["versions"]["ceres"], "2.1.0");
  EXPECT_EQ(json["versions"]["nrsfm"], "0.1.0");
  EXPECT_TRUE(json["versions"].contains("matio"));
  EXPECT_TRUE(json["versions"].contains("eigen"));

  for (int t = 0; t < 3; ++t) {
    char name[64];
    std::snprintf(name, sizeof(name), "/ply/frame_%05d.ply", t);
    std::ifstream ply(dir + name);
    ASSERT_TRUE(ply.good()) << name;
    std::string line, text;
    int vertex_lines = -1;
    bool header_seen = false;
    while (std::getline(ply, line)) {
      if (header_seen) ++vertex_lines;
      if (line == "end_header") header_seen = true, vertex_lines = 0;
      text += line + "\n";
    }
    EXPECT_TRUE(Contains(text, "ply\nformat ascii 1.0\n"));
    EXPECT_TRUE(Contains(text, "element vertex 4\n"));
    EXPECT_EQ(vertex_lines, 4);
  }
  // Only the result directory is left in the parent (no temporary sibling).
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(parent))
    ++entries, (void)entry;
  EXPECT_EQ(entries, 1);
}

TEST(ResultWriter, TwoThreadsWriteTheSameBytes) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  const std::string parent = MakeTempDir("result_writer_threads");
  WriteOptions options;
  ASSERT_TRUE(WriteReconstruction(parent + "/one", measurements, model,
                                  SmallReport(), options)
                  .ok());
  options.num_threads = 2;
  ASSERT_TRUE(WriteReconstruction(parent + "/two", measurements, model,
                                  SmallReport(), options)
                  .ok());
  for (const char* name :
       {"/points_camera.csv", "/points_object.csv", "/rotations.csv",
        "/translations.csv", "/weights.csv", "/basis.csv", "/result.json"}) {
    const std::string one =
        testing_util::ReadFileToString(parent + "/one" + name);
    EXPECT_FALSE(one.empty()) << name;
    EXPECT_EQ(one, testing_util::ReadFileToString(parent + "/two" + name))
        << name;
  }
}

TEST(ResultWriter, PointsCameraCsvReadsBackAsGroundTruth) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  const std::string dir = MakeTempDir("result_reader") + "/out";
  ASSERT_TRUE(
      WriteReconstruction(dir, measurements, model, SmallReport(), {}).ok());
  for (int camera : {0, 1}) {
    GroundTruth truth;
    ASSERT_TRUE(ReadPointsCameraCsv(dir, camera, &truth).ok());
    EXPECT_EQ(truth.source, "points_camera.csv");
    ASSERT_EQ(truth.NumFrames(), 3);
    ASSERT_EQ(truth.NumPoints(), 4);
    for (int t = 0; t < 3; ++t) {
      EXPECT_EQ(truth.points_in_camera[t], model.ShapeInCamera(t, camera));
    }
  }
  GroundTruth truth;
  ASSERT_TRUE(ReadPointsCameraCsv(dir + "/points_camera.csv", 0, &truth).ok());
  Status s = ReadPointsCameraCsv(dir, 2, &truth);
  EXPECT_EQ(s.message(), dir + "/points_camera.csv: no rows for camera 2");

  const std::string bad = MakeTempDir("result_reader_bad");
  std::ofstream(bad + "/dup.csv")
      << "frame,camera,point,x,y,z\n0,0,0,1,2,3\n0,0,1,1,2,3\n"
         "0,0,1,4,5,6\n1,0,0,1,2,3\n";
  s = ReadPointsCameraCsv(bad + "/dup.csv", 0, &truth);
  EXPECT_EQ(s.message(),
            bad + "/dup.csv: frame 0, point 1, camera 0 appears twice");
  std::ofstream(bad + "/gap.csv")
      << "frame,camera,point,x,y,z\n0,0,0,1,2,3\n1,0,1,1,2,3\n";
  s = ReadPointsCameraCsv(bad + "/gap.csv", 0, &truth);
  EXPECT_TRUE(Contains(
      s.message(),
      "camera 0 has 2 rows, but its indices imply F = 2 frames x P = 2"))
      << s.message();
  std::ofstream(bad + "/neg.csv") << "frame,camera,point,x,y,z\n0,0,-1,1,2,3\n";
  s = ReadPointsCameraCsv(bad + "/neg.csv", 0, &truth);
  EXPECT_TRUE(Contains(
      s.message(), "data row 1, column 3: not a non-negative integer index"))
      << s.message();
  std::ofstream(bad + "/header.csv") << "frame,point,x,y,z\n0,0,1,2,3\n";
  s = ReadPointsCameraCsv(bad + "/header.csv", 0, &truth);
  EXPECT_TRUE(
      Contains(s.message(), "expected the header frame,camera,point,x,y,z"))
      << s.message();
  s = ReadPointsCameraCsv(bad, 0, &truth);  // a directory without the file
  EXPECT_EQ(s.message(), bad + "/points_camera.csv: no such file");
}

TEST(ResultWriter, ResultDirectoryReadsBackWithItsObjectFrame) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  const std::string dir = MakeTempDir("result_shapes") + "/out";
  ASSERT_TRUE(
      WriteReconstruction(dir, measurements, model, SmallReport(), {}).ok());
  for (int camera : {0, 1}) {
    GroundTruth shapes;
    ASSERT_TRUE(ReadResultShapes(dir, camera, &shapes).ok());
    EXPECT_EQ(shapes.source, "result");
    ASSERT_TRUE(shapes.HasObjectFrame());
    for (int t = 0; t < 3; ++t) {
      EXPECT_EQ(shapes.points_in_camera[t], model.ShapeInCamera(t, camera));
      EXPECT_EQ(shapes.points_in_object[t], model.ShapeInObject(t));
      EXPECT_LT((shapes.rotations[t] - model.Rotation(t, camera))
                    .cwiseAbs()
                    .maxCoeff(),
                1e-15);
    }
  }
  // Missing or damaged object-frame files are named.
  std::filesystem::remove(dir + "/rotations.csv");
  GroundTruth shapes;
  Status s = ReadResultShapes(dir, 0, &shapes);
  EXPECT_EQ(s.message(), dir + "/rotations.csv: no such file");
  std::ofstream(dir + "/rotations.csv")
      << "frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33\n"
         "0,0,2,0,0,0,1,0,0,0,1\n";
  s = ReadResultShapes(dir, 0, &shapes);
  EXPECT_EQ(s.message(),
            dir + "/rotations.csv: data row 1: not a rotation matrix");
  std::ofstream(dir + "/points_object.csv") << "frame,point,x,y,z\n0,0,1,2,3\n";
  s = ReadResultShapes(dir, 0, &shapes);
  EXPECT_TRUE(
      Contains(s.message(), dir + "/points_object.csv: has 1 rows; expected "
                                  "every frame and point of F = 3, P = 4 once"))
      << s.message();
}

// Empty files and header-only tables in a result directory (as truth or as
// the estimate of `nrsfm evaluate`): one error line naming the file.
TEST(ResultWriter, EmptyResultFilesGiveTheOneLineError) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  const std::string root = MakeTempDir("result_reader_empty");
  const std::string camera_header = "frame,camera,point,x,y,z\n";
  const std::string object_header = "frame,point,x,y,z\n";
  const std::string rotation_header =
      "frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33\n";
  struct Case {
    std::string name, file, contents, expected;
  };
  const std::vector<Case> cases = {
      {"camera_empty", "points_camera.csv", "",
       "points_camera.csv: empty file; expected the header "
       "frame,camera,point,x,y,z"},
      {"camera_comments", "points_camera.csv", "# nothing\n\n",
       "points_camera.csv: empty file; expected the header "
       "frame,camera,point,x,y,z"},
      {"camera_header_only", "points_camera.csv", camera_header,
       "points_camera.csv: no data rows after the header"},
      {"object_empty", "points_object.csv", "",
       "points_object.csv: empty file; expected the header "
       "frame,point,x,y,z"},
      {"object_header_only", "points_object.csv", object_header,
       "points_object.csv: no data rows after the header"},
      {"rotations_empty", "rotations.csv", "",
       "rotations.csv: empty file; expected the header "
       "frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33"},
      {"rotations_header_only", "rotations.csv", rotation_header,
       "rotations.csv: no data rows after the header"},
      {"rotations_other_camera", "rotations.csv",
       rotation_header + "0,5,1,0,0,0,1,0,0,0,1\n",
       "rotations.csv: no rotation of frame 0, camera 0"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string dir = root + "/" + c.name;
    ASSERT_TRUE(
        WriteReconstruction(dir, measurements, model, SmallReport(), {}).ok());
    std::ofstream(dir + "/" + c.file) << c.contents;
    GroundTruth shapes;
    EXPECT_EQ(ReadResultShapes(dir, 0, &shapes).message(),
              dir + "/" + c.expected);
    if (c.file == "points_camera.csv") {
      EXPECT_EQ(ReadPointsCameraCsv(dir, 0, &shapes).message(),
                dir + "/" + c.expected);
    }
  }
}

// A reconstruction that left out point 2 and frame 1 (NaN in the model, as
// solvers/pipeline/drop_unobserved.h makes it): written with "nan" there and
// the lists in result.json, read back with NaN in the same places. Other NaN in
// the model is still refused.
TEST(ResultWriter, LeftOutPointsAndFramesAreWrittenAsNaN) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  model.basis.col(2).setConstant(NAN);
  for (int c = 0; c < 2; ++c) {
    model.rotations.col(model.View(1, c)).setConstant(NAN);
    model.translations.col(model.View(1, c)).setConstant(NAN);
    model.scales(model.View(1, c)) = NAN;
  }
  model.weights.col(1).setConstant(NAN);
  const std::string dir = MakeTempDir("result_nan") + "/out";
  EXPECT_TRUE(
      Contains(WriteReconstruction(dir, measurements, model, SmallReport(), {})
                   .message(),
               "model: rotations has a NaN or infinite value"));
  ReconstructionReport report = SmallReport();
  report.dropped_points = {2};
  report.dropped_frames = {1};
  ASSERT_TRUE(WriteReconstruction(dir, measurements, model, report, {}).ok());
  const std::string json = testing_util::ReadFileToString(dir + "/result.json");
  EXPECT_TRUE(Contains(json, "\"dropped_points\": [\n    2\n  ]")) << json;
  EXPECT_TRUE(Contains(json, "\"dropped_frames\": [\n    1\n  ]")) << json;
  GroundTruth shapes;
  const Status s = ReadResultShapes(dir, 1, &shapes);
  ASSERT_TRUE(s.ok()) << s.message();
  for (int t = 0; t < 3; ++t) {
    for (int p = 0; p < 4; ++p) {
      const bool left_out = t == 1 || p == 2;
      EXPECT_EQ(shapes.points_in_camera[t].col(p).array().isNaN().all(),
                left_out);
      EXPECT_EQ(shapes.points_in_object[t].col(p).array().isNaN().all(),
                left_out);
      if (!left_out) {
        EXPECT_EQ(shapes.points_in_camera[t].col(p),
                  model.ShapeInCamera(t, 1).col(p));
      }
    }
    EXPECT_EQ(shapes.rotations[t].array().isNaN().all(), t == 1);
  }
  // Infinity stays an error.
  model.basis(0, 0) = INFINITY;
  EXPECT_TRUE(Contains(
      WriteReconstruction(dir, measurements, model, report, {}).message(),
      "model: basis has an infinite value"));
}

TEST(ResultWriter, ExistingDirectoriesAreReplacedOnlyWhenSafe) {
  Model model;
  Measurements measurements;
  MakeSmallProblem(&model, &measurements);
  const ReconstructionReport report = SmallReport();
  const std::string parent = MakeTempDir("result_writer_overwrite");
  const std::string dir = parent + "/out";

  // An existing empty directory is fine.
  fs::create_directory(dir);
  ASSERT_TRUE(WriteReconstruction(dir, measurements, model, report, {}).ok());
  // A second write replaces the first result (and drops its extra files).
  std::ofstream(dir + "/stale.txt") << "old";
  WriteOptions options;
  options.overwrite = true;
  ASSERT_TRUE(
      WriteReconstruction(dir + "/", measurements, model, report, options)
          .ok());
  EXPECT_TRUE(fs::exists(dir + "/result.json"));
  EXPECT_FALSE(fs::exists(dir + "/stale.txt"));
  // Without overwrite a non-empty directory is an error and stays untouched.
  options.overwrite = false;
  Status s = WriteReconstruction(dir, measurements, model, report, options);
  EXPECT_TRUE(Contains(s.message(),
                       dir + ": the output directory exists and is not empty"))
      << s.message();
  // A non-empty directory that is not a result is never replaced.
  const std::string other = parent + "/other";
  fs::create_directory(other);
  std::ofstream(other + "/thesis.tex") << "precious";
  options.overwrite = true;
  s = WriteReconstruction(other, measurements, model, report, options);
  EXPECT_TRUE(Contains(
      s.message(), other + ": the output directory is not empty and holds no "
                           "result.json"))
      << s.message();
  EXPECT_TRUE(fs::exists(other + "/thesis.tex"));
  // Unwritable places: below a regular file, or a regular file itself.
  const std::string file = parent + "/file.txt";
  std::ofstream(file) << "x";
  s = WriteReconstruction(file + "/out", measurements, model, report, options);
  EXPECT_TRUE(Contains(s.message(), file + ": cannot create the directory"))
      << s.message();
  s = WriteReconstruction(file, measurements, model, report, options);
  EXPECT_EQ(s.message(), file + ": exists and is not a directory");
  // Model and measurements that disagree.
  Measurements other_size = measurements;
  other_size.num_points = 5;
  s = WriteReconstruction(parent + "/mismatch", other_size, model, report,
                          options);
  EXPECT_TRUE(Contains(s.message(), "do not match the model")) << s.message();
  Model invalid = model;
  invalid.weights(0, 0) = std::nan("");
  s = WriteReconstruction(parent + "/invalid", measurements, invalid, report,
                          options);
  EXPECT_FALSE(s.ok());
  // Nothing but the three directories and the file are left in the parent.
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(parent)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"file.txt", "other", "out"}));
}

}  // namespace
}  // namespace nrsfm
