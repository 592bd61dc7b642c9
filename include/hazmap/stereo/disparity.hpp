#pragma once
// Block-matching disparity (SPEC 3.2): cv::StereoBM or cv::StereoSGBM (modes sgbm, hh,
// sgbm_3way, hh4) with every knob from the `stereo` config: range, block size,
// uniqueness, texture threshold and pre-filter (BM), penalties P1/P2 (SGBM), speckle
// filter (speckle_range in pixels: x16 for StereoBM, which compares fixed-point values,
// while SGBM scales it itself), left-right consistency check (disp12_max_diff, -1 off).
// Output is OpenCV's fixed point with 4 fractional bits (sub-pixel): CV_16S, disparity
// x 16; values <= 16 * min_disparity are invalid (SPEC 3.2).
// Matching runs on OpenCV's thread pool (cv::setNumThreads): StereoBM splits the image
// in stripes, SGBM in its sgbm_3way and hh4 modes; sgbm and hh are single-threaded.
// `stereo.matcher: c2f` is ours (c2f_matcher.hpp), same output format; it needs the
// rectified geometry (its range ends at f B / z_min) and does a full search only.
// `stereo.search: ground_band` (SPEC 3.4) matches horizontal strips over the disparities
// terrain can produce there instead (band_matcher.hpp), strips in parallel.

#include <memory>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/stereo/sensor_model.hpp"
#include "hazmap/stereo/stereo_config.hpp"
#include "hazmap/stereo/texture_gate.hpp"

namespace hazmap {

class BandMatcher;
class C2fMatcher;

/// A cv::StereoBM or cv::StereoSGBM with every knob of `config` except the range, which
/// is [min_disparity, min_disparity + num_disparities); `speckle_filter` false leaves the
/// speckle filter off. Throws Error naming the key for an unknown matcher, mode or
/// pre-filter type, or for c2f (not an OpenCV matcher).
cv::Ptr<cv::StereoMatcher> create_stereo_matcher(const StereoConfig& config, int min_disparity,
                                                 int num_disparities, bool speckle_filter);

/// The largest disparity ground-band matching searches (exclusive end, a multiple of 16):
/// f B / stereo.z_min, since nearer points are dropped anyway (SPEC 3.3), plus the two
/// disparities of the sub-pixel margin, rounded up to 16; and at most what leaves a
/// column to match in an image `width` wide (width - block_size + 1, rounded down).
int band_disparity_cap(const StereoConfig& config, const StereoGeometry& geometry, int width);

/// The end of c2f's search (exclusive): min_disparity + num_disparities, or f B / z_min
/// rounded up plus the sub-pixel margin where that is smaller; at most `width`.
int c2f_disparity_end(const StereoConfig& config, const StereoGeometry& geometry, int width);

/// Throws Error naming the key when the stereo settings cannot fit a `image`-sized
/// rectified image: min_disparity + num_disparities wider than it, or an roi reaching
/// outside it.
void check_against_image(const StereoConfig& config, cv::Size image);

class DisparityMatcher {
 public:
  /// Full search only, bm / sgbm only. Throws Error naming the key for an unknown matcher,
  /// mode or pre-filter type, for c2f or for `search: ground_band` (both need the
  /// camera's geometry).
  explicit DisparityMatcher(const StereoConfig& config);

  /// Either search. `geometry`: the rectified pair; `T_B_Cr`: the rectified left camera
  /// in the body frame (rectified_camera_in_body); `image_size`: the rectified images'.
  DisparityMatcher(const StereoConfig& config, const StereoGeometry& geometry,
                   const Pose3d& T_B_Cr, cv::Size image_size);
  ~DisparityMatcher();
  DisparityMatcher(DisparityMatcher&&) noexcept;
  DisparityMatcher& operator=(DisparityMatcher&&) noexcept;

  /// Rectified 8-bit grey images in, fixed-point disparity out (buffer reused).
  /// Throws Error for other image types or sizes that differ.
  void compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16);

  /// Smallest valid fixed-point value (exclusive): d16 > invalid_below() is valid.
  int invalid_below() const { return 16 * min_disparity_; }
  /// The range searched: stereo.min_disparity / num_disparities for a full search, the
  /// span of all strips' ranges for ground_band.
  int min_disparity() const { return searched_min_; }
  int num_disparities() const { return searched_num_; }
  /// The strip matcher of `search: ground_band`, nullptr for a full search.
  const BandMatcher* band() const { return band_.get(); }
  /// The coarse-to-fine matcher of `matcher: c2f`, nullptr for bm / sgbm.
  const C2fMatcher* c2f() const { return c2f_.get(); }
  /// Per image row (`rows` of them), the end of the disparities searched there (exclusive,
  /// px): min_disparity + num_disparities for a full search, the row's strip's end for
  /// ground_band (0 where a strip searches nothing). A surface nearer than f B / end
  /// cannot be matched in that row.
  std::vector<int> search_end_by_row(int rows) const;

 private:
  /// stereo.match_left_border, after the crop: drops the band's disparities that leave
  /// the right window less than a window from the right image's edge (row-wide rule).
  void drop_matches_into_padding(cv::Mat& disparity_x16) const;

  cv::Ptr<cv::StereoMatcher> matcher_;
  std::unique_ptr<BandMatcher> band_;
  std::unique_ptr<C2fMatcher> c2f_;
  int min_disparity_ = 0;
  int searched_min_ = 0;
  int searched_num_ = 0;
  TextureGate gate_;  ///< stereo.min_texture_snr, over the matcher's window
  cv::Size window_;   ///< the matcher's window (block, or c2f's census window)
  int left_pad_ = 0;  ///< stereo.match_left_border: columns of zeros left of both images
  cv::Mat padded_left_, padded_right_, padded_disparity_;  ///< reused per frame
};

}  // namespace hazmap
