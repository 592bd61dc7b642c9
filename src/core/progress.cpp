#include "hazmap/core/progress.hpp"

#include <cmath>
#include <cstdio>

namespace hazmap {

std::string human_duration(double seconds) {
  if (!(seconds >= 0) || !std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  char text[48];
  if (seconds < 9.95)
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  else if (s < 60)
    std::snprintf(text, sizeof text, "%ld s", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return text;
}

std::string rate_and_time_left(int done, int total, double elapsed_s, const std::string& unit) {
  if (done <= 0 || !(elapsed_s > 0)) return {};
  char text[128];
  const double rate = done / elapsed_s;
  // Two significant digits or more: 0.052, 0.52, 5.2, 52.
  std::snprintf(text, sizeof text, rate < 0.1 ? "%.3f %s/s" : rate < 10 ? "%.2f %s/s" : "%.0f %s/s",
                rate, unit.c_str());
  const std::string out = text;
  if (done >= total) return out + ", " + human_duration(elapsed_s) + " in all";
  return out + ", " + human_duration((total - done) / rate) + " left";
}

std::string progress_text(int done, int total, double elapsed_s, const std::string& unit) {
  const std::string tail = rate_and_time_left(done, total, elapsed_s, unit);
  const std::string count = std::to_string(done) + "/" + std::to_string(total);
  return tail.empty() ? count : count + ", " + tail;
}

}  // namespace hazmap
