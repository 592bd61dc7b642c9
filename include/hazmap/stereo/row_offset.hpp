#pragma once
// The vertical offset left between the rows of a rectified pair, measured from feature
// matches: a calibration whose rectified rows disagree by a pixel or two costs a block
// matcher much of its density (it compares the wrong rows), and no chessboard is needed
// to see it. ORB features are matched across the pair (mutual best Hamming match); the
// matches a horizontal-epipolar pair could give (non-negative disparity, row difference
// within the search) are refined to sub-pixel by normalised cross-correlation of a patch
// around each feature, and the row differences y_left - y_right are then scored against
// a constant-offset model by exhaustive consensus (the most matches within `inlier_px` of
// one value: RANSAC with every hypothesis tried). The estimate is the median of the
// inliers' differences, its spread their robust standard deviation (1.4826 MAD).
// Sign: a positive offset means a feature lies lower (larger row) in the left image.

#include <opencv2/core.hpp>

namespace hazmap {

struct RowOffsetOptions {
  int max_features = 4000;   ///< ORB features per image
  double max_offset_px = 8;  ///< row differences beyond this are not matches of the pair
  double inlier_px = 1.0;    ///< consensus half-width around the offset
  int patch_radius_px = 7;   ///< refinement patch: (2 r + 1)^2 pixels
  int min_inliers = 20;      ///< fewer: no estimate (found = false)
};

struct RowOffsetEstimate {
  bool found = false;
  int matches = 0;           ///< mutual matches within the epipolar band
  int inliers = 0;           ///< of those, consistent with one offset
  double offset_px = 0.0;    ///< median of y_left - y_right over the inliers
  double spread_px = 0.0;    ///< 1.4826 x median absolute deviation of the inliers
};

/// Estimates y_left - y_right of a rectified pair (8-bit grey, same size).
/// Throws Error on images of another type or of different sizes.
RowOffsetEstimate estimate_row_offset(const cv::Mat& left, const cv::Mat& right,
                                      const RowOffsetOptions& options = {});

}  // namespace hazmap
