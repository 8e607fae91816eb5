// Writes the seed corpora of the fuzz targets, with the project's own
// writers and the hand-made v5 files of tests/mat_v5_bytes.h (uncompressed
// v5, empty arrays of every shape, cells and structs with empty fields),
// into <out>/{mat,text,list,keypoints}/ (and empty <out>/work/<kind>/ for the
// inputs libFuzzer finds while it runs):
//   write_fuzz_seeds <out>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/io/mat_io.h"
#include "core/io/text_io.h"
#include "core/model/measurements.h"
#include "tests/mat_v5_bytes.h"

namespace {

using nrsfm::MatVariable;
using nrsfm::MatVersion;

bool Check(const nrsfm::Status& status) {
  if (!status.ok()) std::fprintf(stderr, "%s\n", status.message().c_str());
  return status.ok();
}

// W of F = 2 frames, P = 3 points; one missing point in frame 1.
Eigen::MatrixXd SmallW() {
  Eigen::MatrixXd w(4, 3);
  w << 1, 2, 3, 4, 5, 6, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5;
  return w;
}

Eigen::MatrixXd SmallWithMissing() {
  Eigen::MatrixXd w = SmallW();
  w(2, 1) = w(3, 1) = std::numeric_limits<double>::quiet_NaN();
  return w;
}

std::vector<double> Values(const Eigen::MatrixXd& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

bool WriteFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) std::fprintf(stderr, "%s: cannot write\n", path.c_str());
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_fuzz_seeds <out>\n");
    return 2;
  }
  namespace fs = std::filesystem;
  const fs::path out = argv[1];
  for (const char* kind : {"mat", "text", "list", "keypoints"}) {
    fs::create_directories(out / kind);
    fs::create_directories(out / "work" / kind);
  }
  const std::string mat = (out / "mat").string() + "/";
  Eigen::MatrixXd x(3, 2 * 3);  // X: 3 × P × F with P = 3, F = 2.
  x << 1, 2, 3, 4, 5, 6, 7, 8, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9;
  Eigen::MatrixXd p3(6, 3);  // P3_gt: 3F × P, block layout.
  p3 << 1, 2, 3, 4, 5, 6, 7, 8, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9;
  Eigen::MatrixXd rs(4, 3);  // Rs: 2F × 3.
  rs << 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1;
  Eigen::MatrixXd mask = Eigen::MatrixXd::Ones(2, 3);
  mask(1, 2) = 0;
  bool ok = true;
  ok &= Check(nrsfm::WriteMat(mat + "w_v4.mat", MatVersion::kV4,
                              {{"W", SmallW(), {}}}));
  ok &= Check(
      nrsfm::WriteMat(mat + "w_mask_v5.mat", MatVersion::kV5,
                      {{"W", SmallWithMissing(), {}}, {"mask", mask, {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "w_v73.mat", MatVersion::kV73,
                              {{"W", SmallW(), {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "p3_gt_v4.mat", MatVersion::kV4,
                              {{"P3_gt", p3, {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "x_v5.mat", MatVersion::kV5,
                              {{"X", x, {3, 3, 2}}}));
  ok &= Check(nrsfm::WriteMat(mat + "x_v73.mat", MatVersion::kV73,
                              {{"X", x, {3, 3, 2}}}));
  ok &= Check(
      nrsfm::WriteMat(mat + "s_rs_v5.mat", MatVersion::kV5,
                      {{"W", SmallW(), {}}, {"S", p3, {}}, {"Rs", rs, {}}}));
  // A W of M = 2 cameras that records its camera count, as nrsfm synth
  // writes it, with an FM x P mask.
  ok &= Check(
      nrsfm::WriteMat(mat + "w_cameras_mask_v5.mat", MatVersion::kV5,
                      {{"W", SmallWithMissing(), {}},
                       {"cameras", Eigen::MatrixXd::Constant(1, 1, 2), {}},
                       {"mask", mask, {}}}));
  // Empty arrays: a 3-D W with no slice (issue 18), X with no frame.
  ok &= Check(nrsfm::WriteMat(mat + "w_4x3x0_v5.mat", MatVersion::kV5,
                              {{"W", Eigen::MatrixXd(0, 0), {4, 3, 0}},
                               {"mask", Eigen::MatrixXd(0, 3), {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "x_3x3x0_v73.mat", MatVersion::kV73,
                              {{"X", Eigen::MatrixXd(0, 0), {3, 3, 0}}}));
  ok &= Check(nrsfm::WriteMat(mat + "w_0x3_v4.mat", MatVersion::kV4,
                              {{"W", Eigen::MatrixXd(0, 3), {}}}));
  // Uncompressed v5 (WriteMat compresses), byte by byte.
  namespace v5 = nrsfm::testing_util::v5;
  ok &= WriteFile(mat + "w_mask_raw_v5.mat",
                  v5::Header() + v5::Double("W", {4, 3}, Values(SmallW())) +
                      v5::Double("mask", {2, 3}, Values(mask)));
  ok &= WriteFile(mat + "x_s_rs_raw_v5.mat",
                  v5::Header() + v5::Double("X", {3, 3, 2}, Values(x)) +
                      v5::Double("S", {6, 3}, Values(p3)) +
                      v5::Double("Rs", {4, 3}, Values(rs)));
  ok &= WriteFile(mat + "empty_raw_v5.mat",
                  v5::Header() + v5::Double("W", {2, 3, 0}, {}) +
                      v5::Double("X", {3, 0, 2}, {}) +
                      v5::Double("P3_gt", {0, 3}, {}) +
                      v5::Double("mask", {0, 0}, {}));
  ok &= WriteFile(
      mat + "cell_struct_raw_v5.mat",
      v5::Header() +
          v5::Cell("c", {1, 2},
                   {v5::EmptyMatrix(), v5::Double("", {0, 0}, {})}) +
          v5::Struct(
              "st", {"empty", "w"},
              {v5::EmptyMatrix(), v5::Double("", {4, 3}, Values(SmallW()))}) +
          v5::Cell("W", {0, 0}, {}) + v5::Double("P3_gt", {6, 3}, Values(p3)));

  const fs::path text = out / "text";
  ok &= Check(
      nrsfm::WriteTextMatrix((text / "w.txt").string(), SmallWithMissing()));
  // A result directory: points_camera.csv, points_object.csv and
  // rotations.csv separated by form feeds (fuzz_input_file.h).
  {
    std::ofstream dir(text / "result_dir.csv");
    dir << "frame,camera,point,x,y,z\n0,0,0,1,2,3\n0,0,1,4,5,6\n"
        << "1,0,0,1,2,3\n1,0,1,4,5,6\n1,1,0,0,0,0\n\f"
        << "frame,point,x,y,z\n0,0,1,2,3\n0,1,4,5,6\n1,0,1,2,3\n1,1,4,5,6\n\f"
        << "frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33\n"
        << "0,0,1,0,0,0,1,0,0,0,1\n1,0,0,-1,0,1,0,0,0,0,1\n";
  }
  {
    // A reconstruction that left out point 1 and frame 1 (NaN there).
    std::ofstream dir(text / "result_dir_left_out.csv");
    dir << "frame,camera,point,x,y,z\n0,0,0,1,2,3\n0,0,1,nan,nan,nan\n"
        << "1,0,0,nan,nan,nan\n1,0,1,nan,nan,nan\n\f"
        << "frame,point,x,y,z\n0,0,1,2,3\n0,1,nan,nan,nan\n"
        << "1,0,nan,nan,nan\n1,1,nan,nan,nan\n\f"
        << "frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33\n"
        << "0,0,1,0,0,0,1,0,0,0,1\n1,0,nan,nan,nan,nan,nan,nan,nan,nan,nan\n";
  }
  {
    std::ofstream csv(text / "points_camera.csv");
    csv << "# a result's points\nframe,camera,point,x,y,z\n"
        << "0,0,0,1,2,3\n0,0,1,4,5,6\n1,0,0,1.5,2,3\n1,0,1,4,5e-1,-6\r\n";
    std::ofstream table(text / "table.csv");
    table << "frame,point,x\n0, 0, 1.5\n1 1 NaN\n";
  }

  nrsfm::Measurements measurements;
  ok &= Check(nrsfm::Measurements::FromMatrixWithNaN(SmallWithMissing(), 1,
                                                     "seed", &measurements));
  ok &= Check(nrsfm::WriteObservationList(
      (out / "list" / "two_frames.obs").string(), measurements));
  {
    std::ofstream list(out / "list" / "two_cameras.obs");
    list << "# frame camera point u v\n0 0 0 1 2\n0 1 0 3 4\n1 0 1 5.0 6\n"
         << "1 1 2 -7 8e2\n2.0 0 1 1 1\n";
  }
  {
    // COCO keypoint results (frames with a gap, two entries in one) and an
    // OpenPose folder of three frames, the files separated by form feeds.
    std::ofstream coco(out / "keypoints" / "coco.json");
    coco
        << R"([{"image_id": 3, "category_id": 1, "keypoints": [1, 2, 0.9, 3, 4, 0.1, )"
        << R"(5, 6, 1], "score": 0.8}, {"image_id": 1, "keypoints": [1.5, 2, 1, 3, 4, 1, )"
        << R"(0, 0, 0], "score": 1}, {"image_id": 3, "keypoints": [7, 8, 1, 9, 1e1, 1, )"
        << R"(-1, 2, 0.5]}])";
    std::ofstream named(out / "keypoints" / "coco_named.json");
    named << R"([{"image_id": "b10", "keypoints": [1, 2, 1, 3, 4, 1]}, )"
          << R"({"image_id": "b9", "keypoints": [5, 6, 0.5, 7, 8, 0.25]}])";
    std::ofstream openpose(out / "keypoints" / "openpose.json",
                           std::ios::binary);
    openpose
        << R"({"version": 1.3, "people": [{"person_id": [-1], "pose_keypoints_2d": )"
        << R"([1, 2, 0.9, 3, 4, 0.8], "face_keypoints_2d": [], )"
        << R"("hand_left_keypoints_2d": [], "hand_right_keypoints_2d": []}]})"
        << '\f' << R"({"version": 1.3, "people": []})" << '\f'
        << R"({"people": [{"pose_keypoints_2d": [5, 6, 1, 7, 8, 0]}, )"
        << R"({"pose_keypoints_2d": [1, 1, 1, 2, 2, 1]}]})";
  }
  return ok ? 0 : 1;
}
