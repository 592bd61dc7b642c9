// Row offset of rectified pairs (issue 32 item 3): the feature-match estimate against
// real images shifted by a known sub-pixel offset, the rectifier's map shift against a
// remap of its unshifted output, the shared planetary-analog pairs, the config key.

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/camera/rectifier.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/preflight_check.hpp"
#include "hazmap/sim/simulate.hpp"
#include "hazmap/stereo/row_offset.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;

const std::string kLayer =
    "map:\n  layers:\n    - {resolution: 0.01, size: 128, rule: kalman, hazard: {kernel: 1}}\n";

fs::path analog(const std::string& rig) {
  return testing::source_dir() / "../shared/data/planetary_analog" / rig / "seq";
}

cv::Mat grey(const fs::path& file) {
  cv::Mat m = read_image(file);
  if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  return m;
}

/// right(x, y) = left(x + disparity, y + offset): a feature at row y of the left image is
/// at y - offset in the right one (y_left - y_right = offset).
cv::Mat shifted(const cv::Mat& left, double disparity, double offset) {
  cv::Mat right;
  const cv::Matx23d M(1, 0, disparity, 0, 1, offset);
  cv::warpAffine(left, right, M, left.size(), cv::INTER_CUBIC | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REFLECT);
  return right;
}

TEST(RowOffset, KnownSubPixelShiftOfARealImageIsFoundWithinATenthOfAPixel) {
  // K10's raw left image: asphalt, gravel, boulders, buildings.
  const cv::Mat left = grey(analog("k10_ames") / "left/000000.png");
  for (const double offset : {0.0, 0.37, -0.8, 1.6, 2.5, -3.25}) {
    SCOPED_TRACE(offset);
    const RowOffsetEstimate e = estimate_row_offset(left, shifted(left, 17.0, offset));
    ASSERT_TRUE(e.found) << e.matches << " matches, " << e.inliers << " inliers";
    EXPECT_NEAR(e.offset_px, offset, 0.1);
    EXPECT_GE(e.inliers, 100);
    EXPECT_LT(e.spread_px, 0.2);  // one rigid shift: the matches agree closely
  }
}

TEST(RowOffset, TooFewFeaturesGiveNoEstimateAndBadImagesThrow) {
  const cv::Mat flat(200, 300, CV_8UC1, cv::Scalar(90));
  EXPECT_FALSE(estimate_row_offset(flat, flat).found);
  EXPECT_THROW(estimate_row_offset(flat, cv::Mat(200, 301, CV_8UC1, cv::Scalar(0))), Error);
  EXPECT_THROW(estimate_row_offset(cv::Mat(200, 300, CV_16UC1), cv::Mat(200, 300, CV_16UC1)), Error);
}

/// The raw row index as an image: rectified, each pixel tells the raw row it came from.
cv::Mat raw_rows(cv::Size size) {
  cv::Mat rows(size, CV_32FC1);
  for (int v = 0; v < size.height; ++v) rows.row(v).setTo(static_cast<float>(v));
  return rows;
}

/// The largest |a(u, v) - b(u, v - d)| over the interior (b sampled bilinearly).
double shift_error(const cv::Mat& a, const cv::Mat& b, double d, int margin) {
  cv::Mat map_x(a.size(), CV_32FC1), map_y(a.size(), CV_32FC1);
  for (int v = 0; v < a.rows; ++v)
    for (int u = 0; u < a.cols; ++u) {
      map_x.at<float>(v, u) = static_cast<float>(u);
      map_y.at<float>(v, u) = static_cast<float>(v - d);
    }
  cv::Mat b_moved;
  cv::remap(b, b_moved, map_x, map_y, cv::INTER_LINEAR);
  const cv::Rect inner(margin, margin, a.cols - 2 * margin, a.rows - 2 * margin);
  cv::Mat diff;
  cv::absdiff(a(inner), b_moved(inner), diff);
  double worst = 0;
  cv::minMaxLoc(diff, nullptr, &worst);
  return worst;
}

TEST(RowOffset, RectifierMovesTheRightImageDownByTheOffset) {
  // K10: a distorted pinhole rig; the right image's rows move by d, the left's not at all.
  const StereoCalibration calib = load_stereo_calibration(analog("k10_ames") / "calibration.yaml");
  const cv::Size size(calib.image_width, calib.image_height);
  const cv::Mat rows = raw_rows(size);
  const Rectifier plain(calib, 0.0);
  cv::Mat l0, r0, l1, r1;
  plain.rectify(rows, rows, l0, r0);
  for (const double d : {0.75, -1.6, 3.0}) {
    SCOPED_TRACE(d);
    Rectifier moved(calib, 0.0, d);
    EXPECT_EQ(moved.row_offset(), d);
    moved.rectify(rows, rows, l1, r1);
    EXPECT_EQ(cv::norm(l0, l1, cv::NORM_INF), 0.0);
    // 1/32 px fixed-point maps on both sides, a bilinear resample: a few hundredths.
    EXPECT_LT(shift_error(r1, r0, d, 40), 0.06);
    EXPECT_GT(shift_error(r1, r0, 0.0, 40), 0.5 * std::abs(d));  // it did move
    // rectify_points is still the exact inverse of the remap.
    std::vector<cv::Point2f> raw{{300.f, 200.f}, {700.f, 550.f}}, a, b;
    plain.rectify_points(StereoSide::right, raw, a);
    moved.rectify_points(StereoSide::right, raw, b);
    for (size_t i = 0; i < raw.size(); ++i) {
      EXPECT_NEAR(b[i].x, a[i].x, 1e-3);
      EXPECT_NEAR(b[i].y - a[i].y, d, 1e-3);
    }
    // Its valid region moved with it.
    EXPECT_NEAR(moved.valid_roi_right().y, std::max(0.0, plain.valid_roi_right().y + d), 1.0);
    // Setting the offset back to 0 restores the plain maps exactly.
    moved.set_row_offset(0.0);
    moved.rectify(rows, rows, l1, r1);
    EXPECT_EQ(cv::norm(r0, r1, cv::NORM_INF), 0.0);
  }
}

TEST(RowOffset, RectifiedCalibrationsGetARightShiftMap) {
  StereoCalibration calib = load_stereo_calibration(analog("k10_ames") / "calibration.yaml");
  calib.rectified = true;
  calib.left.D.clear();
  calib.right.D.clear();
  calib.right.K = calib.left.K;
  calib.R.setIdentity();
  const cv::Mat rows = raw_rows(cv::Size(calib.image_width, calib.image_height));
  const Rectifier moved(calib, 0.0, 1.25);
  cv::Mat l, r;
  moved.rectify(rows, rows, l, r);
  EXPECT_EQ(cv::norm(l, rows, cv::NORM_INF), 0.0);
  EXPECT_LT(shift_error(r, rows, 1.25, 4), 1.0 / 32 + 1e-6);
}

/// The rectified pair of one of the shared rigs, with `offset_px` applied.
void rectified_pair(const std::string& rig, double offset_px, cv::Mat& left, cv::Mat& right) {
  const StereoCalibration calib = load_stereo_calibration(analog(rig) / "calibration.yaml");
  const Rectifier rectifier(calib, 0.0, offset_px);
  rectifier.rectify(grey(analog(rig) / "left/000000.png"), grey(analog(rig) / "right/000000.png"),
                    left, right);
}

TEST(RowOffset, SharedPolarPairLeavesAboutPlusOnePointSixPixels) {
  // README_SOURCE: POLAR's calibration leaves y_left - y_right = +1.6 px.
  cv::Mat l, r;
  rectified_pair("polar_traverse_1m", 0.0, l, r);
  const RowOffsetEstimate e = estimate_row_offset(l, r);
  ASSERT_TRUE(e.found);
  EXPECT_NEAR(e.offset_px, 1.6, 0.2) << e.spread_px << " spread, " << e.inliers << " inliers";
  EXPECT_GE(e.inliers, 100);
  // Corrected by that offset, the rows agree.
  rectified_pair("polar_traverse_1m", e.offset_px, l, r);
  const RowOffsetEstimate after = estimate_row_offset(l, r);
  ASSERT_TRUE(after.found);
  EXPECT_NEAR(after.offset_px, 0.0, 0.1);
}

TEST(RowOffset, SharedK10PairAgreesToAboutAPixel) {
  cv::Mat l, r;
  rectified_pair("k10_ames", 0.0, l, r);
  const RowOffsetEstimate e = estimate_row_offset(l, r);
  ASSERT_TRUE(e.found);
  EXPECT_LE(std::abs(e.offset_px), 1.1) << e.spread_px << " spread, " << e.inliers << " inliers";
}

TEST(RowOffset, ConfigTakesANumberOrAuto) {
  EXPECT_EQ(Config{}.stereo.row_offset, 0.0);
  const Config number = parse_config(kLayer + "stereo: {row_offset_px: -1.25}\n", "c.yaml");
  EXPECT_EQ(number.stereo.row_offset, -1.25);
  const Config automatic = parse_config(kLayer + "stereo: {row_offset_px: auto}\n", "c.yaml");
  EXPECT_FALSE(automatic.stereo.row_offset.has_value());
  // The resolved configuration reads back as it was.
  EXPECT_FALSE(parse_config(to_yaml(automatic), "dump").stereo.row_offset.has_value());
  EXPECT_EQ(parse_config(to_yaml(number), "dump").stereo.row_offset, -1.25);
  for (const char* bad : {"stereo: {row_offset_px: 101}\n", "stereo: {row_offset_px: .nan}\n",
                          "stereo: {row_offset_px: automatic}\n"}) {
    SCOPED_TRACE(bad);
    try {
      parse_config(kLayer + bad, "c.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("row_offset_px"), std::string::npos) << e.what();
    }
  }
}

TEST(RowOffset, AutoMeasuresTheOffsetOnTheFirstFrame) {
  const StereoCalibration calib =
      load_stereo_calibration(analog("polar_traverse_1m") / "calibration.yaml");
  StereoConfig stereo = parse_config(kLayer + "stereo: {row_offset_px: auto, matcher: bm, num_disparities: 64}\n",
                                     "c.yaml").stereo;
  StereoFrontEnd front(stereo, SensorConfig{}, calib, false);
  EXPECT_EQ(front.rectifier().row_offset(), 0.0);
  const cv::Mat left = grey(analog("polar_traverse_1m") / "left/000000.png");
  const cv::Mat right = grey(analog("polar_traverse_1m") / "right/000000.png");
  front.process(left, right, Pose3d::Identity());
  EXPECT_NEAR(front.rectifier().row_offset(), 1.6, 0.2);
  // The pair the matcher saw was rectified with it: its rows agree.
  const RowOffsetEstimate after = estimate_row_offset(front.rectified_left(), front.rectified_right());
  ASSERT_TRUE(after.found);
  EXPECT_NEAR(after.offset_px, 0.0, 0.1);
  // Measured once: a later frame keeps it.
  const double first = front.rectifier().row_offset();
  front.process(left, shifted(right, 0.0, 1.0), Pose3d::Identity());
  EXPECT_EQ(front.rectifier().row_offset(), first);
}

TEST(RowOffset, CheckMeasuresItAndTheConfiguredShiftRemovesIt) {
  // A rendered flat field (rectified calibration: the right image gets a shift map), its
  // right images moved 1.5 rows up: y_left - y_right = +1.5 px.
  testing::TempDir dir;
  sim::SimulationOptions o;
  o.scenario = "flat";
  o.seed = 5151;
  o.frames = 1;
  o.scale = 0.4;
  o.png_compression = 1;
  sim::simulate_sequence(o, dir.path());
  for (const auto& e : fs::directory_iterator(dir / "right"))
    cv::imwrite(e.path().string(), shifted(cv::imread(e.path().string(), cv::IMREAD_UNCHANGED), 0.0, 1.5));
  const Sequence seq = load_sequence(dir.path());
  const auto check = [&](const std::string& offset) {
    return preflight_check(
        load_config(testing::source_dir() / "config/default.yaml", {"stereo.row_offset_px=" + offset}),
        seq, {});
  };
  const PreflightReport off = check("0");
  EXPECT_NEAR(off.calibration.row_offset.offset_px, 1.5, 0.1);
  EXPECT_EQ(off.calibration.row_offset.frames, 1);
  ASSERT_FALSE(off.problems.empty());
  EXPECT_EQ(off.problems.front().rfind("rectified rows disagree by +1.5", 0), 0u) << off.problems.front();
  EXPECT_NE(format_report(off).find("row offset (features): y_left - y_right +1.5"), std::string::npos)
      << format_report(off);
  for (const std::string& setting : {std::string("1.5"), std::string("auto")}) {
    SCOPED_TRACE(setting);
    const PreflightReport on = check(setting);
    EXPECT_NEAR(on.calibration.row_offset.applied_px, 1.5, 0.1);
    EXPECT_NEAR(on.calibration.row_offset.offset_px, 0.0, 0.1);
    EXPECT_TRUE(on.problems.empty()) << on.problems.front();
    // Block matching compares the right rows again: more pixels get a disparity.
    EXPECT_GT(on.frames[0].valid_disparity_share, off.frames[0].valid_disparity_share);
  }
}

}  // namespace
}  // namespace hazmap
