#include "hazmap/pipeline/empty_run.hpp"

#include <algorithm>
#include <cstdio>

namespace hazmap {

void count_disparity_drops(const cv::Mat& disparity_x16, const cv::Rect& region,
                           int invalid_below_x16, double d_min_px, double d_max_px,
                           EmptyRunCounts& drops) {
  const cv::Rect r = region & cv::Rect(0, 0, disparity_x16.cols, disparity_x16.rows);
  // The gate's bounds in the matcher's fixed point (x16), compared as the builder does.
  const double lo = 16.0 * d_min_px, hi = 16.0 * d_max_px;
  for (int y = r.y; y < r.y + r.height; ++y) {
    const short* row = disparity_x16.ptr<short>(y);
    for (int x = r.x; x < r.x + r.width; ++x) {
      const int d = row[x];
      if (d <= invalid_below_x16 || d <= 0) ++drops.no_disparity;
      else if (d < lo) ++drops.beyond_z_max;
      else if (d > hi) ++drops.nearer_than_z_min;
    }
  }
  drops.pixels += static_cast<std::size_t>(r.area());
  ++drops.frames;
}

std::string no_points_message(const EmptyRunCounts& d) {
  char text[1024];
  auto pct = [&](std::size_t n) {
    return d.pixels > 0 ? 100.0 * static_cast<double>(n) / static_cast<double>(d.pixels) : 0.0;
  };
  // The gate that took the most pixels names the setting.
  struct Reason {
    std::size_t count;
    std::string setting;
  };
  const Reason reasons[] = {
      {d.no_disparity, "the calibration or the search: run hazmap check (rectified rows, "
                       "stereo.num_disparities)"},
      {d.beyond_z_max, "stereo.z_max, or T if it is not in metres"},
      {d.nearer_than_z_min, "stereo.z_min"},
      {d.unsupported, "stereo.support_rows"},
      {d.below_ground, "T_body_left (the camera's height and pitch put the ground it sees below "
                       "the wheel plane z_B = 0), or stereo.max_below_ground"},
      {d.occluded, "T_body_left or the poses (the points lie behind terrain already mapped: "
                   "the camera is not where the images were taken)"},
  };
  const Reason* top = std::max_element(std::begin(reasons), std::end(reasons),
                                       [](const Reason& a, const Reason& b) { return a.count < b.count; });
  std::snprintf(text, sizeof text,
                "no frame gave a point (%zu frames, %zu pixels): no disparity %.1f %%, beyond "
                "stereo.z_max %.1f %%, nearer than stereo.z_min %.1f %%, unsupported %.1f %%, "
                "below the ground %.1f %%, occluded %.1f %%; most likely wrong: %s",
                d.frames, d.pixels, pct(d.no_disparity), pct(d.beyond_z_max),
                pct(d.nearer_than_z_min), pct(d.unsupported), pct(d.below_ground),
                pct(d.occluded), top->setting.c_str());
  return text;
}

}  // namespace hazmap
