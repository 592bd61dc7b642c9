// Image statistics for comparing hazmap simulate renders with real imagery (issue 33,
// docs/simulator.md "Against POLAR Traverse"). Not part of the build: tools/polar_compare/
// polar_compare.sh compiles it with the system OpenCV.
//
//   image_stats stats IMAGE.png [ROI_TOP_FRACTION] [SHADOW_DN]
//     one line: mean, p5/p50/p95 grey level, local contrast (std of 7 x 7 patches: median
//     and mean), shadowed share (grey < SHADOW_DN), a 8-bin histogram (% per 32 DN), over
//     the rows below ROI_TOP_FRACTION of the height (the ground; default 0.45).
//   image_stats montage OUT.png HEIGHT A.png B.png [C.png ...]
//     the images side by side, each scaled to HEIGHT rows, 4 px white gaps.
//   image_stats resize IN.png OUT.png FACTOR
//     IN scaled by FACTOR (area averaging).
//   image_stats hist OUT.png ROI_TOP_FRACTION A.png B.png
//     the two grey-level histograms (ground rows) as a 512 x 200 plot: A white, B grey.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace {

cv::Mat load_grey8(const std::string& path) {
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) {
    std::fprintf(stderr, "image_stats: cannot read %s\n", path.c_str());
    std::exit(2);
  }
  if (image.channels() > 1) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  if (image.depth() == CV_16U) image.convertTo(image, CV_8U, 1.0 / 256.0);
  return image;
}

cv::Mat ground_rows(const cv::Mat& image, double top_fraction) {
  const int top = static_cast<int>(top_fraction * image.rows);
  return image.rowRange(top, image.rows);
}

std::vector<double> histogram(const cv::Mat& grey, int bins) {
  std::vector<double> h(bins, 0.0);
  for (int v = 0; v < grey.rows; ++v)
    for (int u = 0; u < grey.cols; ++u) h[grey.at<unsigned char>(v, u) * bins / 256] += 1.0;
  for (double& x : h) x *= 100.0 / grey.total();
  return h;
}

int percentile(const cv::Mat& grey, double p) {
  std::vector<double> h = histogram(grey, 256);
  double sum = 0;
  for (int i = 0; i < 256; ++i) {
    sum += h[i];
    if (sum >= p) return i;
  }
  return 255;
}

int stats(int argc, char** argv) {
  if (argc < 3) return 2;
  const double top = argc > 3 ? std::atof(argv[3]) : 0.45;
  const int shadow_dn = argc > 4 ? std::atoi(argv[4]) : 20;
  const cv::Mat grey = ground_rows(load_grey8(argv[2]), top);
  cv::Mat f, mean7, sq7;
  grey.convertTo(f, CV_64F);
  cv::boxFilter(f, mean7, CV_64F, cv::Size(7, 7), cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  cv::boxFilter(f.mul(f), sq7, CV_64F, cv::Size(7, 7), cv::Point(-1, -1), true,
                cv::BORDER_REFLECT);
  cv::Mat var7 = sq7 - mean7.mul(mean7);
  cv::max(var7, 0.0, var7);
  cv::Mat std7;
  cv::sqrt(var7, std7);
  // Patches 7 apart (independent): median and mean.
  std::vector<double> patches;
  for (int v = 3; v + 3 < std7.rows; v += 7)
    for (int u = 3; u + 3 < std7.cols; u += 7) patches.push_back(std7.at<double>(v, u));
  std::nth_element(patches.begin(), patches.begin() + patches.size() / 2, patches.end());
  const double median7 = patches[patches.size() / 2];
  double mean_std7 = 0;
  for (double p : patches) mean_std7 += p;
  mean_std7 /= patches.size();
  const double shadow = 100.0 * cv::countNonZero(grey < shadow_dn) / grey.total();
  const std::vector<double> h = histogram(grey, 8);
  std::printf("mean %.1f p5 %d p50 %d p95 %d std7_median %.2f std7_mean %.2f shadow%% %.1f hist%%",
              cv::mean(grey)[0], percentile(grey, 5), percentile(grey, 50), percentile(grey, 95),
              median7, mean_std7, shadow);
  for (double x : h) std::printf(" %.1f", x);
  std::printf("\n");
  return 0;
}

int montage(int argc, char** argv) {
  if (argc < 5) return 2;
  const int height = std::atoi(argv[3]);
  std::vector<cv::Mat> parts;
  for (int i = 4; i < argc; ++i) {
    cv::Mat image = load_grey8(argv[i]);
    cv::Mat scaled;
    cv::resize(image, scaled, cv::Size(image.cols * height / image.rows, height), 0, 0,
               cv::INTER_AREA);
    if (!parts.empty()) parts.push_back(cv::Mat(height, 4, CV_8U, cv::Scalar(255)));
    parts.push_back(scaled);
  }
  cv::Mat out;
  cv::hconcat(parts, out);
  return cv::imwrite(argv[2], out) ? 0 : 1;
}

int hist_plot(int argc, char** argv) {
  if (argc < 6) return 2;
  const double top = std::atof(argv[3]);
  cv::Mat plot(200, 512, CV_8U, cv::Scalar(0));
  const std::vector<double> a = histogram(ground_rows(load_grey8(argv[4]), top), 64);
  const std::vector<double> b = histogram(ground_rows(load_grey8(argv[5]), top), 64);
  const double peak = std::max(*std::max_element(a.begin(), a.end()),
                               *std::max_element(b.begin(), b.end()));
  for (int i = 0; i < 64; ++i) {
    const int ha = static_cast<int>(190 * a[i] / peak);
    const int hb = static_cast<int>(190 * b[i] / peak);
    cv::rectangle(plot, cv::Rect(i * 8, 200 - ha, 4, ha), cv::Scalar(255), cv::FILLED);
    cv::rectangle(plot, cv::Rect(i * 8 + 4, 200 - hb, 4, hb), cv::Scalar(128), cv::FILLED);
  }
  return cv::imwrite(argv[2], plot) ? 0 : 1;
}

int resize(int argc, char** argv) {
  if (argc < 5) return 2;
  const cv::Mat image = load_grey8(argv[2]);
  const double f = std::atof(argv[4]);
  cv::Mat out;
  cv::resize(image, out, cv::Size(), f, f, cv::INTER_AREA);
  return cv::imwrite(argv[3], out) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  int rc = 2;
  if (mode == "stats") rc = stats(argc, argv);
  if (mode == "montage") rc = montage(argc, argv);
  if (mode == "hist") rc = hist_plot(argc, argv);
  if (mode == "resize") rc = resize(argc, argv);
  if (rc == 2) std::fprintf(stderr, "usage: see the comment at the top of image_stats.cpp\n");
  return rc;
}
