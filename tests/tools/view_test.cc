// `nrsfm view` driven through the real binary on small synthetic
// reconstructions: the page is self-contained and carries the data the
// library computes (the estimate, the truth after the e3D alignment, the
// per-frame errors, tracks, reprojections, edges), and bad input gives one
// error line naming the path and no page. The page in a real browser:
// tests/tools/view_browser_test.cc.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/ground_truth.h"
#include "core/io/mat_io.h"
#include "core/io/read_measurements.h"
#include "core/io/result_reader.h"
#include "problems/delaunay_edges.h"
#include "tests/test_util.h"
#include "tests/tools/tool_test.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

using RunResult = testing_util::CommandResult;

constexpr char kDataOpen[] =
    "<script id=\"nrsfm-data\" type=\"application/json\">";

// The data object of a page (null when the page has none).
nlohmann::json PageData(const std::string& html) {
  const size_t begin = html.find(kDataOpen);
  if (begin == std::string::npos) return nullptr;
  const size_t start = begin + std::string(kDataOpen).size();
  const size_t end = html.find("</script>", start);
  if (end == std::string::npos) return nullptr;
  return nlohmann::json::parse(html.substr(start, end - start));
}

std::string Lowercase(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Nothing in the page can make the browser fetch anything: its only script
// elements are inline (no src), the markup outside them names no resource,
// a Content-Security-Policy forbids any load, and nothing nrsfm writes (the
// markup, the data, the page script) holds a URL. The inlined three.js and
// OrbitControls hold a few as text (authors' credits in comments, an XML
// namespace, a paper cited in a shader) that are never fetched;
// tests/tools/view_browser_test.cc checks in Chromium that the page loads
// nothing.
void ExpectSelfContained(const std::string& html) {
  std::string markup, ours;
  size_t pos = 0;
  int scripts = 0;
  for (;;) {
    const size_t open = html.find("<script", pos);
    if (open == std::string::npos) break;
    markup += html.substr(pos, open - pos);
    const size_t tag_end = html.find('>', open);
    ASSERT_NE(tag_end, std::string::npos);
    const std::string tag = html.substr(open, tag_end + 1 - open);
    EXPECT_TRUE(tag == "<script>" || tag == kDataOpen) << "script tag " << tag;
    const size_t close = html.find("</script>", tag_end);
    ASSERT_NE(close, std::string::npos) << "unterminated " << tag;
    // Scripts 0 and 1 are three.js and OrbitControls; then the data and the
    // page script.
    if (scripts >= 2) ours += html.substr(tag_end + 1, close - tag_end - 1);
    pos = close + 9;
    ++scripts;
  }
  markup += html.substr(pos);
  EXPECT_EQ(scripts, 4);
  ours += markup;
  EXPECT_EQ(ours.find("http:"), std::string::npos);
  EXPECT_EQ(ours.find("https:"), std::string::npos);
  EXPECT_EQ(ours.find("//www."), std::string::npos);
  const std::string lower = Lowercase(markup);
  for (const char* needle :
       {"src=", "href=", "url(", "@import", "<link", "<img", "<iframe",
        "<object", "<embed", "http:", "https:"}) {
    EXPECT_EQ(lower.find(needle), std::string::npos)
        << needle << " in the page's markup";
  }
  EXPECT_NE(
      markup.find("content=\"default-src 'none'; script-src 'unsafe-inline'; "
                  "style-src 'unsafe-inline'; img-src data:\""),
      std::string::npos)
      << "no Content-Security-Policy";
}

std::vector<Eigen::Matrix3Xd> Centred(
    const std::vector<Eigen::Matrix3Xd>& shapes) {
  std::vector<Eigen::Matrix3Xd> out;
  for (const Eigen::Matrix3Xd& x : shapes)
    out.push_back(x.colwise() - x.rowwise().mean());
  return out;
}

// F frames of 3 × P from a flat page array (x y z per point, frame-major).
std::vector<Eigen::Matrix3Xd> Shapes(const nlohmann::json& array, int frames,
                                     int points) {
  std::vector<Eigen::Matrix3Xd> shapes(frames, Eigen::Matrix3Xd(3, points));
  EXPECT_EQ(array.size(), static_cast<size_t>(3 * frames * points));
  if (array.size() != static_cast<size_t>(3 * frames * points)) return shapes;
  for (int t = 0; t < frames; ++t) {
    for (int p = 0; p < points; ++p) {
      for (int i = 0; i < 3; ++i)
        shapes[t](i, p) = array[3 * (t * points + p) + i].get<double>();
    }
  }
  return shapes;
}

// A (2FM) × P matrix from a flat page array (u v per point, frame-major,
// then camera), NaN for null.
Eigen::MatrixXd Tracks(const nlohmann::json& array, int views, int points) {
  Eigen::MatrixXd w(2 * views, points);
  EXPECT_EQ(array.size(), static_cast<size_t>(2 * views * points));
  if (array.size() != static_cast<size_t>(2 * views * points)) return w;
  for (int v = 0; v < views; ++v) {
    for (int p = 0; p < points; ++p) {
      for (int i = 0; i < 2; ++i) {
        const nlohmann::json& x = array[2 * (v * points + p) + i];
        w(2 * v + i, p) = x.is_null() ? NAN : x.get<double>();
      }
    }
  }
  return w;
}

double Mean(const nlohmann::json& array) {
  double sum = 0.0;
  for (const auto& x : array) sum += x.get<double>();
  return sum / static_cast<double>(array.size());
}

class ViewTest : public ToolTest {
 protected:
  ViewTest() : ToolTest("nrsfm_view") {}

  // A noisy random-basis sequence with missing entries (r.mat) and its
  // K = 2 reconstruction (r/).
  void MakeReconstruction() {
    RunResult r =
        Run("synth --dataset random --K 2 --frames 40 --points 25 --seed 3 "
            "--noise 0.02 --missing 0.1 --output r.mat");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = Run("reconstruct --input r.mat --K 2 --output r --truth r.mat --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  }

  // `nrsfm view <args>` fails with exit code 1, one line on stderr that
  // starts with "nrsfm view: error:" and holds `needle`, and writes no page.
  void ExpectRejected(const std::string& args, const std::string& needle,
                      const std::string& page = "v.html") {
    const bool existed = fs::exists(Path(page));
    const RunResult r = Run("view " + args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nrsfm view: error: ", 0), 0u) << args << "\n"
                                                         << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n"
                                                               << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    if (!existed) {
      EXPECT_FALSE(fs::exists(Path(page))) << args;
    }
    for (const auto& entry : fs::directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"),
                std::string::npos)
          << "left behind: " << entry.path();
    }
  }
};

TEST_F(ViewTest, PageIsSelfContainedAndHoldsTheReconstruction) {
  MakeReconstruction();
  const RunResult r =
      Run("view --result r --truth r.mat --input r.mat --output page.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote page.html"), std::string::npos) << r.out;
  const std::string html = testing_util::ReadFileToString(Path("page.html"));
  ExpectSelfContained(html);
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos)
      << "three.js r111 not inlined";
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);

  const nlohmann::json data = PageData(html);
  ASSERT_TRUE(data.is_object());
  const nlohmann::json& meta = data["meta"];
  const int f = 40, p = 25;
  EXPECT_EQ(meta["num_frames"], f);
  EXPECT_EQ(meta["num_cameras"], 1);
  EXPECT_EQ(meta["num_points"], p);
  EXPECT_EQ(meta["num_bases"], 2);
  EXPECT_TRUE(meta["has_truth"].get<bool>());
  EXPECT_TRUE(meta["has_tracks"].get<bool>());
  EXPECT_TRUE(meta["solution_usable"].get<bool>());

  // The metrics are those of `nrsfm evaluate`, and the per-frame errors are
  // the terms of its e3D.
  const RunResult e = Run("evaluate --truth r.mat --result r");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const nlohmann::json evaluated = nlohmann::json::parse(e.out);
  const double e3d = evaluated["e3d"].get<double>();
  EXPECT_GT(e3d, 0.01) << "the noisy reconstruction should not be exact";
  EXPECT_NEAR(meta["metrics"]["e3d"].get<double>(), e3d, 1e-12 * e3d);
  EXPECT_NEAR(meta["metrics"]["frob_zsign"].get<double>(),
              evaluated["frob_zsign"].get<double>(), 1e-12);
  ASSERT_EQ(data["frame_error"].size(), static_cast<size_t>(f));
  EXPECT_NEAR(Mean(data["frame_error"]), e3d, 1e-8 * e3d);

  // The estimate is camera 0's points_camera.csv, centred per frame.
  GroundTruth points;
  ASSERT_TRUE(ReadPointsCameraCsv(Path("r"), 0, &points).ok());
  const std::vector<Eigen::Matrix3Xd> expected =
      Centred(points.points_in_camera);
  const std::vector<Eigen::Matrix3Xd> estimate = Shapes(data["estimate"], f, p);
  const double size = expected[0].norm() / std::sqrt(p);
  for (int t = 0; t < f; ++t) {
    EXPECT_LT((estimate[t] - expected[t]).cwiseAbs().maxCoeff(), 1e-6 * size)
        << "frame " << t;
  }

  // The truth is shown in the estimate's frame after the e3D alignment: the
  // distances between the two, over e3D's scale s (from the truth file),
  // average to e3D, frame by frame.
  GroundTruth truth;
  ASSERT_TRUE(ReadGroundTruth(Path("r.mat"), "", &truth).ok());
  const std::vector<Eigen::Matrix3Xd> truth_centred =
      Centred(truth.points_in_camera);
  double s = 0.0;
  for (const Eigen::Matrix3Xd& x : truth_centred) {
    s += (x.rowwise().squaredNorm() / p).cwiseSqrt().sum();
  }
  s /= 3.0 * f;
  const std::vector<Eigen::Matrix3Xd> shown_truth = Shapes(data["truth"], f, p);
  double sum = 0.0;
  for (int t = 0; t < f; ++t) {
    const double frame_error =
        (shown_truth[t] - estimate[t]).colwise().norm().mean() / s;
    EXPECT_NEAR(frame_error, data["frame_error"][t].get<double>(),
                1e-4 * frame_error)
        << "frame " << t;
    sum += frame_error;
    // An orthogonal map of the centred truth: the same shape.
    EXPECT_NEAR(shown_truth[t].norm(), truth_centred[t].norm(),
                1e-6 * truth_centred[t].norm());
  }
  EXPECT_NEAR(sum / f, e3d, 1e-4 * e3d);

  // Tracks are the input's W (NaN where missing), and the RMS between them
  // and the reprojections is the reconstruction's reprojection RMS.
  Measurements input;
  ASSERT_TRUE(ReadMeasurements(Path("r.mat"), InputOptions(), &input).ok());
  const Eigen::MatrixXd tracks = Tracks(data["tracks"], f, p);
  const Eigen::MatrixXd reprojection = Tracks(data["reprojection"], f, p);
  ASSERT_TRUE(reprojection.allFinite());
  double squared = 0.0;
  for (int t = 0; t < f; ++t) {
    for (int q = 0; q < p; ++q) {
      if (!input.visible(t, q)) {
        EXPECT_TRUE(std::isnan(tracks(2 * t, q))) << t << ", " << q;
        continue;
      }
      EXPECT_NEAR(tracks(2 * t, q), input.W(2 * t, q), 1e-6 * size);
      EXPECT_NEAR(tracks(2 * t + 1, q), input.W(2 * t + 1, q), 1e-6 * size);
      squared +=
          (tracks.block<2, 1>(2 * t, q) - reprojection.block<2, 1>(2 * t, q))
              .squaredNorm();
    }
  }
  const nlohmann::json result = nlohmann::json::parse(
      testing_util::ReadFileToString(Path("r/result.json")));
  const double rms = result["reprojection_rms"].get<double>();
  EXPECT_GT(rms, 0.005);
  EXPECT_NEAR(std::sqrt(squared / input.NumVisible()), rms, 1e-3 * rms);
  EXPECT_NEAR(meta["reprojection_rms"].get<double>(), rms, 1e-9 * rms);

  // No skeleton in the file: the Delaunay edges the smoothness term uses.
  std::vector<NeighbourEdge> edges;
  ASSERT_TRUE(ComputeDelaunayEdges(input, DelaunayEdgesOptions(), &edges).ok());
  ASSERT_EQ(data["edges"].size(), edges.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    EXPECT_EQ(data["edges"][i][0].get<int>(), edges[i].i);
    EXPECT_EQ(data["edges"][i][1].get<int>(), edges[i].j);
  }
  EXPECT_NE(meta["edge_source"].get<std::string>().find("Delaunay"),
            std::string::npos);
}

TEST_F(ViewTest, WithoutTruthOrTracksThePageSaysSo) {
  MakeReconstruction();
  const RunResult r = Run("view --result r --output bare.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json data =
      PageData(testing_util::ReadFileToString(Path("bare.html")));
  ASSERT_TRUE(data.is_object());
  EXPECT_TRUE(data["truth"].is_null());
  EXPECT_TRUE(data["tracks"].is_null());
  EXPECT_TRUE(data["frame_error"].is_null());
  EXPECT_EQ(data["estimate"].size(), 3u * 40 * 25);
  EXPECT_EQ(data["reprojection"].size(), 2u * 40 * 25);
  const std::string notes = data["meta"]["notes"].dump();
  EXPECT_NE(notes.find("2D tracks were not given (--input)"), std::string::npos)
      << notes;
  EXPECT_NE(notes.find("no ground truth given (--truth)"), std::string::npos)
      << notes;
  EXPECT_NE(r.out.find("note: the 2D tracks were not given"), std::string::npos)
      << r.out;
  // Edges from the reprojected points.
  EXPECT_GT(data["edges"].size(), 25u);
  EXPECT_NE(
      data["meta"]["edge_source"].get<std::string>().find("reprojected points"),
      std::string::npos);
}

// --frames_dir: the frames' files, byte for byte, as data: URLs of the
// page (the browser decodes them under the 2D view); a folder that does not
// fit the result is one error line.
TEST_F(ViewTest, FramesOfAFolderGoUnderThe2DView) {
  MakeReconstruction();
  fs::create_directories(Path("frames"));
  // 40 tiny "PNG" files: the page does not decode them, so any bytes do;
  // bytes 0..255 and the lengths 1, 2, 3 mod 3 exercise the base64 padding.
  std::string bytes;
  for (int i = 0; i < 256; ++i) bytes += static_cast<char>(i);
  for (int t = 0; t < 40; ++t) {
    std::ofstream(Path("frames/" + std::to_string(t) + ".png"),
                  std::ios::binary)
        << bytes.substr(0, 250 + t % 3);
  }
  const RunResult r =
      Run("view --result r --frames_dir frames --output frames.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = testing_util::ReadFileToString(Path("frames.html"));
  ExpectSelfContained(html);
  const nlohmann::json data = PageData(html);
  ASSERT_TRUE(data["frames"].is_array());
  ASSERT_EQ(data["frames"].size(), 40u);
  // Hand-computed: base64 of bytes 0, 1, 2 is "AAEC"; 250 bytes end in
  // "+Q==" (byte 249 = 0xf9), 251 in "+fo=" (249, 250), 252 in "+fr7"
  // (249-251); each is 336 characters.
  const std::string first = data["frames"][0];
  EXPECT_EQ(first.rfind("data:image/png;base64,AAEC", 0), 0u)
      << first.substr(0, 40);
  EXPECT_EQ(first.substr(first.size() - 4), "+Q==");
  const std::string second = data["frames"][1];
  EXPECT_EQ(second.substr(second.size() - 4), "+fo=");
  const std::string third = data["frames"][2];
  EXPECT_EQ(third.substr(third.size() - 4), "+fr7");
  EXPECT_EQ(first.size(),
            std::string("data:image/png;base64,").size() + 4 * 84);

  fs::remove(Path("frames/39.png"));
  const RunResult fewer =
      Run("view --result r --frames_dir frames --output fewer.html");
  EXPECT_EQ(fewer.exit_code, 1);
  EXPECT_NE(fewer.err.find("--frames_dir 'frames' holds 39 frames but the "
                           "result has F = 40"),
            std::string::npos)
      << fewer.err;
  std::ofstream(Path("frames/39.pgm")) << "P5";
  const RunResult pgm =
      Run("view --result r --frames_dir frames --output pgm.html");
  EXPECT_EQ(pgm.exit_code, 1);
  EXPECT_NE(pgm.err.find("39.pgm: a page shows PNG, JPEG, BMP or WebP frames"),
            std::string::npos)
      << pgm.err;
  EXPECT_FALSE(fs::exists(Path("fewer.html")));
  EXPECT_FALSE(fs::exists(Path("pgm.html")));
}

TEST_F(ViewTest, SkeletonListOfTheTruthIsDrawn) {
  MakeReconstruction();
  // The truth file with a motion-capture style skeleton: n × 2, 1-based.
  Eigen::MatrixXd w, p3_gt;
  ASSERT_TRUE(ReadMatVariable(Path("r.mat"), "W", &w).ok());
  ASSERT_TRUE(ReadMatVariable(Path("r.mat"), "P3_gt", &p3_gt).ok());
  Eigen::MatrixXd list(4, 2);
  list << 2, 1, 1, 3, 25, 24, 3, 1;  // (1, 3) twice: drawn once
  ASSERT_TRUE(WriteMat(Path("skeleton.mat"), MatVersion::kV5,
                       {{"W", w, {}}, {"P3_gt", p3_gt, {}}, {"list", list, {}}})
                  .ok());
  const RunResult r =
      Run("view --result r --truth skeleton.mat --output s.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json data =
      PageData(testing_util::ReadFileToString(Path("s.html")));
  ASSERT_TRUE(data.is_object());
  EXPECT_EQ(data["edges"], nlohmann::json::parse("[[0,1],[0,2],[23,24]]"));
  EXPECT_NE(
      data["meta"]["edge_source"].get<std::string>().find("skeleton 'list' of"),
      std::string::npos);

  // A list that does not index the points is an error naming it.
  list(2, 0) = 26;
  ASSERT_TRUE(WriteMat(Path("bad_list.mat"), MatVersion::kV5,
                       {{"W", w, {}}, {"P3_gt", p3_gt, {}}, {"list", list, {}}})
                  .ok());
  ExpectRejected("--result r --truth bad_list.mat --output v.html",
                 "bad_list.mat: variable 'list' (skeleton edges, 1-based point "
                 "indices): row 3 "
                 "holds 26; expected an integer in 1..25");
}

TEST_F(ViewTest, TwoCamerasHaveTheirOwnReprojections) {
  RunResult r = Run(
      "synth --dataset shoe --frames 30 --cameras 2 --points 60 --noise 0.002 "
      "--output s.mat");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = Run("reconstruct --input s.mat --cameras 2 --K 2 --output s --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  r = Run("view --result s --input s.mat --output two.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json data =
      PageData(testing_util::ReadFileToString(Path("two.html")));
  ASSERT_TRUE(data.is_object());
  EXPECT_EQ(data["meta"]["num_cameras"], 2);
  InputOptions options;
  options.num_cameras = 2;
  Measurements input;
  ASSERT_TRUE(ReadMeasurements(Path("s.mat"), options, &input).ok());
  const Eigen::MatrixXd reprojection =
      Tracks(data["reprojection"], 60, input.num_points);
  double squared = 0.0;
  for (int view = 0; view < input.NumViews(); ++view) {
    for (int q = 0; q < input.num_points; ++q) {
      if (!input.visible(view, q)) continue;
      squared += (input.W.block<2, 1>(2 * view, q) -
                  reprojection.block<2, 1>(2 * view, q))
                     .squaredNorm();
    }
  }
  const nlohmann::json result = nlohmann::json::parse(
      testing_util::ReadFileToString(Path("s/result.json")));
  const double rms = result["reprojection_rms"].get<double>();
  EXPECT_NEAR(std::sqrt(squared / input.NumVisible()), rms, 1e-3 * rms);
  EXPECT_NEAR(data["meta"]["reprojection_rms"].get<double>(), rms, 1e-9 * rms);
}

// A result with --uncertainty: each point's std on the page is
// sqrt(trace) of its covariance in points_covariance.csv; a result
// without one has none; a covariance file that is cut short, or holds a
// negative variance, is one error line naming the file.
TEST_F(ViewTest, PredictedStdOfEachPointComesFromItsCovariance) {
  MakeReconstruction();
  ASSERT_EQ(Run("reconstruct --input r.mat --K 2 --output ru --uncertainty "
                "--quiet")
                .exit_code,
            0);
  ASSERT_EQ(Run("view --result ru --output u.html").exit_code, 0);
  const nlohmann::json data =
      PageData(testing_util::ReadFileToString(Path("u.html")));
  ASSERT_TRUE(data.is_object());
  EXPECT_TRUE(data["meta"]["has_uncertainty"].get<bool>());
  const int f = 40, p = 25;
  std::vector<Eigen::Matrix3d> covariances;
  ASSERT_TRUE(ReadPointsCovarianceCsv(Path("ru"), 0, f, p, &covariances).ok());
  ASSERT_EQ(data["point_std"].size(), static_cast<size_t>(f * p));
  double smallest = 1e300, largest = 0.0;
  for (int i = 0; i < f * p; ++i) {
    const double expected = std::sqrt(covariances[i].trace());
    EXPECT_NEAR(data["point_std"][i].get<double>(), expected, 1e-5 * expected)
        << "entry " << i;
    smallest = std::min(smallest, expected);
    largest = std::max(largest, expected);
  }
  // Noise 0.02 on tracks of about unit size: stds of that order, and not
  // all alike (the colour scale has something to show).
  EXPECT_GT(smallest, 1e-3);
  EXPECT_LT(largest, 0.2);
  EXPECT_GT(largest, 1.5 * smallest);
  ASSERT_EQ(Run("view --result r --output plain.html").exit_code, 0);
  const nlohmann::json plain =
      PageData(testing_util::ReadFileToString(Path("plain.html")));
  EXPECT_FALSE(plain["meta"]["has_uncertainty"].get<bool>());
  EXPECT_TRUE(plain["point_std"].is_null());

  // Cut short: the reader names the missing (frame, point).
  std::string csv =
      testing_util::ReadFileToString(Path("ru/points_covariance.csv"));
  std::ofstream(Path("ru/points_covariance.csv"))
      << csv.substr(0, csv.rfind('\n', csv.size() - 2) + 1);
  ExpectRejected("--result ru --output v.html", "ru/points_covariance.csv");
  // A negative variance (xx of the first row).
  const size_t header = csv.find('\n') + 1;
  const size_t xx = csv.find(',', csv.find(',', csv.find(',', header) + 1) + 1);
  std::ofstream(Path("ru/points_covariance.csv"))
      << csv.substr(0, xx + 1) << "-1" << csv.substr(csv.find(',', xx + 1));
  ExpectRejected("--result ru --output v.html",
                 "ru/points_covariance.csv: frame 0, point 0: the variances");
}

// A perspective result: the 2D view reprojects points_camera.csv (which
// holds the translation) through result.json's intrinsics, reproducing the
// result's reprojection RMS, and the truth is aligned with one scale as
// e3d_scaled (the number for an answer fixed up to scale).
TEST_F(ViewTest, PerspectiveResultIsReprojectedThroughItsIntrinsics) {
  MakeReconstruction();
  ASSERT_EQ(Run("synth --dataset reproject --input r.mat --distance_ratio 3 "
                "--noise_fraction 0.002 --output p.mat")
                .exit_code,
            0);
  RunResult r = Run(
      "reconstruct --input p.mat --K 2 --camera perspective --priors manual "
      "--output p --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  r = Run("view --result p --truth p.mat --input p.mat --output p.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("with one scale"), std::string::npos) << r.out;
  const nlohmann::json data =
      PageData(testing_util::ReadFileToString(Path("p.html")));
  ASSERT_TRUE(data.is_object());
  const nlohmann::json& meta = data["meta"];
  EXPECT_EQ(meta["camera_model"], "perspective");
  const nlohmann::json result = nlohmann::json::parse(
      testing_util::ReadFileToString(Path("p/result.json")));
  const double rms = result["reprojection_rms"].get<double>();
  EXPECT_GT(rms, 0.3);  // pixels: noise 0.2 % of a 451-pixel image
  EXPECT_NEAR(meta["reprojection_rms"].get<double>(), rms, 1e-6 * rms);
  const RunResult e = Run("evaluate --truth p.mat --result p");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const double scaled =
      nlohmann::json::parse(e.out)["e3d_scaled"].get<double>();
  ASSERT_EQ(data["frame_error"].size(), 40u);
  EXPECT_NEAR(Mean(data["frame_error"]), scaled, 1e-8 * scaled);
  EXPECT_NEAR(meta["metrics"]["e3d_scaled"].get<double>(), scaled,
              1e-12 * scaled);
  // A perspective result without its intrinsics is one error line.
  nlohmann::json cut = result;
  cut.erase("intrinsics");
  std::ofstream(Path("p/result.json")) << cut.dump();
  ExpectRejected("--result p --output v.html",
                 "p/result.json: a perspective result needs \"intrinsics\"");
}

TEST_F(ViewTest, HelpDescribesTheCommand) {
  const RunResult r = Run("--help");
  EXPECT_EQ(r.exit_code, 0);
  const std::string text = r.out + r.err;
  EXPECT_NE(text.find("nrsfm view --result DIR [--truth PATH] [--input PATH] "
                      "--output FILE.html"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("view writes one self-contained HTML page"),
            std::string::npos)
      << text;
}

TEST_F(ViewTest, BadInputGetsOneLineNamingThePathAndNoPage) {
  MakeReconstruction();
  ExpectRejected("--output v.html", "--result DIR is required");
  ExpectRejected("--result r", "--output FILE.html is required");
  ExpectRejected("--result nope --output v.html",
                 "--result 'nope': no such directory");
  ExpectRejected("--result r.mat --output v.html",
                 "--result 'r.mat' is not a directory");
  // A directory without a result.
  fs::create_directory(Path("empty"));
  ExpectRejected("--result empty --output v.html", "empty/points_camera.csv");
  // points_camera.csv but no translations.csv.
  fs::create_directory(Path("half"));
  fs::copy_file(Path("r/points_camera.csv"), Path("half/points_camera.csv"));
  ExpectRejected("--result half --output v.html", "half/translations.csv");
  // Truth and tracks of another size.
  ASSERT_EQ(Run("synth --dataset random --K 2 --frames 30 --points 25 --output "
                "other.mat")
                .exit_code,
            0);
  ExpectRejected("--result r --truth other.mat --output v.html",
                 "--truth 'other.mat' has F = 30, P = 25 but the result 'r' "
                 "has F = 40, P = 25");
  ExpectRejected("--result r --input other.mat --output v.html",
                 "--input 'other.mat' has F = 30, M = 1, P = 25 but the result "
                 "'r' has F = 40");
  ExpectRejected("--result r --truth missing.mat --output v.html",
                 "missing.mat");
  ExpectRejected("--result r --input missing.mat --output v.html",
                 "missing.mat");
  // Outputs that cannot be written.
  ExpectRejected("--result r --output v.txt",
                 "--output must name a .html file, got 'v.txt'", "v.txt");
  ExpectRejected("--result r --output /proc/nrsfm_view.html",
                 "'/proc/nrsfm_view.html'", "nope.html");
  fs::create_directory(Path("d.html"));
  ExpectRejected("--result r --output d.html",
                 "--output 'd.html' is a directory", "d.html");
  ExpectRejected(
      "--result r --output no/such/v.html",
      "--output 'no/such/v.html': the directory 'no/such' does not exist");
  // An existing page is replaced only with --overwrite.
  ASSERT_EQ(Run("view --result r --output v.html").exit_code, 0);
  const auto before = fs::last_write_time(Path("v.html"));
  ExpectRejected("--result r --output v.html",
                 "--output 'v.html' exists (use --overwrite");
  EXPECT_EQ(fs::last_write_time(Path("v.html")), before);
  const RunResult r =
      Run("view --result r --truth r.mat --output v.html --overwrite");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(PageData(testing_util::ReadFileToString(
      Path("v.html")))["meta"]["has_truth"]
                  .get<bool>());
}

}  // namespace
}  // namespace nrsfm
