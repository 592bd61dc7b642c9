// Stereo calibration on OpenCV's 13 real chessboard pairs (shared data,
// ../shared/data/chessboard): the calibration must fit (RMS) and must rectify: the same
// corners, detected again in the rectified images, lie on one row.

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hazmap/camera/chessboard_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/chessboard_pairs.hpp"
#include "hazmap/io/images.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr double kMaxRmsPx = 0.5;
constexpr double kMaxMeanDyPx = 0.3;
constexpr double kMaxP99DyPx = 1.0;

std::filesystem::path chessboard_dir() {
  return testing::source_dir() / "../shared/data/chessboard";
}

#define SKIP_WITHOUT_CHESSBOARDS()                                                   \
  if (!std::filesystem::is_directory(chessboard_dir()))                              \
  GTEST_SKIP() << chessboard_dir().string() << " is absent (shared real data)"

ChessboardOptions board_9x6() {
  ChessboardOptions o;
  o.inner_corners = {9, 6};
  o.square_m = 0.025;
  return o;
}

TEST(ChessboardCalibration, FitsAndRectifiesTheRealPairs) {
  SKIP_WITHOUT_CHESSBOARDS();
  const ChessboardCalibration result = calibrate_chessboard_pairs(chessboard_dir(), board_9x6());
  EXPECT_EQ(result.views.size(), 13u);
  EXPECT_TRUE(result.rejected.empty());
  EXPECT_LT(result.rms_px, kMaxRmsPx);
  const StereoCalibration& c = result.calibration;
  EXPECT_EQ(c.image_width, 640);
  EXPECT_EQ(c.image_height, 480);
  EXPECT_EQ(c.left.D.size(), 5u);  // OpenCV's 5-parameter model
  // A side-by-side rig: the right camera lies along +x of the left one.
  EXPECT_LT(c.T.x(), 0.0);
  EXPECT_LT(std::hypot(c.T.y(), c.T.z()), 0.05 * c.T.norm());

  // Rectify the images with this calibration and detect the corners again.
  const Rectifier rectifier(c, 0.0);
  std::vector<ChessboardView> rectified;
  cv::Mat grey_left, grey_right, rect_left, rect_right;
  for (const ChessboardPairFiles& pair : find_chessboard_pairs(chessboard_dir())) {
    to_gray8(read_image(pair.left), grey_left);
    to_gray8(read_image(pair.right), grey_right);
    rectifier.rectify(grey_left, grey_right, rect_left, rect_right);
    ChessboardView view;
    view.name = pair.name;
    ASSERT_TRUE(detect_chessboard_pair(rect_left, rect_right, board_9x6(), view)) << pair.name;
    rectified.push_back(view);
  }
  const RowAlignment detected = row_alignment(rectified);
  EXPECT_EQ(detected.points, 13u * 54u);
  EXPECT_LE(detected.mean_abs_dy_px, kMaxMeanDyPx);
  EXPECT_LE(detected.p99_abs_dy_px, kMaxP99DyPx);
  // The raw corners mapped through the rectification: the same bounds.
  const RowAlignment mapped = measure_row_alignment(rectifier, result.views);
  EXPECT_LE(mapped.mean_abs_dy_px, kMaxMeanDyPx);
  EXPECT_LE(mapped.p99_abs_dy_px, kMaxP99DyPx);
  std::printf("[ measured ] RMS %.3f px, baseline %.2f mm, f' %.1f px; |dy| re-detected: mean "
              "%.3f, p99 %.3f, max %.3f px; mapped: mean %.3f, p99 %.3f, max %.3f px\n",
              result.rms_px, 1e3 * c.T.norm(), rectifier.geometry().focal_px,
              detected.mean_abs_dy_px, detected.p99_abs_dy_px, detected.max_abs_dy_px,
              mapped.mean_abs_dy_px, mapped.p99_abs_dy_px, mapped.max_abs_dy_px);
}

TEST(ChessboardCalibration, CalibrateCommandWritesOurFormat) {
  SKIP_WITHOUT_CHESSBOARDS();
  testing::TempDir dir;
  const std::string cmd = std::string(HAZMAP_CLI) + " calibrate --images " +
                          chessboard_dir().string() + " --board 9x6 --square 0.025 --out " +
                          (dir / "calibration.yaml").string() + " --quiet > " +
                          (dir / "out.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  std::ifstream out(dir / "out.txt");
  const std::string text((std::istreambuf_iterator<char>(out)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("RMS reprojection error: 0."), std::string::npos) << text;
  EXPECT_NE(text.find("baseline: 0.08"), std::string::npos) << text;
  // The file holds what the library computes in-process.
  const StereoCalibration written = load_stereo_calibration(dir / "calibration.yaml");
  const StereoCalibration direct =
      calibrate_chessboard_pairs(chessboard_dir(), board_9x6()).calibration;
  EXPECT_LT((written.left.K - direct.left.K).norm(), 1e-9);
  EXPECT_LT((written.T - direct.T).norm(), 1e-12);
}

TEST(ChessboardCalibration, PairsByFolderOrPrefixAndErrors) {
  testing::TempDir dir;
  const cv::Mat blank(48, 64, CV_8UC1, cv::Scalar(128));
  std::filesystem::create_directories(dir / "seq/left");
  std::filesystem::create_directories(dir / "seq/right");
  cv::imwrite((dir / "seq/left/a.png").string(), blank);
  cv::imwrite((dir / "seq/right/a.png").string(), blank);
  cv::imwrite((dir / "seq/left/b.png").string(), blank);  // no partner
  const auto pairs = find_chessboard_pairs(dir / "seq");
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].name, "a");
  cv::imwrite((dir / "left07.jpg").string(), blank);
  cv::imwrite((dir / "right07.jpg").string(), blank);
  const auto prefixed = find_chessboard_pairs(dir.path());
  ASSERT_EQ(prefixed.size(), 1u);
  EXPECT_EQ(prefixed[0].name, "07");
  // Blank images show no board: too few views.
  try {
    calibrate_chessboard_pairs(dir.path(), board_9x6());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("found in both images of only 0 pairs"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(find_chessboard_pairs(dir / "seq/left"), Error);  // no pairs there
}

}  // namespace
}  // namespace hazmap
