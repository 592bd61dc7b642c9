#include "hazmap/stereo/c2f_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "stereo/c2f_kernels.hpp"
#include "stereo/parallel_strips.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/map/internal/simd.hpp"

namespace hazmap {

using c2f::kInf;
using c2f::kLanes;
using c2f::kPad;
using stereo_detail::parallel_range;
using stereo_detail::strip;

namespace {

using c2f::kNoSeed;

int round_up(int v, int q) { return (v + q - 1) / q * q; }

/// Index of pixel (x, y) in a level's row-major per-pixel arrays.
struct PixelIndex {
  int w;
  size_t operator()(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
  }
};

}  // namespace

struct C2fMatcher::Level {
  cv::Size size;
  int lo = 0, hi = 0;  // disparities [lo, hi) at this level
  int n = 0;           // disparities per pixel window
  int npad = 0;        // n rounded up to kLanes; kNarrow on a narrow level
  int stride = 0;      // a padded path-cost vector: kPad + npad + kPad; narrow: kNarrow
  bool full = false;   // the coarsest level: every pixel searches [lo, hi)
  bool narrow = false; // a finer level with n <= kNarrowMax: the 8-lane kernels
  cv::Mat left, right;            // CV_8U
  cv::Mat left_pad, right_pad;    // borders replicated for the census window
  std::vector<std::uint64_t> census_l, census_r;
  std::vector<std::int16_t> dmin;     // per pixel; kNoSeed: no window
  std::vector<std::uint8_t> cost;     // per pixel npad lanes
  std::vector<std::uint16_t> sum;     // per pixel npad lanes, summed over paths
  std::vector<float> disp;            // result [px of this level], < 0 invalid
  std::vector<std::int16_t> winner;   // its whole-pixel winner, for the left-right check
  std::vector<std::uint8_t> conf;     // full level: confidence x 255
  std::vector<std::uint16_t> right_s; // LR: per right pixel the lowest sum ...
  std::vector<std::int16_t> right_d;  // ... and its disparity
  std::vector<std::int16_t> state;    // column / diagonal passes: 2 rows of W padded vectors
  std::vector<int> state_min;         // 2 x W
  std::vector<std::int16_t> pad_mask; // kLanes: 0 below n % npad, kInf above
};

C2fMatcher::C2fMatcher(const C2fConfig& config, int min_disparity, int end_disparity,
                       cv::Size image, int speckle_window, int speckle_range,
                       C2fKernels kernels)
    : config_(config),
      min_disparity_(min_disparity),
      end_disparity_(end_disparity),
      speckle_window_(speckle_window),
      speckle_range_(speckle_range),
      avx2_(kernels == C2fKernels::best && c2f::avx2_available()) {
  if (end_disparity <= min_disparity + 1)
    throw Error("config: key 'stereo.num_disparities': the c2f search range [" +
                std::to_string(min_disparity) + ", " + std::to_string(end_disparity) +
                ") is empty (stereo.z_min too far or num_disparities too small)");
  if (config.radius * 2 + 1 > kLanes - 1)
    throw Error("config: key 'stereo.c2f.radius': at most " + std::to_string((kLanes - 2) / 2));
  const int bits = config.census_width * config.census_height - 1;
  if (bits > 64 || bits < 1)
    throw Error("config: key 'stereo.c2f.census_height': census_width x census_height - 1 must "
                "be in [1, 64] bits");
  const int shrink = 1 << (config.levels - 1);
  if (image.width / shrink < config.census_width || image.height / shrink < config.census_height)
    throw Error("config: key 'stereo.c2f.levels': " + std::to_string(config.levels) +
                " levels shrink the " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + " image below the census window");

  if (config.p2_edge > 0) {
    // max(p1, p2 e / (e + D)), rounded: a jump across an edge of D DN costs less.
    const int e = config.p2_edge;
    p2_of_diff_.resize(256);
    for (int d = 0; d < 256; ++d)
      p2_of_diff_[static_cast<size_t>(d)] =
          static_cast<std::int16_t>(std::max(config.p1, (config.p2 * e + (e + d) / 2) / (e + d)));
  }
  levels_.resize(static_cast<size_t>(config.levels));
  cv::Size size = image;
  for (int l = 0; l < config.levels; ++l) {
    Level& L = levels_[static_cast<size_t>(l)];
    L.size = size;
    L.full = l == config.levels - 1;
    L.lo = min_disparity >> l;
    L.hi = std::min((end_disparity + (1 << l) - 1) / (1 << l) + (L.full ? 0 : 1), size.width);
    L.n = L.full ? L.hi - L.lo : std::min(2 * config.radius + 1, L.hi - L.lo);
    if (L.n < 2)
      throw Error("config: key 'stereo.c2f.levels': level " + std::to_string(l) +
                  " has no disparities to search");
    L.narrow = !L.full && L.n <= c2f::kNarrowMax;
    L.npad = L.narrow ? c2f::kNarrow : round_up(L.n, kLanes);
    L.stride = L.narrow ? c2f::kNarrow : kPad + L.npad + kPad;
    const size_t pixels = static_cast<size_t>(size.area());
    if (l > 0) {
      L.left.create(size, CV_8UC1);
      L.right.create(size, CV_8UC1);
    }
    const int rw = config.census_width / 2, rh = config.census_height / 2;
    L.left_pad.create(size.height + 2 * rh, size.width + 2 * rw, CV_8UC1);
    L.right_pad.create(size.height + 2 * rh, size.width + 2 * rw, CV_8UC1);
    L.census_l.assign(pixels, 0);
    L.census_r.assign(pixels, 0);
    L.dmin.assign(pixels, static_cast<std::int16_t>(L.lo));
    L.cost.assign(pixels * static_cast<size_t>(L.npad), 0);
    L.sum.assign(pixels * static_cast<size_t>(L.npad), 0);
    L.disp.assign(pixels, -1.f);
    L.winner.assign(pixels, 0);
    if (L.full) L.conf.assign(pixels, 0);
    L.right_s.assign(pixels, 0);
    L.right_d.assign(pixels, 0);
    // Narrow: two padded state rows (c2f::state_at), whose padding stays kInf.
    L.state.assign(L.narrow ? 2 * c2f::state_row_lanes(size.width)
                            : 2 * static_cast<size_t>(size.width) * static_cast<size_t>(L.stride),
                   kInf);
    L.state_min.assign(2 * static_cast<size_t>(size.width), 0);
    L.pad_mask.assign(kLanes, 0);
    for (int k = L.n - (L.npad - kLanes); k < kLanes; ++k)
      L.pad_mask[static_cast<size_t>(std::max(k, 0))] = kInf;
    size = cv::Size((size.width + 1) / 2, (size.height + 1) / 2);
  }
  strips_ = stereo_detail::frame_strips();
  int widest = 0;
  for (const Level& L : levels_) widest = std::max(widest, L.stride);
  scratch_.assign(static_cast<size_t>(strips_),
                  std::vector<std::int16_t>(2 * static_cast<size_t>(widest), kInf));
  confidence_.create(image, CV_8UC1);
  pyramid_row_.assign(static_cast<size_t>(image.width) * static_cast<size_t>(strips_), 0);
  valid_by_level_.assign(levels_.size(), 0);
  if (config.outline_jump_px > 0) {
    outline_row_.assign(static_cast<size_t>(image.width), 0);
    outline_value_.assign(static_cast<size_t>(image.width), 0);
    outline_drop_.create(image, CV_8UC1);
  }
}

C2fMatcher::~C2fMatcher() = default;
C2fMatcher::C2fMatcher(C2fMatcher&&) noexcept = default;
C2fMatcher& C2fMatcher::operator=(C2fMatcher&&) noexcept = default;

namespace c2f_detail {

/// cost[k] = differing bits of `left` and right[xr0 - k], `bits` where xr0 - k < 0.
HAZMAP_KERNEL void hamming_window(std::uint64_t left, const std::uint64_t* right, int xr0, int n,
                                  int bits, std::uint8_t* cost) {
  for (int k = 0; k < n; ++k) {
    const int xr = xr0 - k;
    cost[k] = static_cast<std::uint8_t>(xr >= 0 ? __builtin_popcountll(left ^ right[xr]) : bits);
  }
}

using c2f::kNoSum;
using c2f::WinnerRow;

/// Winner takes all (the first lowest sum), the right image's lowest sums for the
/// left-right check, uniqueness and confidence (full level) or the window-edge test, the
/// parabola. Written as plain reductions the compiler vectorises.
HAZMAP_KERNEL void winners_row(const WinnerRow& r) {
  const int n = r.n;
  for (int x = 0; x < r.width; ++x) {
    r.disp[x] = -1.f;
    const int d0 = r.dmin[x];
    if (d0 == kNoSeed) continue;
    const std::uint16_t* s = r.sum + static_cast<size_t>(x) * static_cast<size_t>(r.npad);
    std::uint16_t best = kNoSum;
    for (int k = 0; k < n; ++k) best = std::min(best, s[k]);
    int kb = 0;
    while (s[kb] != best) ++kb;
    // Right pixel x - d0 - k (>= 0) keeps its first lowest sum.
    if (x - d0 < 0) continue;  // every right pixel left of the image
    offer_to_right(r, s, x, d0, n);
    if (x - d0 - kb < 0) continue;
    if (r.full) {
      std::uint16_t low = kNoSum;
      for (int k = 0; k < kb - 1; ++k) low = std::min(low, s[k]);
      for (int k = kb + 2; k < n; ++k) low = std::min(low, s[k]);
      const int second = low == kNoSum ? std::numeric_limits<int>::max() : low;
      r.conf[x] = second > 0 && second != std::numeric_limits<int>::max()
                      ? static_cast<std::uint8_t>(255 * (second - best) / second)
                      : 0;
      if (r.uniqueness > 0 && second != std::numeric_limits<int>::max() &&
          best * 100 >= (100 - r.uniqueness) * second)
        continue;
    } else if ((kb == 0 && d0 > r.lo) || (kb == n - 1 && d0 + n < r.hi)) {
      continue;  // the minimum lies outside the window: the seed was wrong
    }
    float d = static_cast<float>(d0 + kb);
    if (kb > 0 && kb < n - 1) {
      const int a = s[kb - 1], c = s[kb + 1];
      const int denom = a + c - 2 * best;
      if (denom > 0) d += static_cast<float>(a - c) / static_cast<float>(2 * denom);
    }
    r.disp[x] = d;
    r.winner[x] = static_cast<std::int16_t>(d0 + kb);
  }
}

}  // namespace c2f_detail

namespace {

/// Half size with the [1 4 6 4 1] / 16 kernel in both directions, borders reflected
/// (OpenCV's BORDER_REFLECT_101, as cv::pyrDown), rounded; `rows`: strips x src.cols ints,
/// row strips in parallel.
void pyramid_down(const cv::Mat& src, cv::Mat& dst, std::vector<int>& rows, int strips) {
  const int w = src.cols, h = src.rows;
  auto reflect = [](int i, int n) { return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i); };
  static constexpr int kTaps[5] = {1, 4, 6, 4, 1};
  parallel_range(cv::Range(0, strips), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      int* row = rows.data() + static_cast<size_t>(s) * static_cast<size_t>(w);
      const cv::Range ys = strip(dst.rows, strips, s);
      for (int y = ys.start; y < ys.end; ++y) {
        const std::uint8_t* r[5];
        for (int t = 0; t < 5; ++t) r[t] = src.ptr<std::uint8_t>(reflect(2 * y - 2 + t, h));
        for (int x = 0; x < w; ++x)
          row[x] = r[0][x] + 4 * r[1][x] + 6 * r[2][x] + 4 * r[3][x] + r[4][x];
        std::uint8_t* out = dst.ptr<std::uint8_t>(y);
        // Interior columns without reflection; the borders with it.
        const int inner_end = std::max(1, std::min(dst.cols, (w - 3) / 2 + 1));
        for (int x = 1; x < inner_end; ++x) {
          const int* c = row + 2 * x;
          const int sum = c[-2] + 4 * c[-1] + 6 * c[0] + 4 * c[1] + c[2];
          out[x] = static_cast<std::uint8_t>((sum + 128) >> 8);
        }
        auto border = [&](int x) {
          int sum = 0;
          for (int t = 0; t < 5; ++t) sum += kTaps[t] * row[reflect(2 * x - 2 + t, w)];
          out[x] = static_cast<std::uint8_t>((sum + 128) >> 8);
        };
        border(0);
        for (int x = inner_end; x < dst.cols; ++x) border(x);
      }
    }
  });
}

/// Census of every pixel of `src` (borders replicated into `pad`): bit per window pixel
/// (row-major, centre skipped), set where it is darker than the centre.
void census(const cv::Mat& src, cv::Mat& pad, int cw, int ch, bool avx2,
            std::vector<std::uint64_t>& out) {
  const int rh = ch / 2;
  cv::copyMakeBorder(src, pad, rh, rh, cw / 2, cw / 2, cv::BORDER_REPLICATE);
  const int width = src.cols;
  const auto row_kernel = avx2 ? c2f::census_row_avx2 : c2f::census_row_scalar;
  parallel_range(cv::Range(0, src.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const std::uint8_t* window[16];
      for (int i = 0; i < ch; ++i) window[i] = pad.ptr<std::uint8_t>(y + i);
      row_kernel(window, cw, ch, width,
                 out.data() + static_cast<size_t>(y) * static_cast<size_t>(width));
    }
  });
}

/// std::lround for x >= 0, without the library call.
inline int round_non_negative(float x) {
  const int whole = static_cast<int>(x);
  return whole + (x - static_cast<float>(whole) >= 0.5f ? 1 : 0);
}

}  // namespace

void C2fMatcher::seed_level(int l) {
  Level& L = levels_[static_cast<size_t>(l)];
  if (L.full) {
    std::fill(L.dmin.begin(), L.dmin.end(), static_cast<std::int16_t>(L.lo));
    return;
  }
  const Level& C = levels_[static_cast<size_t>(l + 1)];
  const int w = L.size.width, cw = C.size.width;
  const int r = config_.radius;
  const int top = L.hi - L.n;
  parallel_range(cv::Range(0, L.size.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float* coarse = C.disp.data() + static_cast<size_t>(y / 2) * static_cast<size_t>(cw);
      std::int16_t* dmin = L.dmin.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
      for (int x = 0; x < w; ++x) {
        const float d = coarse[x / 2];
        dmin[x] = d < 0 ? kNoSeed
                        : static_cast<std::int16_t>(
                              std::clamp(round_non_negative(2 * d) - r, L.lo, top));
      }
      if (!config_.fill_unseeded) continue;
      // A hole takes the smaller of the nearest windows left and right of it: occlusions
      // and untextured gaps are mostly background.
      int x = 0;
      while (x < w) {
        if (dmin[x] != kNoSeed) { ++x; continue; }
        int end = x;
        while (end < w && dmin[end] == kNoSeed) ++end;
        const int left = x > 0 ? dmin[x - 1] : std::numeric_limits<int>::max();
        const int right = end < w ? dmin[end] : std::numeric_limits<int>::max();
        const int fill = std::min(left, right);
        if (fill != std::numeric_limits<int>::max())
          std::fill(dmin + x, dmin + end, static_cast<std::int16_t>(fill));
        x = end;
      }
    }
  });
}

/// stereo.c2f.max_match_cost: the pixel's own census distance at its winner, as the cost
/// pass stored it, against the key; the aggregated sums chose the winner, this asks
/// whether the pixel's window matched there at all.
void C2fMatcher::drop_poor_matches(Level& L) const {
  const int w = L.size.width;
  const std::size_t npad = static_cast<std::size_t>(L.npad);
  const int max_cost = config_.max_match_cost;
  const PixelIndex at{w};
  parallel_range(cv::Range(0, L.size.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      float* disp = L.disp.data() + at(0, y);
      const std::int16_t* winner = L.winner.data() + at(0, y);
      const std::int16_t* dmin = L.dmin.data() + at(0, y);
      const std::uint8_t* cost = L.cost.data() + at(0, y) * npad;
      for (int x = 0; x < w; ++x) {
        if (disp[x] < 0) continue;
        const int k = winner[x] - dmin[x];
        if (cost[static_cast<std::size_t>(x) * npad + static_cast<std::size_t>(k)] > max_cost)
          disp[x] = -1.f;
      }
    }
  });
}

void C2fMatcher::refine_subpixel(Level& L) const {
  // A parabola through one pixel's aggregated sums locks onto whole pixels (a rendered
  // ramp's disparities measured -0.06 px off at a quarter pixel, +0.07 at three
  // quarters): its raw census costs are small integers and the penalties flatten the
  // sums. Summed over a box of neighbours, each read at the centre's own three
  // disparities, and fitted with two lines (a census cost grows linearly with the
  // shift), the bias falls to ~0.01-0.03 px (docs/stereo.md). A neighbour adds all
  // three costs or none: its window must hold them and its right pixels lie in the image.
  const int w = L.size.width, h = L.size.height;
  const int r = config_.subpixel_radius;
  const std::size_t npad = static_cast<std::size_t>(L.npad);
  const unsigned last = static_cast<unsigned>(L.n - 3);
  const PixelIndex at{w};
  parallel_range(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      float* disp = L.disp.data() + at(0, y);
      const std::int16_t* winner = L.winner.data() + at(0, y);
      const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
      for (int x = 0; x < w; ++x) {
        if (disp[x] < 0) continue;
        // The box's costs at d - 1, d, d + 1.
        const int d = winner[x];
        const int x0 = std::max(d + 1, x - r), x1 = std::min(w - 1, x + r);
        int s0 = 0, s1 = 0, s2 = 0;
        for (int yy = y0; yy <= y1; ++yy) {
          const std::int16_t* dmin = L.dmin.data() + at(0, yy);
          const std::uint8_t* cost = L.cost.data() + at(0, yy) * npad;
          for (int xx = x0; xx <= x1; ++xx) {
            const int k = d - 1 - dmin[xx];  // kNoSeed: far above `last`
            if (static_cast<unsigned>(k) > last) continue;
            const std::uint8_t* c = cost + static_cast<std::size_t>(xx) * npad + k;
            s0 += c[0];
            s1 += c[1];
            s2 += c[2];
          }
        }
        // The box's lowest sum beside the winner: the neighbours disagree with the
        // aggregation (a slope steep across the box, an edge); the pixel keeps the
        // aggregated parabola (clamping the lines' vertex to +-0.5 px instead proved
        // 0.6-6 points less seen ground traversable, docs/stereo.md).
        if (s0 < s1 || s2 < s1) continue;
        // Equiangular: two lines of opposite slope through the three sums (a census cost
        // grows linearly with the shift, so a parabola would still lock, by 0.09 px).
        const int denom = std::max(s0, s2) - s1;
        float offset = 0.f;
        if (denom > 0) offset = static_cast<float>(s0 - s2) / static_cast<float>(2 * denom);
        disp[x] = static_cast<float>(d) + offset;
      }
    }
  });
}

void C2fMatcher::match_level(int l) {
  Level& L = levels_[static_cast<size_t>(l)];
  census(L.left, L.left_pad, config_.census_width, config_.census_height, avx2_, L.census_l);
  census(L.right, L.right_pad, config_.census_width, config_.census_height, avx2_, L.census_r);
  seed_level(l);
  if (!L.narrow) compute_costs(L);  // a narrow level: in its first row pass
  aggregate_rows(L);
  aggregate_columns(L);
  select_winners(L);
  if (l == 0 && config_.max_match_cost > 0) drop_poor_matches(L);
  if (l == 0 && config_.subpixel_radius > 0 && L.n >= 3) refine_subpixel(L);
  size_t valid = 0;
  for (const float d : L.disp) valid += d >= 0;
  valid_by_level_[static_cast<size_t>(l)] = valid;
}

// The stages below run in match_level's order; each pass reads what the one before wrote.
// Their loops and arithmetic are those of the single function they were split from.

c2f::StepParams C2fMatcher::step_params(const Level& L) const {
  c2f::StepParams sp;
  sp.n = L.n;
  sp.npad = L.npad;
  sp.p1 = config_.p1;
  sp.p2 = config_.p2;
  sp.pad_mask = L.pad_mask.data();
  return sp;
}

/// Costs (Hamming distances of the census codes over each pixel's window), and the sums
/// zeroed.
void C2fMatcher::compute_costs(Level& L) const {
  const int w = L.size.width, h = L.size.height;
  const int n = L.n, npad = L.npad;
  const int bits = config_.census_width * config_.census_height - 1;
  const PixelIndex at{w};
  parallel_range(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const std::uint64_t* cl = L.census_l.data() + at(0, y);
      const std::uint64_t* cr = L.census_r.data() + at(0, y);
      for (int x = 0; x < w; ++x) {
        std::uint8_t* c = L.cost.data() + at(x, y) * static_cast<size_t>(npad);
        std::fill(L.sum.data() + at(x, y) * static_cast<size_t>(npad),
                  L.sum.data() + (at(x, y) + 1) * static_cast<size_t>(npad), 0);
        const int d0 = L.dmin[at(x, y)];
        if (d0 == kNoSeed) continue;
        c2f_detail::hamming_window(cl[x], cr, x - d0, n, bits, c);
      }
    }
  });
}

/// Along rows, both ways: rows in strips (a narrow level: its costs and sums too).
void C2fMatcher::aggregate_rows(Level& L) {
  const int w = L.size.width, h = L.size.height;
  const int n = L.n, npad = L.npad, stride = L.stride;
  const int bits = config_.census_width * config_.census_height - 1;
  const PixelIndex at{w};
  const auto step = avx2_ ? c2f::step_avx2 : c2f::step_scalar;
  const std::int16_t* lut = p2_lut();
  parallel_range(cv::Range(0, strips_), [&](const cv::Range& range) {
    c2f::StepParams sp = step_params(L);
    for (int s = range.start; s < range.end; ++s) {
      std::vector<std::int16_t>& buffer = scratch_[static_cast<size_t>(s)];
      std::fill(buffer.begin(), buffer.end(), kInf);  // another level's lanes
      std::int16_t* a = buffer.data() + kPad;
      std::int16_t* b = a + stride;
      const cv::Range rows = strip(h, strips_, s);
      if (L.narrow) {
        c2f::NarrowRow r;
        r.width = w;
        r.n = n;
        r.bits = bits;
        r.p1 = config_.p1;
        r.p2 = config_.p2;
        r.p2_of_diff = lut;
        for (int y = rows.start; y < rows.end; ++y) {
          r.image = L.left.ptr<std::uint8_t>(y);
          r.dmin = L.dmin.data() + at(0, y);
          r.census_l = L.census_l.data() + at(0, y);
          r.census_r = L.census_r.data() + at(0, y);
          r.cost = L.cost.data() + at(0, y) * static_cast<size_t>(npad);
          r.sum = L.sum.data() + at(0, y) * static_cast<size_t>(npad);
          (avx2_ ? c2f::rows_narrow_avx2 : c2f::rows_narrow_scalar)(r);
        }
        continue;
      }
      for (int y = rows.start; y < rows.end; ++y) {
        for (int dir = 0; dir < 2; ++dir) {
          const int x0 = dir == 0 ? 0 : w - 1, dx = dir == 0 ? 1 : -1;
          std::int16_t* prev = a;
          std::int16_t* cur = b;
          bool has_prev = false;
          int prev_min = 0, prev_dmin = 0;
          for (int i = 0, x = x0; i < w; ++i, x += dx) {
            const size_t p = at(x, y);
            const int d0 = L.dmin[p];
            if (d0 == kNoSeed) {
              has_prev = false;
              continue;
            }
            if (lut && has_prev) {
              const std::uint8_t* img = L.left.ptr<std::uint8_t>(y);
              sp.p2 = c2f::edge_p2(lut, img[x], img[x - dx]);
            }
            prev_min = step(has_prev ? prev : nullptr, prev_min, d0 - prev_dmin,
                            L.cost.data() + p * static_cast<size_t>(npad), sp, cur,
                            L.sum.data() + p * static_cast<size_t>(npad));
            prev_dmin = d0;
            has_prev = true;
            std::swap(prev, cur);
          }
        }
      }
    }
  });
}

/// Down and up the columns (and diagonals with 8 paths): rows in order, each row's
/// pixels from the row before; column strips in parallel, diagonals serial.
void C2fMatcher::aggregate_columns(Level& L) const {
  const int w = L.size.width;
  for (int dy : {1, -1}) {
    parallel_range(cv::Range(0, strips_), [&](const cv::Range& range) {
      for (int s = range.start; s < range.end; ++s) column_pass(L, 0, dy, strip(w, strips_, s));
    });
  }
  if (config_.paths == 8)
    for (int dy : {1, -1})
      for (int dx : {1, -1}) column_pass(L, dx, dy, cv::Range(0, w));
}

/// One vertical (dx = 0) or diagonal pass over columns [cols.start, cols.end).
void C2fMatcher::column_pass(Level& L, int dx, int dy, cv::Range cols) const {
  if (L.narrow) {
    column_pass_narrow(L, dx, dy, cols);
    return;
  }
  const int w = L.size.width, h = L.size.height;
  const int npad = L.npad, stride = L.stride;
  const PixelIndex at{w};
  c2f::StepParams sp = step_params(L);
  const std::int16_t* lut = p2_lut();
  const auto step = avx2_ ? c2f::step_avx2 : c2f::step_scalar;
  std::int16_t* rowbuf[2] = {L.state.data() + kPad,
                             L.state.data() + kPad + static_cast<size_t>(w) * stride};
  int* rowmin[2] = {L.state_min.data(), L.state_min.data() + w};
  const int y0 = dy > 0 ? 0 : h - 1;
  // Which pixels of the previous row have a path cost: dmin != kNoSeed there and the
  // row exists.
  for (int i = 0, y = y0; i < h; ++i, y += dy) {
    std::int16_t* prev = rowbuf[(i + 1) & 1];
    std::int16_t* cur = rowbuf[i & 1];
    int* pmin = rowmin[(i + 1) & 1];
    int* cmin = rowmin[i & 1];
    const int yq = y - dy;
    for (int x = cols.start; x < cols.end; ++x) {
      const size_t p = at(x, y);
      const int d0 = L.dmin[p];
      if (d0 == kNoSeed) continue;
      const int xq = x - dx;
      const bool has_prev = i > 0 && xq >= 0 && xq < w && L.dmin[at(xq, yq)] != kNoSeed;
      const int qd0 = has_prev ? L.dmin[at(xq, yq)] : 0;
      if (lut && has_prev)
        sp.p2 = c2f::edge_p2(lut, L.left.at<std::uint8_t>(y, x), L.left.at<std::uint8_t>(yq, xq));
      cmin[x] = step(has_prev ? prev + static_cast<size_t>(xq) * stride : nullptr,
                     has_prev ? pmin[xq] : 0, d0 - qd0,
                     L.cost.data() + p * static_cast<size_t>(npad), sp,
                     cur + static_cast<size_t>(x) * stride,
                     L.sum.data() + p * static_cast<size_t>(npad));
    }
  }
}

/// column_pass on a narrow level: whole rows of 8-lane windows per kernel call.
void C2fMatcher::column_pass_narrow(Level& L, int dx, int dy, cv::Range cols) const {
  const int w = L.size.width, h = L.size.height;
  const int npad = L.npad;
  const PixelIndex at{w};
  c2f::NarrowColumnRow r;
  r.width = w;
  r.n = L.n;
  r.p1 = config_.p1;
  r.p2 = config_.p2;
  r.p2_of_diff = p2_lut();
  r.x0 = cols.start;
  r.x1 = cols.end;
  r.dx = dx;
  const auto kernel = avx2_ ? c2f::column_row_narrow_avx2 : c2f::column_row_narrow_scalar;
  const int y0 = dy > 0 ? 0 : h - 1;
  for (int i = 0, y = y0; i < h; ++i, y += dy) {
    r.dmin = L.dmin.data() + at(0, y);
    r.prev_dmin = i > 0 ? L.dmin.data() + at(0, y - dy) : nullptr;
    r.image = L.left.ptr<std::uint8_t>(y);
    r.prev_image = i > 0 ? L.left.ptr<std::uint8_t>(y - dy) : nullptr;
    r.prev = L.state.data() + static_cast<size_t>((i + 1) & 1) * c2f::state_row_lanes(w);
    r.prev_min = L.state_min.data() + static_cast<size_t>((i + 1) & 1) * w;
    r.cur = L.state.data() + static_cast<size_t>(i & 1) * c2f::state_row_lanes(w);
    r.cur_min = L.state_min.data() + static_cast<size_t>(i & 1) * w;
    r.cost = L.cost.data() + at(0, y) * static_cast<size_t>(npad);
    r.sum = L.sum.data() + at(0, y) * static_cast<size_t>(npad);
    kernel(r);
  }
}

/// Winner takes all, uniqueness (full level), left-right check, sub-pixel.
void C2fMatcher::select_winners(Level& L) const {
  const int w = L.size.width, h = L.size.height;
  const int n = L.n, npad = L.npad;
  const PixelIndex at{w};
  const int lr = config_.lr_max_diff;
  const int uniq = config_.uniqueness;
  parallel_range(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      std::uint16_t* rs = L.right_s.data() + at(0, y);
      std::int16_t* rd = L.right_d.data() + at(0, y);
      std::fill(rs, rs + w, c2f::kNoSum);
      std::fill(rd, rd + w, static_cast<std::int16_t>(-1));
      float* disp = L.disp.data() + at(0, y);
      c2f::WinnerRow row;
      row.sum = L.sum.data() + at(0, y) * static_cast<size_t>(npad);
      row.npad = npad;
      row.n = n;
      row.width = w;
      row.lo = L.lo;
      row.hi = L.hi;
      row.full = L.full;
      row.uniqueness = uniq;
      row.dmin = L.dmin.data() + at(0, y);
      row.right_s = rs;
      row.right_d = rd;
      row.disp = disp;
      row.winner = L.winner.data() + at(0, y);
      row.conf = L.full ? L.conf.data() + at(0, y) : nullptr;
      (avx2_ && L.narrow ? c2f::winners_narrow_avx2 : c2f_detail::winners_row)(row);
      if (lr < 0) continue;
      for (int x = 0; x < w; ++x) {
        if (disp[x] < 0) continue;
        const int d = L.winner[at(x, y)];
        const int xr = x - d;
        if (xr < 0 || rd[xr] < 0 || std::abs(rd[xr] - d) > lr) disp[x] = -1.f;
      }
    }
  });
  if (L.full)
    for (size_t i = 0; i < L.disp.size(); ++i)
      if (L.disp[i] < 0) L.conf[i] = 0;
}

/// stereo.c2f.outline_jump_px, on the fixed-point output: each column top to bottom, a
/// valid pixel against the last valid one above it (at most 2 k + 2 rows up); a jump of
/// more than the key drops k pixels on its smaller-disparity side, starting at the pixel
/// next to the jump and going away from it. Decided on the undropped values.
void C2fMatcher::drop_outline_rows(cv::Mat& disparity_x16, int invalid) {
  const int k = config_.outline_rows;
  const int gap = 2 * k + 2;
  const int jump = static_cast<int>(std::lround(16.0 * config_.outline_jump_px));
  const int rows = disparity_x16.rows;
  outline_drop_.setTo(0);
  parallel_range(cv::Range(0, disparity_x16.cols), [&](const cv::Range& cols) {
    for (int x = cols.start; x < cols.end; ++x) outline_row_[static_cast<size_t>(x)] = -gap - 1;
    for (int y = 0; y < rows; ++y) {
      const std::int16_t* d = disparity_x16.ptr<std::int16_t>(y);
      for (int x = cols.start; x < cols.end; ++x) {
        const int v = d[x];
        if (v <= invalid) continue;
        const size_t i = static_cast<size_t>(x);
        const int above = outline_value_[i];
        if (y - outline_row_[i] <= gap && std::abs(v - above) > jump) {
          // The far side is the smaller disparity: upwards from the pixel above, or
          // downwards from this one.
          const int from = v > above ? outline_row_[i] : y;
          const int step = v > above ? -1 : 1;
          for (int j = 0, yy = from; j < k && yy >= 0 && yy < rows; ++j, yy += step)
            outline_drop_.ptr<std::uint8_t>(yy)[x] = 1;
        }
        outline_row_[i] = y;
        outline_value_[i] = static_cast<std::int16_t>(v);
      }
    }
  });
  disparity_x16.setTo(cv::Scalar::all(invalid), outline_drop_);
}

void C2fMatcher::compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16) {
  Level& L0 = levels_[0];
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != L0.size ||
      right.size() != L0.size)
    throw Error("c2f: expected 8-bit grey images of the configured size");
  L0.left = left;
  L0.right = right;
  for (size_t l = 1; l < levels_.size(); ++l) {
    pyramid_down(levels_[l - 1].left, levels_[l].left, pyramid_row_, strips_);
    pyramid_down(levels_[l - 1].right, levels_[l].right, pyramid_row_, strips_);
  }
  for (int l = static_cast<int>(levels_.size()) - 1; l >= 0; --l) match_level(l);

  const int invalid = (min_disparity_ - 1) * 16;
  disparity_x16.create(L0.size, CV_16SC1);
  const Level& top = levels_.back();
  const int shift = static_cast<int>(levels_.size()) - 1;
  parallel_range(cv::Range(0, L0.size.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      std::int16_t* out = disparity_x16.ptr<std::int16_t>(y);
      std::uint8_t* conf = confidence_.ptr<std::uint8_t>(y);
      const float* d = L0.disp.data() + static_cast<size_t>(y) * static_cast<size_t>(L0.size.width);
      const std::uint8_t* tc =
          top.conf.data() + static_cast<size_t>(y >> shift) * static_cast<size_t>(top.size.width);
      for (int x = 0; x < L0.size.width; ++x) {
        out[x] = d[x] < 0 ? static_cast<std::int16_t>(invalid)
                          : static_cast<std::int16_t>(round_non_negative(16.f * d[x]));
        conf[x] = tc[x >> shift];
      }
    }
  });
  if (config_.outline_jump_px > 0) drop_outline_rows(disparity_x16, invalid);
  if (speckle_window_ > 0)
    speckle_.apply(disparity_x16, invalid, speckle_window_, 16 * speckle_range_);
  L0.left = cv::Mat();
  L0.right = cv::Mat();
}

}  // namespace hazmap
