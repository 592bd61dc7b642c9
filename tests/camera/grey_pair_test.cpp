// Input conversion: colour and 16-bit pairs reach the matcher as the same 8-bit grey
// images an 8-bit grey camera would give, through real PNG files.

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/camera/grey_pair.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "stereo/stereo_scene.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

cv::Mat grey8(int seed) {
  cv::Mat out;
  testing::smooth_texture(320, 240, seed).convertTo(out, CV_8U);
  return out;
}

/// 8-bit values v stored as a `bits`-bit sensor would: v * 2^(bits-8), plus low bits
/// below the 8-bit quantum (they must not change the result).
cv::Mat widen(const cv::Mat& g8, int bits) {
  cv::Mat out;
  g8.convertTo(out, CV_16U, static_cast<double>(1 << (bits - 8)), bits > 9 ? (1 << (bits - 10)) - 1 : 0);
  return out;
}

TEST(GreyPair, SignificantBits) {
  cv::Mat a(4, 4, CV_16U, cv::Scalar(10)), b(4, 4, CV_16U, cv::Scalar(10));
  EXPECT_EQ(significant_bits(a, b), 8);
  b.at<uint16_t>(1, 1) = 255;
  EXPECT_EQ(significant_bits(a, b), 8);
  a.at<uint16_t>(2, 3) = 256;
  EXPECT_EQ(significant_bits(a, b), 9);
  a.at<uint16_t>(2, 3) = 4095;
  EXPECT_EQ(significant_bits(a, b), 12);
  b.at<uint16_t>(0, 0) = 4096;
  EXPECT_EQ(significant_bits(a, b), 13);
  b.at<uint16_t>(0, 0) = 65535;
  EXPECT_EQ(significant_bits(a, b), 16);
}

TEST(GreyPair, ColourAndWideInputGiveTheSameGrey) {
  const cv::Mat l8 = grey8(1), r8 = grey8(2);
  GreyPairConverter auto_bits;
  cv::Mat ol, or_;
  EXPECT_EQ(auto_bits.convert(l8, r8, ol, or_), 8);
  EXPECT_EQ(cv::norm(ol, l8, cv::NORM_INF), 0);
  EXPECT_NE(ol.data, l8.data) << "the caller's image is copied, not shared";

  cv::Mat lc, rc;  // grey as BGR: luminance of equal channels is the grey value exactly
  cv::cvtColor(l8, lc, cv::COLOR_GRAY2BGR);
  cv::cvtColor(r8, rc, cv::COLOR_GRAY2BGR);
  EXPECT_EQ(auto_bits.convert(lc, rc, ol, or_), 8);
  EXPECT_EQ(cv::norm(ol, l8, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(or_, r8, cv::NORM_INF), 0);

  for (int bits : {10, 12, 16}) {
    EXPECT_EQ(auto_bits.convert(widen(l8, bits), widen(r8, bits), ol, or_), bits);
    EXPECT_EQ(cv::norm(ol, l8, cv::NORM_INF), 0) << bits;
    EXPECT_EQ(cv::norm(or_, r8, cv::NORM_INF), 0) << bits;
    GreyPairConverter fixed(bits);
    EXPECT_EQ(fixed.convert(widen(l8, bits), widen(r8, bits), ol, or_), bits);
    EXPECT_EQ(cv::norm(ol, l8, cv::NORM_INF), 0) << bits;
  }
  cv::Mat lc16, rc16;  // 16-bit colour
  cv::cvtColor(widen(l8, 12), lc16, cv::COLOR_GRAY2BGRA);
  cv::cvtColor(widen(r8, 12), rc16, cv::COLOR_GRAY2BGRA);
  EXPECT_EQ(auto_bits.convert(lc16, rc16, ol, or_), 12);
  EXPECT_LE(cv::norm(ol, l8, cv::NORM_INF), 1);  // luminance of 16-bit rounds once more

  EXPECT_THROW(auto_bits.convert(l8, widen(r8, 12), ol, or_), Error);
  cv::Mat f32;
  l8.convertTo(f32, CV_32F);
  EXPECT_THROW(auto_bits.convert(f32, f32, ol, or_), Error);
  EXPECT_THROW(GreyPairConverter(7), Error);
}

TEST(GreyPair, TenBitPngsMatchLikeTheirEightBitOriginals) {
  // A fronto-parallel plane at 9.5 px disparity, written as 8-bit and as 10-bit-in-16
  // PNGs: the front end must find identical disparities. Scaled by a fixed 1/256, the
  // 10-bit pair keeps 4 grey levels and its disparities lose accuracy.
  const int w = 320, h = 240;
  const double true_disparity_px = 9.5;
  const cv::Mat wide = grey8(3);
  cv::Mat shifted;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, -true_disparity_px, 0, 1, 0);
  cv::warpAffine(wide, shifted, shift, wide.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  testing::TempDir dir;
  cv::imwrite((dir / "l8.png").string(), wide);
  cv::imwrite((dir / "r8.png").string(), shifted);
  cv::imwrite((dir / "l10.png").string(), widen(wide, 10));
  cv::imwrite((dir / "r10.png").string(), widen(shifted, 10));
  StereoCalibration calib;
  calib.image_width = w;
  calib.image_height = h;
  calib.left.K << 300, 0, 159.5, 0, 300, 119.5, 0, 0, 1;
  calib.right.K = calib.left.K;
  calib.T = Eigen::Vector3d(-0.05, 0, 0);
  calib.rectified = true;
  StereoConfig stereo;
  stereo.num_disparities = 32;
  stereo.z_min_m = 0.1;
  SensorConfig sensor;
  StereoFrontEnd eight(stereo, sensor, calib), ten(stereo, sensor, calib);
  eight.process(read_image(dir / "l8.png"), read_image(dir / "r8.png"), Pose3d::Identity());
  ten.process(read_image(dir / "l10.png"), read_image(dir / "r10.png"), Pose3d::Identity());
  ASSERT_EQ(read_image(dir / "l10.png").depth(), CV_16U);
  EXPECT_EQ(ten.input_bits(), 10);
  ASSERT_GT(eight.cloud().size(), static_cast<size_t>(w * h / 2));
  EXPECT_EQ(cv::norm(eight.disparity_x16(), ten.disparity_x16(), cv::NORM_INF), 0);
  EXPECT_EQ(eight.cloud().size(), ten.cloud().size());

  auto mean_error_px = [&](const StereoFrontEnd& fe) {
    double sum = 0;
    for (const cv::Point& p : fe.pixels())
      sum += std::abs(fe.disparity_x16().at<int16_t>(p) / 16.0 - true_disparity_px);
    return sum / static_cast<double>(fe.pixels().size());
  };
  stereo.input_bits = 16;  // what a fixed 1/256 does to 10-bit data
  StereoFrontEnd crushed(stereo, sensor, calib);
  crushed.process(read_image(dir / "l10.png"), read_image(dir / "r10.png"), Pose3d::Identity());
  EXPECT_LT(mean_error_px(ten), 0.05);
  EXPECT_GT(mean_error_px(crushed), 2 * mean_error_px(ten));
}

}  // namespace
}  // namespace hazmap
