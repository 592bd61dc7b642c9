#include "hazmap/stereo/disparity.hpp"

#include "hazmap/core/error.hpp"

namespace hazmap {

DisparityMatcher::DisparityMatcher(const StereoConfig& c)
    : min_disparity_(c.min_disparity), num_disparities_(c.num_disparities) {
  if (c.matcher == "bm") {
    auto bm = cv::StereoBM::create(c.num_disparities, c.block_size);
    bm->setMinDisparity(c.min_disparity);
    bm->setUniquenessRatio(c.uniqueness_ratio);
    bm->setTextureThreshold(c.texture_threshold);
    if (c.pre_filter_type == "normalized_response")
      bm->setPreFilterType(cv::StereoBM::PREFILTER_NORMALIZED_RESPONSE);
    else if (c.pre_filter_type == "xsobel")
      bm->setPreFilterType(cv::StereoBM::PREFILTER_XSOBEL);
    else
      throw Error("config: key 'stereo.pre_filter_type': unknown type '" + c.pre_filter_type + "'");
    bm->setPreFilterSize(c.pre_filter_size);
    bm->setPreFilterCap(c.pre_filter_cap);
    bm->setSpeckleWindowSize(c.speckle_window);
    // StereoBM compares fixed-point values in its speckle filter, SGBM scales itself.
    bm->setSpeckleRange(16 * c.speckle_range);
    bm->setDisp12MaxDiff(c.disp12_max_diff);
    matcher_ = bm;
  } else if (c.matcher == "sgbm") {
    const int area = c.block_size * c.block_size;
    int mode = 0;
    if (c.sgbm_mode == "sgbm") mode = cv::StereoSGBM::MODE_SGBM;
    else if (c.sgbm_mode == "hh") mode = cv::StereoSGBM::MODE_HH;
    else if (c.sgbm_mode == "sgbm_3way") mode = cv::StereoSGBM::MODE_SGBM_3WAY;
    else if (c.sgbm_mode == "hh4") mode = cv::StereoSGBM::MODE_HH4;
    else throw Error("config: key 'stereo.sgbm_mode': unknown mode '" + c.sgbm_mode + "'");
    matcher_ = cv::StereoSGBM::create(c.min_disparity, c.num_disparities, c.block_size,
                                      c.sgbm_p1 > 0 ? c.sgbm_p1 : 8 * area,
                                      c.sgbm_p2 > 0 ? c.sgbm_p2 : 32 * area, c.disp12_max_diff,
                                      c.pre_filter_cap, c.uniqueness_ratio, c.speckle_window,
                                      c.speckle_range, mode);
  } else {
    throw Error("config: key 'stereo.matcher': unknown matcher '" + c.matcher + "'");
  }
}

void DisparityMatcher::compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16) {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1)
    throw Error("disparity: expected 8-bit grey rectified images");
  if (left.size() != right.size())
    throw Error("disparity: left and right images differ in size");
  matcher_->compute(left, right, disparity_x16);
}

}  // namespace hazmap
