#include "hazmap/stereo/disparity.hpp"

#include <algorithm>
#include <cmath>

#include "hazmap/core/error.hpp"
#include "hazmap/stereo/band_matcher.hpp"
#include "hazmap/stereo/c2f_matcher.hpp"
#include "hazmap/stereo/ground_band.hpp"

namespace hazmap {

cv::Ptr<cv::StereoMatcher> create_stereo_matcher(const StereoConfig& c, int min_disparity,
                                                 int num_disparities, bool speckle_filter) {
  const int speckle_window = speckle_filter ? c.speckle_window : 0;
  if (c.matcher == StereoMatcher::c2f)
    throw Error("config: key 'stereo.matcher': c2f is not an OpenCV matcher (it needs the "
                "rectified geometry and stereo.search: full)");
  if (c.matcher == StereoMatcher::bm) {
    auto bm = cv::StereoBM::create(num_disparities, c.block_size);
    bm->setMinDisparity(min_disparity);
    bm->setUniquenessRatio(c.uniqueness_ratio);
    bm->setTextureThreshold(c.texture_threshold);
    bm->setPreFilterType(c.pre_filter_type == PreFilterType::xsobel
                             ? cv::StereoBM::PREFILTER_XSOBEL
                             : cv::StereoBM::PREFILTER_NORMALIZED_RESPONSE);
    bm->setPreFilterSize(c.pre_filter_size);
    bm->setPreFilterCap(c.pre_filter_cap);
    bm->setSpeckleWindowSize(speckle_window);
    // StereoBM compares fixed-point values in its speckle filter, SGBM scales itself.
    bm->setSpeckleRange(16 * c.speckle_range);
    bm->setDisp12MaxDiff(c.disp12_max_diff);
    return bm;
  }
  {
    const int area = c.block_size * c.block_size;
    int mode = cv::StereoSGBM::MODE_HH;
    switch (c.sgbm_mode) {
      case SgbmMode::sgbm: mode = cv::StereoSGBM::MODE_SGBM; break;
      case SgbmMode::hh: mode = cv::StereoSGBM::MODE_HH; break;
      case SgbmMode::sgbm_3way: mode = cv::StereoSGBM::MODE_SGBM_3WAY; break;
      case SgbmMode::hh4: mode = cv::StereoSGBM::MODE_HH4; break;
    }
    return cv::StereoSGBM::create(min_disparity, num_disparities, c.block_size,
                                  c.sgbm_p1.value_or(8 * area),
                                  c.sgbm_p2.value_or(32 * area), c.disp12_max_diff,
                                  c.pre_filter_cap, c.uniqueness_ratio, speckle_window,
                                  c.speckle_range, mode);
  }
}

int band_disparity_cap(const StereoConfig& config, const StereoGeometry& geometry, int width) {
  constexpr int kQuantum = 16;
  const double nearest = geometry.focal_px * geometry.baseline_m / config.z_min_m + 2;
  const int physical = kQuantum * static_cast<int>(std::ceil(nearest / kQuantum));
  const int image = kQuantum * ((width - config.block_size + 1) / kQuantum);
  return std::min(physical, image);
}

int c2f_disparity_end(const StereoConfig& c, const StereoGeometry& geometry, int width) {
  const double nearest = geometry.focal_px * geometry.baseline_m / c.z_min_m + 2;
  const long long end = std::min<long long>(static_cast<long long>(c.min_disparity) + c.num_disparities,
                                            static_cast<long long>(std::ceil(nearest)));
  return static_cast<int>(std::min<long long>(end, width));
}

namespace {

/// The window a matcher compares: c2f's census window, else the block.
cv::Size matcher_window(const StereoConfig& c) {
  return c.matcher == StereoMatcher::c2f ? cv::Size(c.c2f.census_width, c.c2f.census_height)
                                         : cv::Size(c.block_size, c.block_size);
}

}  // namespace

DisparityMatcher::DisparityMatcher(const StereoConfig& c)
    : matcher_(create_stereo_matcher(c, c.min_disparity, c.num_disparities, true)),
      min_disparity_(c.min_disparity),
      searched_min_(c.min_disparity),
      searched_num_(c.num_disparities),
      gate_(c.min_texture_snr, matcher_window(c)), window_(matcher_window(c)) {
  if (c.match_left_border) left_pad_ = c.min_disparity + c.num_disparities;
  if (c.search != DisparitySearch::full)
    throw Error("config: key 'stereo.search': '" + std::string(enum_name(c.search)) +
                "' needs the camera geometry; this matcher only does a full search");
}

void check_against_image(const StereoConfig& c, cv::Size image) {
  const std::string size = std::to_string(image.width) + "x" + std::to_string(image.height);
  // Disparities beyond the image width match nothing; OpenCV would still size its cost
  // buffers from them (1048576 disparities: gigabytes, then "Insufficient memory").
  if (static_cast<long long>(c.min_disparity) + c.num_disparities > image.width)
    throw Error("config: key 'stereo.num_disparities': min_disparity + num_disparities = " +
                std::to_string(static_cast<long long>(c.min_disparity) + c.num_disparities) +
                " exceeds the " + size + " image's width (no match can be that far)");
  const auto& r = c.roi_px;
  if (r[2] > 0 && r[3] > 0 &&
      (static_cast<long long>(r[0]) + r[2] > image.width ||
       static_cast<long long>(r[1]) + r[3] > image.height))
    throw Error("config: key 'stereo.roi': [" + std::to_string(r[0]) + ", " +
                std::to_string(r[1]) + ", " + std::to_string(r[2]) + ", " + std::to_string(r[3]) +
                "] reaches outside the " + size + " image");
}

DisparityMatcher::DisparityMatcher(const StereoConfig& c, const StereoGeometry& geometry,
                                   const Pose3d& T_B_Cr, cv::Size image_size)
    : min_disparity_(c.min_disparity), searched_min_(c.min_disparity),
      searched_num_(c.num_disparities), gate_(c.min_texture_snr, matcher_window(c)),
      window_(matcher_window(c)) {
  check_against_image(c, image_size);
  if (c.matcher == StereoMatcher::c2f) {
    if (c.search != DisparitySearch::full)
      throw Error("config: key 'stereo.search': ground_band works with bm and sgbm; c2f "
                  "narrows its own search (stereo.c2f.*)");
    const int end = c2f_disparity_end(c, geometry, image_size.width);
    c2f_ = std::make_unique<C2fMatcher>(c.c2f, c.min_disparity, end, image_size,
                                        c.speckle_window, c.speckle_range);
    searched_num_ = end - c.min_disparity;
    return;
  }
  if (c.match_left_border) left_pad_ = c.min_disparity + c.num_disparities;
  if (c.search == DisparitySearch::full) {
    matcher_ = create_stereo_matcher(c, c.min_disparity, c.num_disparities, true);
    return;
  }
  const int cap = band_disparity_cap(c, geometry, image_size.width);
  if (cap <= c.min_disparity)
    throw Error("config: key 'stereo.search': ground_band leaves no disparity to search "
                "(image too narrow or stereo.min_disparity too large)");
  const GroundBand band(geometry, T_B_Cr, TerrainEnvelope::from(c), cap);
  if (c.match_left_border) left_pad_ = cap;
  band_ = std::make_unique<BandMatcher>(
      c, band, cv::Size(image_size.width + left_pad_, image_size.height));
  searched_min_ = band_->min_searched();
  searched_num_ = std::max(16, band_->end_searched() - band_->min_searched());
}

std::vector<int> DisparityMatcher::search_end_by_row(int rows) const {
  std::vector<int> end(static_cast<size_t>(std::max(rows, 0)), searched_min_ + searched_num_);
  if (band_) {
    std::fill(end.begin(), end.end(), 0);
    for (const BandStrip& s : band_->strips())
      for (int v = std::max(s.row0, 0); v < std::min(s.row1, rows); ++v)
        end[static_cast<size_t>(v)] = s.num_disparities > 0 ? s.min_disparity + s.num_disparities : 0;
  }
  return end;
}

DisparityMatcher::~DisparityMatcher() = default;
DisparityMatcher::DisparityMatcher(DisparityMatcher&&) noexcept = default;
DisparityMatcher& DisparityMatcher::operator=(DisparityMatcher&&) noexcept = default;

void DisparityMatcher::drop_matches_into_padding(cv::Mat& disparity_x16) const {
  // A left pixel whose true match lies within a window of the right image's edge cannot be
  // matched: its window's partner reaches the zeros, and the matcher settles on a smaller
  // disparity, a point too far away (on the unseen ramps 35 % of the pixels within 5 px
  // of that edge, 0.01 % elsewhere). Its true disparity is unknown, but along a row the
  // surface's disparity is near its neighbours': column x keeps a disparity only when no
  // column from x up to a window past the padded band has a disparity that would put
  // the right window closer to the edge than one window width (a whole window to spare).
  const int width = window_.width;
  const short invalid = static_cast<short>(16 * (min_disparity_ - 1));
  const int last = std::min(left_pad_ + width, disparity_x16.cols);
  for (int r = 0; r < disparity_x16.rows; ++r) {
    auto* row = disparity_x16.ptr<short>(r);
    int nearest = 0;  // the largest valid disparity x16 seen from `last` down to x
    for (int x = last - 1; x >= 0; --x) {
      nearest = std::max(nearest, static_cast<int>(row[x]));
      if (x >= left_pad_) continue;
      if (row[x] > invalid && nearest > 16 * (x - width)) row[x] = invalid;
    }
  }
}

void DisparityMatcher::compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16) {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1)
    throw Error("disparity: expected 8-bit grey rectified images");
  if (left.size() != right.size())
    throw Error("disparity: left and right images differ in size");
  if (c2f_) {
    c2f_->compute(left, right, disparity_x16);
  } else {
    // OpenCV blanks every column whose full range would leave the right image. Zeros on
    // the left of both images let those columns search what the right image holds; what
    // could only have matched the zeros is dropped after the crop.
    const bool pad = left_pad_ > 0;
    if (pad) {
      cv::copyMakeBorder(left, padded_left_, 0, 0, left_pad_, 0, cv::BORDER_CONSTANT, 0);
      cv::copyMakeBorder(right, padded_right_, 0, 0, left_pad_, 0, cv::BORDER_CONSTANT, 0);
    }
    const cv::Mat& l = pad ? padded_left_ : left;
    const cv::Mat& r = pad ? padded_right_ : right;
    cv::Mat& out = pad ? padded_disparity_ : disparity_x16;
    if (band_)
      band_->compute(l, r, out);
    else
      matcher_->compute(l, r, out);
    if (pad) {
      padded_disparity_.colRange(left_pad_, padded_disparity_.cols).copyTo(disparity_x16);
      drop_matches_into_padding(disparity_x16);
    }
  }
  if (gate_.enabled()) gate_.apply(left, disparity_x16, static_cast<short>(invalid_below()));
}

}  // namespace hazmap
