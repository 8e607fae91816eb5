// Writes the seed corpora of the fuzz targets, with the project's own
// writers, into <out>/{mat,text,list}/ (and empty <out>/work/{mat,text,list}/
// for the inputs libFuzzer finds while it runs):
//   write_fuzz_seeds <out>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/mat_io.h"
#include "core/measurements.h"
#include "core/text_io.h"

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

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_fuzz_seeds <out>\n");
    return 2;
  }
  namespace fs = std::filesystem;
  const fs::path out = argv[1];
  for (const char* kind : {"mat", "text", "list"}) {
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
  ok &= Check(nrsfm::WriteMat(mat + "w_mask_v5.mat", MatVersion::kV5,
                              {{"W", SmallWithMissing(), {}},
                               {"mask", mask, {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "w_v73.mat", MatVersion::kV73,
                              {{"W", SmallW(), {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "p3_gt_v4.mat", MatVersion::kV4,
                              {{"P3_gt", p3, {}}}));
  ok &= Check(nrsfm::WriteMat(mat + "x_v5.mat", MatVersion::kV5,
                              {{"X", x, {3, 3, 2}}}));
  ok &= Check(nrsfm::WriteMat(mat + "x_v73.mat", MatVersion::kV73,
                              {{"X", x, {3, 3, 2}}}));
  ok &= Check(nrsfm::WriteMat(mat + "s_rs_v5.mat", MatVersion::kV5,
                              {{"W", SmallW(), {}}, {"S", p3, {}},
                               {"Rs", rs, {}}}));

  const fs::path text = out / "text";
  ok &= Check(nrsfm::WriteTextMatrix((text / "w.txt").string(),
                                     SmallWithMissing()));
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
  return ok ? 0 : 1;
}
