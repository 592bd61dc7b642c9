#include "hazmap/stereo/band_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "hazmap/core/error.hpp"
#include "hazmap/stereo/disparity.hpp"
#include "stereo/parallel_strips.hpp"

namespace hazmap {
namespace {

constexpr int kDisparityQuantum = 16;  // StereoBM / SGBM need num_disparities % 16 == 0

int floor_to_quantum(double d) {
  return kDisparityQuantum * static_cast<int>(std::floor(d / kDisparityQuantum));
}
int ceil_to_quantum(double d) {
  return kDisparityQuantum * static_cast<int>(std::ceil(d / kDisparityQuantum));
}

DisparityInterval hull_of(const std::vector<DisparityInterval>& rows, int row0, int row1) {
  DisparityInterval hull;
  for (int v = row0; v < row1; ++v) hull.include(rows[static_cast<std::size_t>(v)]);
  return hull;
}

/// Matching work of a strip: rows matched (with the margins that exist) x disparities.
double strip_work(const BandStrip& s, int rows, int margin) {
  if (s.num_disparities == 0) return 0.0;
  const int matched = s.row1 - s.row0 + std::min(margin, s.row0) + std::min(margin, rows - s.row1);
  return static_cast<double>(matched) * s.num_disparities;
}

}  // namespace

BandStrip band_range(const DisparityInterval& hull, int min_disparity, int cap_disparity) {
  BandStrip s;
  if (hull.empty()) return s;
  // The sub-pixel fit of disparity d needs candidates floor(d) - 1 .. ceil(d) + 1, and a
  // fit is only made off the range's first and last candidate.
  const int lo = std::max(min_disparity, floor_to_quantum(std::max(0.0, std::floor(hull.lo) - 1)));
  const int end = std::min(cap_disparity, ceil_to_quantum(std::ceil(hull.hi) + 2));
  if (end <= lo) return s;
  int num = ceil_to_quantum(end - lo);
  if (lo + num > cap_disparity) num -= kDisparityQuantum;  // min_disparity off the grid
  if (num <= 0) return s;
  s.min_disparity = lo;
  s.num_disparities = num;
  return s;
}

std::vector<BandStrip> plan_band_strips(const std::vector<DisparityInterval>& rows,
                                        int min_disparity, int cap_disparity, int margin_rows,
                                        int pieces) {
  const int n = static_cast<int>(rows.size());
  if (n == 0) return {};
  auto strip_for = [&](int row0, int row1) {
    BandStrip s = band_range(hull_of(rows, row0, row1), min_disparity, cap_disparity);
    s.row0 = row0;
    s.row1 = row1;
    return s;
  };
  // best[j]: least work for rows [0, j); from[j]: where its last strip starts.
  std::vector<double> best(static_cast<std::size_t>(n) + 1,
                           std::numeric_limits<double>::infinity());
  std::vector<int> from(static_cast<std::size_t>(n) + 1, 0);
  best[0] = 0.0;
  for (int j = 1; j <= n; ++j) {
    DisparityInterval hull;
    for (int i = j - 1; i >= 0; --i) {
      hull.include(rows[static_cast<std::size_t>(i)]);
      BandStrip s = band_range(hull, min_disparity, cap_disparity);
      s.row0 = i;
      s.row1 = j;
      const double work = best[static_cast<std::size_t>(i)] + strip_work(s, n, margin_rows);
      if (work < best[static_cast<std::size_t>(j)]) {
        best[static_cast<std::size_t>(j)] = work;
        from[static_cast<std::size_t>(j)] = i;
      }
    }
  }
  std::vector<BandStrip> strips;
  for (int j = n; j > 0; j = from[static_cast<std::size_t>(j)])
    strips.push_back(strip_for(from[static_cast<std::size_t>(j)], j));
  std::reverse(strips.begin(), strips.end());

  // Cut heavy strips so that the pool has pieces to balance; each part gets the range of
  // its own rows, which can only be narrower.
  const double total = best[static_cast<std::size_t>(n)];
  const double target = total / std::max(1, pieces);
  std::vector<BandStrip> out;
  for (const BandStrip& s : strips) {
    const double work = strip_work(s, n, margin_rows);
    const int height = s.row1 - s.row0;
    const int parts =
        target > 0 ? std::min(height, static_cast<int>(std::ceil(work / target - 1e-9))) : 1;
    if (parts <= 1) {
      out.push_back(s);
      continue;
    }
    for (int k = 0; k < parts; ++k)
      out.push_back(strip_for(s.row0 + height * k / parts, s.row0 + height * (k + 1) / parts));
  }
  return out;
}

std::string describe_strips(const std::vector<BandStrip>& strips) {
  std::string s = std::to_string(strips.size()) + " strips:";
  for (std::size_t i = 0; i < strips.size(); ++i) {
    const BandStrip& b = strips[i];
    s += (i ? ", rows " : " rows ") + std::to_string(b.row0) + "-" + std::to_string(b.row1);
    s += b.num_disparities == 0 ? " none"
                                : " d [" + std::to_string(b.min_disparity) + ", " +
                                      std::to_string(b.min_disparity + b.num_disparities) + ")";
  }
  return s;
}

BandMatcher::BandMatcher(const StereoConfig& config, const GroundBand& band, cv::Size image_size)
    : config_(config), size_(image_size) {
  check(image_size.width > 0 && image_size.height > 0, "ground band: empty image size");
  // Rows a matched row depends on: the block's half height plus the pre-filter's (the
  // normalized response box, or the 3 x 3 Sobel / SGBM's 3 x 3 pre-filter).
  const int prefilter_radius =
      config.matcher == StereoMatcher::bm && config.pre_filter_type == PreFilterType::normalized_response
          ? config.pre_filter_size / 2
          : 1;
  margin_ = config.block_size / 2 + prefilter_radius;
  const int cap = static_cast<int>(band.max_disparity());
  check(cap % kDisparityQuantum == 0, "ground band: the disparity cap must be a multiple of 16");
  plan_ = plan_band_strips(band.rows(image_size), config.min_disparity, cap, margin_,
                           stereo_detail::frame_strips());
  min_searched_ = std::numeric_limits<int>::max();
  end_searched_ = 0;
  std::vector<double> work;
  for (const BandStrip& s : plan_) {
    Strip strip;
    strip.in0 = std::max(0, s.row0 - margin_);
    strip.in1 = std::min(size_.height, s.row1 + margin_);
    if (s.num_disparities > 0) {
      // Speckles are filtered once on the whole image (compute), as a full search does.
      strip.matcher = create_stereo_matcher(config, s.min_disparity, s.num_disparities, false);
      strip.out.create(strip.in1 - strip.in0, size_.width, CV_16S);
      min_searched_ = std::min(min_searched_, s.min_disparity);
      end_searched_ = std::max(end_searched_, s.min_disparity + s.num_disparities);
    }
    strips_.push_back(std::move(strip));
    work.push_back(strip_work(s, size_.height, margin_));
  }
  if (end_searched_ == 0) min_searched_ = config.min_disparity;
  order_.resize(plan_.size());
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  std::stable_sort(order_.begin(), order_.end(),
                   [&](std::size_t a, std::size_t b) { return work[a] > work[b]; });
}

void BandMatcher::run_strip(std::size_t i, const cv::Mat& left, const cv::Mat& right,
                            cv::Mat& disparity) {
  const BandStrip& s = plan_[i];
  Strip& strip = strips_[i];
  const int16_t invalid = static_cast<int16_t>(16 * (config_.min_disparity - 1));
  if (s.num_disparities == 0) {
    disparity.rowRange(s.row0, s.row1).setTo(cv::Scalar::all(invalid));
    return;
  }
  strip.matcher->compute(left.rowRange(strip.in0, strip.in1), right.rowRange(strip.in0, strip.in1),
                         strip.out);
  // Only values strictly between the band's first and last candidate are estimates.
  const int first = 16 * s.min_disparity, last = 16 * (s.min_disparity + s.num_disparities - 1);
  for (int v = s.row0; v < s.row1; ++v) {
    const int16_t* in = strip.out.ptr<int16_t>(v - strip.in0);
    int16_t* out = disparity.ptr<int16_t>(v);
    for (int u = 0; u < size_.width; ++u) out[u] = in[u] > first && in[u] < last ? in[u] : invalid;
  }
}

void BandMatcher::compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16) {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1)
    throw Error("disparity: expected 8-bit grey rectified images");
  if (left.size() != size_ || right.size() != size_)
    throw Error("disparity: images differ from the calibrated size");
  disparity_x16.create(size_, CV_16S);
  cv::parallel_for_(cv::Range(0, static_cast<int>(order_.size())), [&](const cv::Range& r) {
    for (int k = r.start; k < r.end; ++k)
      run_strip(order_[static_cast<std::size_t>(k)], left, right, disparity_x16);
  });
  if (config_.speckle_window > 0) {
    // StereoBM compares fixed-point values, SGBM scales the range itself: either way
    // the filter sees 16 x speckle_range (SPEC 3.2).
    speckle_.apply(disparity_x16, 16 * (config_.min_disparity - 1), config_.speckle_window,
                   16 * config_.speckle_range);
  }
}

}  // namespace hazmap
