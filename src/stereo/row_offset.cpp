#include "hazmap/stereo/row_offset.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

// Patch matches below this normalised correlation are not the same surface.
constexpr double kMinCorrelation = 0.8;
// Search half-width of the patch refinement around the predicted position [px]; ORB
// keypoints found on coarse pyramid levels are a pixel or two off at full resolution.
constexpr int kSearchPx = 3;

struct FeatureMatch {
  cv::Point left;       ///< integer position of the left feature (the patch centre)
  cv::Point2f right;    ///< where it was found in the right image
};

double median_of(std::vector<double> v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

/// Vertex of the parabola through (-1, a), (0, b), (1, c), in [-0.5, 0.5].
double parabola_peak(double a, double b, double c) {
  const double denom = a - 2.0 * b + c;
  if (!(denom < 0.0)) return 0.0;
  return std::clamp(0.5 * (a - c) / denom, -0.5, 0.5);
}

/// The sub-pixel position in `right` of the patch of `left` around m.left, searched within
/// kSearchPx of `guess`; false when the patch leaves an image, the peak lies on the search
/// border or correlates weakly.
bool refine(const cv::Mat& left, const cv::Mat& right, cv::Point l, cv::Point guess, int r,
            cv::Point2f& found, cv::Mat& score) {
  const int s = kSearchPx;
  const cv::Rect tpl(l.x - r, l.y - r, 2 * r + 1, 2 * r + 1);
  const cv::Rect area(guess.x - r - s, guess.y - r - s, 2 * (r + s) + 1, 2 * (r + s) + 1);
  const cv::Rect whole(0, 0, left.cols, left.rows);
  if ((tpl & whole) != tpl || (area & whole) != area) return false;
  cv::matchTemplate(right(area), left(tpl), score, cv::TM_CCOEFF_NORMED);
  double best = 0;
  cv::Point at;
  cv::minMaxLoc(score, nullptr, &best, nullptr, &at);
  if (!(best >= kMinCorrelation) || at.x == 0 || at.y == 0 || at.x == score.cols - 1 ||
      at.y == score.rows - 1)
    return false;
  const auto v = [&](int y, int x) { return static_cast<double>(score.at<float>(y, x)); };
  const double dx = parabola_peak(v(at.y, at.x - 1), v(at.y, at.x), v(at.y, at.x + 1));
  const double dy = parabola_peak(v(at.y - 1, at.x), v(at.y, at.x), v(at.y + 1, at.x));
  found = cv::Point2f(static_cast<float>(guess.x - s + at.x + dx),
                      static_cast<float>(guess.y - s + at.y + dy));
  return true;
}

/// The largest set of values within `half_width` of one value (exhaustive consensus on
/// a constant model), as indices into `v`.
std::vector<std::size_t> consensus(const std::vector<double>& v, double half_width) {
  std::vector<std::size_t> order(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::size_t best_begin = 0, best_end = 0;
  for (std::size_t i = 0, j = 0; i < order.size(); ++i) {
    while (j < order.size() && v[order[j]] - v[order[i]] <= 2.0 * half_width) ++j;
    if (j - i > best_end - best_begin) best_begin = i, best_end = j;
  }
  std::vector<double> window;
  for (std::size_t k = best_begin; k < best_end; ++k) window.push_back(v[order[k]]);
  if (window.empty()) return {};
  const double centre = median_of(window);
  std::vector<std::size_t> inliers;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::abs(v[i] - centre) <= half_width) inliers.push_back(i);
  return inliers;
}

}  // namespace

RowOffsetEstimate estimate_row_offset(const cv::Mat& left, const cv::Mat& right,
                                      const RowOffsetOptions& o) {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != right.size())
    throw Error("row offset: expected two 8-bit grey images of one size");
  RowOffsetEstimate out;
  const cv::Ptr<cv::ORB> orb = cv::ORB::create(o.max_features);
  std::vector<cv::KeyPoint> kl, kr;
  cv::Mat dl, dr;
  orb->detectAndCompute(left, cv::noArray(), kl, dl);
  orb->detectAndCompute(right, cv::noArray(), kr, dr);
  if (kl.empty() || kr.empty()) return out;

  // Guided matching: only pairs a horizontal-epipolar pair can give (the right feature
  // not right of the left one, rows within max_offset_px), each the other's best.
  cv::Mat allowed(static_cast<int>(kl.size()), static_cast<int>(kr.size()), CV_8UC1);
  for (int i = 0; i < allowed.rows; ++i) {
    uchar* row = allowed.ptr<uchar>(i);
    const cv::Point2f p = kl[static_cast<std::size_t>(i)].pt;
    for (int j = 0; j < allowed.cols; ++j) {
      const cv::Point2f q = kr[static_cast<std::size_t>(j)].pt;
      row[j] = (std::abs(p.y - q.y) <= o.max_offset_px && p.x - q.x >= -o.max_offset_px) ? 1 : 0;
    }
  }
  // OpenCV's cross check takes no mask: both directions, kept where they agree.
  std::vector<cv::DMatch> forward, backward, raw;
  const cv::BFMatcher matcher(cv::NORM_HAMMING);
  matcher.match(dl, dr, forward, allowed);
  matcher.match(dr, dl, backward, cv::Mat(allowed.t()));
  std::vector<int> back_of(kr.size(), -1);
  for (const cv::DMatch& m : backward) back_of[static_cast<std::size_t>(m.queryIdx)] = m.trainIdx;
  for (const cv::DMatch& m : forward)
    if (back_of[static_cast<std::size_t>(m.trainIdx)] == m.queryIdx) raw.push_back(m);

  // Pass 1: each match refined to sub-pixel by patch correlation.
  const int r = o.patch_radius_px;
  std::vector<FeatureMatch> matches;
  std::vector<double> dy;
  cv::Mat score;
  for (const cv::DMatch& m : raw) {
    const cv::Point2f p = kl[static_cast<std::size_t>(m.queryIdx)].pt;
    const cv::Point2f q = kr[static_cast<std::size_t>(m.trainIdx)].pt;
    FeatureMatch f{cv::Point(cvRound(p.x), cvRound(p.y)), {}};
    if (!refine(left, right, f.left, cv::Point(cvRound(q.x), cvRound(q.y)), r, f.right, score))
      continue;
    if (std::abs(f.left.y - static_cast<double>(f.right.y)) > o.max_offset_px) continue;
    matches.push_back(f);
    dy.push_back(f.left.y - static_cast<double>(f.right.y));
  }
  out.matches = static_cast<int>(matches.size());
  std::vector<std::size_t> in = consensus(dy, o.inlier_px);
  if (static_cast<int>(in.size()) < o.min_inliers) {
    out.inliers = static_cast<int>(in.size());
    return out;
  }
  std::vector<double> kept;
  for (std::size_t i : in) kept.push_back(dy[i]);
  const double first = median_of(kept);

  // Pass 2: parabola peaks lean towards whole pixels, the same way for every match of a
  // constant offset, so the bias does not average out. The right image shifted by the
  // first estimate leaves a residual near zero, where that bias vanishes.
  cv::Mat shifted;
  const cv::Matx23d shift(1, 0, 0, 0, 1, first);
  cv::warpAffine(right, shifted, shift, right.size(), cv::INTER_CUBIC, cv::BORDER_REPLICATE);
  std::vector<double> final_dy;
  for (std::size_t i : in) {
    const FeatureMatch& f = matches[i];
    cv::Point2f found;
    if (!refine(left, shifted, f.left, cv::Point(cvRound(f.right.x), f.left.y), r, found, score))
      continue;
    final_dy.push_back(first + (f.left.y - static_cast<double>(found.y)));
  }
  in = consensus(final_dy, o.inlier_px);
  out.inliers = static_cast<int>(in.size());
  if (out.inliers < o.min_inliers) return out;
  kept.clear();
  for (std::size_t i : in) kept.push_back(final_dy[i]);
  out.offset_px = median_of(kept);
  std::vector<double> deviation;
  for (double v : kept) deviation.push_back(std::abs(v - out.offset_px));
  out.spread_px = 1.4826 * median_of(deviation);
  out.found = true;
  return out;
}

}  // namespace hazmap
