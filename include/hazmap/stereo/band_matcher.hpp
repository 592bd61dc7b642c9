#pragma once
// Ground-band matching (SPEC 3.4, `stereo.search: ground_band`): the rectified pair is
// cut into horizontal strips, each strip is matched by its own cv::StereoBM / StereoSGBM
// over only the disparities terrain can produce in its rows (ground_band.hpp), and the
// strips run in parallel on OpenCV's thread pool (a matcher called inside it runs
// serially, so each strip keeps one core busy).
//
// Equality with a full search (StereoBM): every strip is matched on its rows plus
// `margin_rows()` rows above and below (block radius + pre-filter radius), so each output
// row sees exactly the pre-filtered pixels and matching windows a full search sees; the
// speckle filter runs once on the assembled image, as StereoBM runs it once on its own.
// A pixel whose full-search disparity lies strictly inside its strip's band then gets
// the same value. What can differ, all at the band's edges: a best match on the band's
// first or last candidate (no sub-pixel fit; invalid here, see below), the uniqueness
// check and OpenCV's left-right check (fewer competing candidates), and speckle regions
// that touch pixels whose disparity lies outside the band. StereoSGBM aggregates costs
// along paths across the whole image, so its strips restart those paths: close to, but
// not the same as, a full search.
//
// Band per strip: the hull of its rows' intervals, widened by one disparity below and two
// above (the sub-pixel fit of the extreme disparities needs their integer neighbours),
// rounded out to multiples of 16 and clamped to [stereo.min_disparity, cap], with the cap
// from DisparityMatcher (stereo.z_min and the image width). Not limited by
// stereo.num_disparities: near rows search as far as the ground there needs.
// Invalid: pixels outside every band, the left columns u < band max + block / 2 (as
// StereoBM marks them in a full search), and a best match on a band's first or last
// candidate (the true minimum may lie outside the band). Invalid pixels hold
// 16 (stereo.min_disparity - 1), as a full search's do.
//
// Buffers (strip images, matcher state, speckle buffer) are allocated once; a frame
// allocates nothing beyond what the OpenCV matchers allocate on their first call.
// Not thread-safe: one BandMatcher per thread.

#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "hazmap/stereo/ground_band.hpp"
#include "hazmap/stereo/speckle_filter.hpp"
#include "hazmap/stereo/stereo_config.hpp"

namespace hazmap {

/// One strip: output rows [row0, row1) search [min_disparity, min_disparity +
/// num_disparities); num_disparities 0 means nothing to search (all invalid).
struct BandStrip {
  int row0 = 0;
  int row1 = 0;
  int min_disparity = 0;
  int num_disparities = 0;
};

/// Per-strip search ranges for rows with the given intervals: each strip's range as
/// described above (min_disparity, cap_disparity: the clamp; cap a multiple of 16).
/// Strip boundaries minimise the matching work sum (rows + margins) x num_disparities
/// (dynamic programming over row boundaries), then strips are cut into equal parts until
/// none carries more than 1 / `pieces` of the total, so that the thread pool can balance
/// them. Strips cover all rows in order.
std::vector<BandStrip> plan_band_strips(const std::vector<DisparityInterval>& rows,
                                        int min_disparity, int cap_disparity, int margin_rows,
                                        int pieces);

/// The search range a strip with this interval hull gets (num_disparities 0 if empty).
BandStrip band_range(const DisparityInterval& hull, int min_disparity, int cap_disparity);

/// One line for logs: "7 strips: rows 0-67 d [0, 32), rows 67-168 d [0, 64), ...".
std::string describe_strips(const std::vector<BandStrip>& strips);

class BandMatcher {
 public:
  /// `band`: the camera's terrain band; `image_size`: of the rectified pair. Throws Error
  /// for an unknown matcher, mode or pre-filter (as DisparityMatcher).
  BandMatcher(const StereoConfig& config, const GroundBand& band, cv::Size image_size);

  /// Rectified 8-bit grey images of image_size in, fixed-point disparity out (CV_16S,
  /// x16; `disparity_x16` reused). Throws Error for other types or sizes.
  void compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16);

  const std::vector<BandStrip>& strips() const { return plan_; }
  int margin_rows() const { return margin_; }
  /// Lowest and one past the highest disparity any strip searches.
  int min_searched() const { return min_searched_; }
  int end_searched() const { return end_searched_; }

 private:
  struct Strip {
    int in0 = 0, in1 = 0;  ///< input rows matched: the strip's rows plus margins
    cv::Ptr<cv::StereoMatcher> matcher;
    cv::Mat out;  ///< matcher output, (in1 - in0) x width
  };
  void run_strip(std::size_t i, const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity);

  StereoConfig config_;
  cv::Size size_;
  int margin_ = 0;
  int min_searched_ = 0;
  int end_searched_ = 0;
  std::vector<BandStrip> plan_;
  std::vector<Strip> strips_;
  std::vector<std::size_t> order_;  ///< strips by decreasing work: longest first
  SpeckleFilter speckle_;
};

}  // namespace hazmap
