// The page of `nrsfm view` in a real browser: headless Chromium (Debian
// package `chromium`; NRSFM_CHROMIUM may name another binary) loads it from
// a file with every network lookup failing, and
//   * screenshots of two frames show non-blank 3D and 2D panes, in the
//     colours of the reconstruction, the truth, the tracks and the
//     reprojections, that differ between the frames (and not between two
//     shots of the same frame);
//   * the frame slider moves the frame (its input event, driven by the page's
//     #slide_to= fragment), and playback advances it;
//   * a result with --uncertainty colours the reconstruction by each point's
//     predicted std (viridis: its most uncertain points yellow), and #std=0
//     turns that off;
//   * the console shows no script error and no blocked load.
// Skips when Chromium is not installed.

#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_util.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

using RunResult = testing_util::CommandResult;

// The chromium binary: $NRSFM_CHROMIUM, else chromium or chromium-browser on
// the PATH; "" when there is none.
std::string FindChromium() {
  if (const char* env = std::getenv("NRSFM_CHROMIUM")) return env;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    for (const char* name : {"chromium", "chromium-browser"}) {
      const fs::path candidate = fs::path(dir) / name;
      std::error_code ec;
      if (fs::is_regular_file(candidate, ec)) return candidate.string();
    }
  }
  return "";
}

// An 8-bit RGB or RGBA, non-interlaced PNG (what Chromium writes) as RGB.
struct Image {
  int width = 0, height = 0;
  std::vector<std::array<uint8_t, 3>> pixels;  // row-major
  const std::array<uint8_t, 3>& at(int x, int y) const {
    return pixels[y * width + x];
  }
};

uint32_t BigEndian32(const std::string& s, size_t at) {
  return (uint32_t(uint8_t(s[at])) << 24) |
         (uint32_t(uint8_t(s[at + 1])) << 16) |
         (uint32_t(uint8_t(s[at + 2])) << 8) | uint32_t(uint8_t(s[at + 3]));
}

bool DecodePng(const std::string& file, Image* image, std::string* error) {
  if (file.size() < 8 || file.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) {
    *error = "not a PNG";
    return false;
  }
  int color_type = -1;
  std::string compressed;
  for (size_t at = 8; at + 12 <= file.size();) {
    const uint32_t length = BigEndian32(file, at);
    const std::string type = file.substr(at + 4, 4);
    if (at + 12 + length > file.size()) break;
    const std::string body = file.substr(at + 8, length);
    if (type == "IHDR") {
      image->width = static_cast<int>(BigEndian32(body, 0));
      image->height = static_cast<int>(BigEndian32(body, 4));
      color_type = uint8_t(body[9]);
      if (uint8_t(body[8]) != 8 || (color_type != 2 && color_type != 6) ||
          body[12] != 0) {
        *error = "unsupported PNG format";
        return false;
      }
    } else if (type == "IDAT") {
      compressed += body;
    }
    at += 12 + length;
  }
  if (color_type < 0 || image->width <= 0 || image->height <= 0) {
    *error = "no IHDR";
    return false;
  }
  const int channels = color_type == 6 ? 4 : 3;
  const size_t stride = size_t(image->width) * channels;
  std::vector<uint8_t> raw((stride + 1) * image->height);
  uLongf raw_size = raw.size();
  if (uncompress(raw.data(), &raw_size,
                 reinterpret_cast<const Bytef*>(compressed.data()),
                 compressed.size()) != Z_OK ||
      raw_size != raw.size()) {
    *error = "bad image data";
    return false;
  }
  // Undo the per-row filters (PNG spec 9.2).
  std::vector<uint8_t> previous(stride, 0), row(stride);
  image->pixels.resize(size_t(image->width) * image->height);
  for (int y = 0; y < image->height; ++y) {
    const uint8_t filter = raw[y * (stride + 1)];
    const uint8_t* in = &raw[y * (stride + 1) + 1];
    for (size_t i = 0; i < stride; ++i) {
      const int a = i >= size_t(channels) ? row[i - channels] : 0;
      const int b = previous[i];
      const int c = i >= size_t(channels) ? previous[i - channels] : 0;
      int predictor = 0;
      switch (filter) {
        case 0:
          predictor = 0;
          break;
        case 1:
          predictor = a;
          break;
        case 2:
          predictor = b;
          break;
        case 3:
          predictor = (a + b) / 2;
          break;
        case 4: {
          const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b),
                    pc = std::abs(p - c);
          predictor = (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
          break;
        }
        default:
          *error = "bad PNG filter";
          return false;
      }
      row[i] = static_cast<uint8_t>(in[i] + predictor);
    }
    for (int x = 0; x < image->width; ++x) {
      image->pixels[size_t(y) * image->width + x] = {
          row[x * channels], row[x * channels + 1], row[x * channels + 2]};
    }
    previous.swap(row);
  }
  return true;
}

struct Rect {
  int x = 0, y = 0, w = 0, h = 0;
};

// Pixels of `r` within `tolerance` (per channel) of `rgb`.
int CountColour(const Image& image, const Rect& r, std::array<int, 3> rgb,
                int tolerance) {
  int count = 0;
  for (int y = r.y; y < r.y + r.h; ++y) {
    for (int x = r.x; x < r.x + r.w; ++x) {
      const auto& p = image.at(x, y);
      if (std::abs(p[0] - rgb[0]) <= tolerance &&
          std::abs(p[1] - rgb[1]) <= tolerance &&
          std::abs(p[2] - rgb[2]) <= tolerance) {
        ++count;
      }
    }
  }
  return count;
}

int CountNotWhite(const Image& image, const Rect& r) {
  return r.w * r.h - CountColour(image, r, {255, 255, 255}, 24);
}

// Pixels of `r` where the two images differ by more than 24 in a channel.
int CountDifferent(const Image& a, const Image& b, const Rect& r) {
  int count = 0;
  for (int y = r.y; y < r.y + r.h; ++y) {
    for (int x = r.x; x < r.x + r.w; ++x) {
      const auto& p = a.at(x, y);
      const auto& q = b.at(x, y);
      if (std::abs(p[0] - q[0]) > 24 || std::abs(p[1] - q[1]) > 24 ||
          std::abs(p[2] - q[2]) > 24) {
        ++count;
      }
    }
  }
  return count;
}

// The page's colours (tools/viewer/viewer.js).
constexpr std::array<int, 3> kEstimate = {0x1f, 0x5f, 0xbf};
constexpr std::array<int, 3> kTruth = {0xe0, 0x7b, 0x00};
constexpr std::array<int, 3> kTrack = {0x1a, 0x96, 0x41};
constexpr std::array<int, 3> kStdHigh = {0xfd, 0xe7, 0x25};  // viridis(1)
constexpr std::array<int, 3> kStdLow = {0x44, 0x01, 0x54};   // viridis(0)

class ViewBrowserTest : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = FindChromium();
    if (chromium_.empty()) {
      GTEST_SKIP()
          << "chromium is not installed (apt-get install "
             "--no-install-recommends "
             "chromium); the page's data are checked by tools_view_test";
    }
    dir_ = testing_util::MakeTempDir("nrsfm_view_browser");
    ASSERT_FALSE(dir_.empty());
    RunResult r = Run(NRSFM_CLI,
                      "synth --dataset random --K 2 --frames 40 --points 25 "
                      "--seed 3 --noise 0.02 --missing 0.1 --output r.mat");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = Run(NRSFM_CLI, "reconstruct --input r.mat --K 2 --output r --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    r = Run(NRSFM_CLI,
            "view --result r --truth r.mat --input r.mat --output page.html");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  void TearDown() override {
    if (dir_.empty()) return;
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  RunResult Run(const std::string& executable, const std::string& args) {
    return testing_util::RunInDirectory(dir_, executable, args);
  }

  // Loads page.html#<fragment> in headless Chromium with a fresh profile,
  // no network (every host lookup fails) and the console on stderr; the DOM
  // after `virtual_time_ms` of (virtual) time is the output. With
  // `screenshot`, also writes a 1200 x 800 screenshot there.
  RunResult Chromium(const std::string& fragment,
                     const std::string& screenshot = "",
                     int virtual_time_ms = 500) {
    const std::string profile =
        (fs::path(dir_) / ("profile" + std::to_string(runs_++))).string();
    const std::string url =
        "file://" + (fs::path(dir_) / "page.html").string() + "#" + fragment;
    const std::string args =
        "120 env HOME='" + dir_ + "' '" + chromium_ +
        "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
        " --disable-background-networking --disable-component-update "
        "--disable-sync"
        " --user-data-dir='" +
        profile +
        "'"
        " --enable-unsafe-swiftshader --window-size=1200,800 "
        "--force-device-scale-factor=1"
        " --hide-scrollbars --host-resolver-rules='MAP * ~NOTFOUND'"
        " --enable-logging=stderr --v=0 --virtual-time-budget=" +
        std::to_string(virtual_time_ms) + " --dump-dom" +
        (screenshot.empty() ? "" : " --screenshot='" + screenshot + "'") +
        " '" + url + "'";
    RunResult r = Run("timeout", args);
    std::error_code ec;
    fs::remove_all(profile, ec);
    ExpectCleanConsole(r.err);
    return r;
  }

  // No uncaught script error and no load blocked by the page's
  // Content-Security-Policy (which would mean the page tried to fetch).
  static void ExpectCleanConsole(const std::string& log) {
    std::stringstream lines(log);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.find("CONSOLE") == std::string::npos) continue;
      EXPECT_EQ(line.find("Uncaught"), std::string::npos) << line;
      EXPECT_EQ(line.find("Content Security Policy"), std::string::npos)
          << line;
      EXPECT_EQ(line.find("Refused"), std::string::npos) << line;
    }
  }

  static std::string Title(const std::string& dom) {
    std::smatch m;
    return std::regex_search(dom, m, std::regex("<title>([^<]*)</title>"))
               ? m[1].str()
               : "";
  }

  static Rect BodyRect(const std::string& dom, const std::string& name) {
    std::smatch m;
    Rect r;
    if (std::regex_search(
            dom, m, std::regex(name + "=\"(\\d+) (\\d+) (\\d+) (\\d+)\""))) {
      r = {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4])};
    }
    return r;
  }

  // The screenshot of page.html#<fragment>; *dom (optional) gets the DOM.
  Image Screenshot(const std::string& fragment, const std::string& name,
                   std::string* dom = nullptr) {
    const std::string file = (fs::path(dir_) / name).string();
    const RunResult r = Chromium(fragment, file);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (dom != nullptr) *dom = r.out;
    Image image;
    std::string error;
    EXPECT_TRUE(DecodePng(testing_util::ReadFileToString(file), &image, &error))
        << name << ": " << error << "\n"
        << r.err;
    return image;
  }

  std::string chromium_, dir_;
  int runs_ = 0;
};

TEST_F(ViewBrowserTest, TwoFramesShowDifferentNonBlankPictures) {
  std::string dom0, dom20;
  const Image frame0 = Screenshot("frame=0", "frame0.png", &dom0);
  const Image again = Screenshot("frame=0", "frame0_again.png");
  const Image frame20 = Screenshot("frame=20", "frame20.png", &dom20);
  EXPECT_EQ(Title(dom0), "nrsfm view: frame 0 of 40");
  EXPECT_EQ(Title(dom20), "nrsfm view: frame 20 of 40");
  // Where the panes are (the page records its layout on <body>).
  const Rect view3d = BodyRect(dom0, "data-view3d");
  const Rect view2d = BodyRect(dom0, "data-view2d");
  ASSERT_GT(view3d.w, 200) << dom0.substr(0, 2000);
  ASSERT_GT(view3d.h, 200);
  ASSERT_GT(view2d.w, 200);
  ASSERT_GT(view2d.h, 200);
  for (const Image* image : {&frame0, &again, &frame20}) {
    ASSERT_EQ(image->width, 1200);
    ASSERT_EQ(image->height, 800);
    ASSERT_LE(view3d.x + view3d.w, 1200);
    ASSERT_LE(view3d.y + view3d.h, 800);
    ASSERT_LE(view2d.x + view2d.w, 1200);
    ASSERT_LE(view2d.y + view2d.h, 800);
  }
  for (const Image* image : {&frame0, &frame20}) {
    // Drawn, in the page's colours: reconstruction and truth in 3D, tracks
    // and reprojections in 2D.
    EXPECT_GT(CountNotWhite(*image, view3d), 1000);
    EXPECT_GT(CountColour(*image, view3d, kEstimate, 30), 100);
    EXPECT_GT(CountColour(*image, view3d, kTruth, 30), 100);
    EXPECT_GT(CountNotWhite(*image, view2d), 1000);
    EXPECT_GT(CountColour(*image, view2d, kTrack, 30), 100);
    EXPECT_GT(CountColour(*image, view2d, kEstimate, 30), 100);
  }
  // The same frame gives the same picture; another frame another one.
  EXPECT_LT(CountDifferent(frame0, again, view3d), 20);
  EXPECT_LT(CountDifferent(frame0, again, view2d), 20);
  EXPECT_GT(CountDifferent(frame0, frame20, view3d), 500);
  EXPECT_GT(CountDifferent(frame0, frame20, view2d), 500);
}

TEST_F(ViewBrowserTest, SliderAndPlaybackMoveTheFrame) {
  // The slider's input event, as a drag sends it, moves the frame from the
  // one the fragment shows first (frame=N alone: TwoFramesShow… above).
  RunResult r = Chromium("frame=2&slide_to=9");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Title(r.out), "nrsfm view: frame 9 of 40");
  EXPECT_NE(r.out.find("frame 9 / 39"), std::string::npos)
      << "frame label not updated";
  // Playing at 10 frames/s for 3 s of (virtual) time advances the frame.
  r = Chromium("frame=0&play=1&fps=10", "", /*virtual_time_ms=*/3000);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  const std::string title = Title(r.out);
  ASSERT_TRUE(
      std::regex_match(title, m, std::regex("nrsfm view: frame (\\d+) of 40")))
      << title;
  EXPECT_GE(std::stoi(m[1]), 10) << title;
}

TEST_F(ViewBrowserTest, PointsAreColouredByTheirPredictedStd) {
  RunResult r = Run(NRSFM_CLI,
                    "reconstruct --input r.mat --K 2 --output ru --uncertainty "
                    "--quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  r = Run(NRSFM_CLI,
          "view --result ru --truth r.mat --input r.mat --output page.html "
          "--overwrite");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The frame with the largest predicted spread holds points above the
  // scale's 95th percentile (yellow); with #std=0 the plain colour again.
  // Measured (Chromium 1200 x 800): 167 yellow pixels and none of the plain
  // colour; with std=0 262 of the plain colour and none of either end.
  const nlohmann::json result = nlohmann::json::parse(
      testing_util::ReadFileToString((fs::path(dir_) / "ru/result.json")));
  const int worst = static_cast<int>(
      result["diagnostics"]["uncertainty_worst_frame"].get<double>());
  const std::string frame = "frame=" + std::to_string(worst);
  std::string dom;
  const Image coloured = Screenshot(frame, "std.png", &dom);
  const Image plain = Screenshot(frame + "&std=0", "plain.png");
  const Rect view3d = BodyRect(dom, "data-view3d");
  ASSERT_GT(view3d.w, 200) << dom.substr(0, 2000);
  EXPECT_GT(CountColour(coloured, view3d, kStdHigh, 30), 20);
  EXPECT_LT(CountColour(coloured, view3d, kEstimate, 30), 20);
  EXPECT_LT(CountColour(plain, view3d, kStdHigh, 30), 5);
  EXPECT_LT(CountColour(plain, view3d, kStdLow, 30), 5);
  EXPECT_GT(CountColour(plain, view3d, kEstimate, 30), 100);
  // The legend names the scale's ends; the controls offer the switch.
  EXPECT_NE(dom.find("predicted std "), std::string::npos);
  EXPECT_NE(dom.find("colour by std"), std::string::npos);
}

}  // namespace
}  // namespace nrsfm
