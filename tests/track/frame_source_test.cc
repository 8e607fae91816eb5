// The frame sources and the queries: every bad input is one clear error.
#include "track/frame_source.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "tests/test_util.h"
#include "track/tracker.h"

namespace nrsfm {
namespace track {
namespace {

namespace fs = std::filesystem;

cv::Mat Gradient(int width, int height, int offset) {
  cv::Mat image(height, width, CV_8U);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.at<unsigned char>(y, x) =
          static_cast<unsigned char>((x + y + offset) % 256);
    }
  }
  return image;
}

TEST(FrameSourceTest, AFolderIsInTheOrderOfTheFrameNumbers) {
  const std::string dir = testing_util::MakeTempDir("frames");
  // Unpadded names: by name 10 would come before 9.
  for (int f : {10, 9, 11}) {
    ASSERT_TRUE(cv::imwrite(dir + "/img" + std::to_string(f) + ".png",
                            Gradient(40, 30, f)));
  }
  std::ofstream(dir + "/notes.txt") << "not an image";
  FrameSource source;
  const Status status = FrameSource::OpenFolder(dir, &source);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(source.frame_numbers(), (std::vector<int>{9, 10, 11}));
  EXPECT_EQ(source.size(), cv::Size(40, 30));
  cv::Mat grey;
  ASSERT_TRUE(source.Read(1, &grey).ok());
  // Frame 10's pixel (0, 0) is 10 (PNG is lossless).
  EXPECT_EQ(grey.at<unsigned char>(0, 0), 10);
}

TEST(FrameSourceTest, BadFoldersAreErrorsThatNameTheFile) {
  FrameSource source;
  const std::string empty = testing_util::MakeTempDir("empty");
  EXPECT_NE(FrameSource::OpenFolder(empty, &source)
                .message()
                .find("no image in the folder"),
            std::string::npos);
  EXPECT_NE(FrameSource::OpenFolder(empty + "/missing", &source)
                .message()
                .find("not a folder"),
            std::string::npos);

  const std::string unnumbered = testing_util::MakeTempDir("unnumbered");
  ASSERT_TRUE(cv::imwrite(unnumbered + "/first.png", Gradient(40, 30, 0)));
  EXPECT_NE(FrameSource::OpenFolder(unnumbered, &source)
                .message()
                .find("first.png: no frame number"),
            std::string::npos);

  const std::string twice = testing_util::MakeTempDir("twice");
  ASSERT_TRUE(cv::imwrite(twice + "/a1.png", Gradient(40, 30, 0)));
  ASSERT_TRUE(cv::imwrite(twice + "/b001.png", Gradient(40, 30, 0)));
  EXPECT_NE(FrameSource::OpenFolder(twice, &source)
                .message()
                .find("frame number 1 is also that of"),
            std::string::npos);

  const std::string mixed = testing_util::MakeTempDir("mixed");
  ASSERT_TRUE(cv::imwrite(mixed + "/0.png", Gradient(40, 30, 0)));
  ASSERT_TRUE(cv::imwrite(mixed + "/1.png", Gradient(41, 30, 0)));
  ASSERT_TRUE(FrameSource::OpenFolder(mixed, &source).ok());
  cv::Mat grey;
  const Status size_error = source.Read(1, &grey);
  EXPECT_NE(size_error.message().find(
                "1.png: 41 x 30, but the first frame is 40 x 30"),
            std::string::npos)
      << size_error.message();

  const std::string broken = testing_util::MakeTempDir("broken");
  ASSERT_TRUE(cv::imwrite(broken + "/0.png", Gradient(40, 30, 0)));
  std::ofstream(broken + "/1.jpg") << "not a JPEG";
  ASSERT_TRUE(FrameSource::OpenFolder(broken, &source).ok());
  EXPECT_NE(
      source.Read(1, &grey).message().find("1.jpg: cannot decode the image"),
      std::string::npos);
}

TEST(FrameSourceTest, AVideoIsCountedAndReadInOrder) {
  const std::string dir = testing_util::MakeTempDir("video");
  QuietOpenCvLog();  // FFmpeg's message on the fake file below
  const std::string path = dir + "/clip.avi";
  // OpenCV's own Motion-JPEG writer: no external encoder needed.
  cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                         cv::Size(64, 48), /*isColor=*/false);
  ASSERT_TRUE(writer.isOpened());
  for (int f = 0; f < 7; ++f)
    writer.write(cv::Mat(48, 64, CV_8U, cv::Scalar(30 * f)));
  writer.release();
  FrameSource source;
  const Status status = FrameSource::OpenVideo(path, &source);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(source.num_frames(), 7);
  cv::Mat grey;
  ASSERT_TRUE(source.Read(5, &grey).ok());
  // Flat frames survive JPEG to within a grey level or two.
  EXPECT_NEAR(grey.at<unsigned char>(20, 20), 150, 3);
  ASSERT_TRUE(source.Read(2, &grey).ok());  // backwards: reopened
  EXPECT_NEAR(grey.at<unsigned char>(20, 20), 60, 3);

  std::ofstream(dir + "/fake.mp4") << "not a video";
  const Status bad = FrameSource::OpenVideo(dir + "/fake.mp4", &source);
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("fake.mp4"), std::string::npos) << bad.message();
}

TEST(QueriesTest, BadRowsAreNamed) {
  const std::string dir = testing_util::MakeTempDir("queries");
  std::vector<Query> queries;
  std::ofstream(dir + "/good.csv") << "point,frame,x,y\n3,0,10.5,20\n7,4,1,2\n";
  ASSERT_TRUE(ReadQueries(dir + "/good.csv", &queries).ok());
  ASSERT_EQ(queries.size(), 2u);
  EXPECT_EQ(queries[1].point, 7);
  EXPECT_EQ(queries[1].frame, 4);
  EXPECT_DOUBLE_EQ(queries[0].x, 10.5);
  std::ofstream(dir + "/twice.csv") << "point,frame,x,y\n3,0,1,2\n3,1,1,2\n";
  EXPECT_NE(ReadQueries(dir + "/twice.csv", &queries)
                .message()
                .find("row 2 of the queries: point 3 is queried twice"),
            std::string::npos);
  std::ofstream(dir + "/frac.csv") << "point,frame,x,y\n3,0.5,1,2\n";
  EXPECT_NE(ReadQueries(dir + "/frac.csv", &queries)
                .message()
                .find("frame is not an integer"),
            std::string::npos);
  std::ofstream(dir + "/header.csv") << "id,frame,x,y\n3,0,1,2\n";
  EXPECT_FALSE(ReadQueries(dir + "/header.csv", &queries).ok());
}

}  // namespace
}  // namespace track
}  // namespace nrsfm
