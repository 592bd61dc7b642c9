#pragma once
// The speckle filter (SPEC 3.2): a blob of disparities that agree with their neighbours
// (4-connected, |difference| <= max_diff) but covers at most max_size pixels is a
// mismatch, set invalid. Equal, pixel for pixel, to cv::filterSpeckles, which runs on one
// core (a tenth of the c2f stage at full CADRE resolution): here row strips are labelled in
// parallel (union-find), joined across strip borders, then cleared in parallel.

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace hazmap {

class SpeckleFilter {
 public:
  /// Sets to `invalid` every pixel of `disparity` (CV_16S) whose component has at most
  /// `max_size` pixels; pixels already `invalid` belong to none. Buffers are kept: no
  /// allocation after the first image of a given size. Throws Error on another type.
  void apply(cv::Mat& disparity, int invalid, int max_size, int max_diff);

 private:
  std::vector<int> parent_;    ///< per pixel: its strip's root, then (roots) the joined root
  std::vector<int> count_;     ///< per strip root: its pixels in the strip
  std::vector<int> absorbed_;  ///< strip roots joined to another across a strip border
};

}  // namespace hazmap
