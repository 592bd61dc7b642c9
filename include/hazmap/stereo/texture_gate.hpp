#pragma once
// stereo.min_texture_snr: a matcher fed a window that holds nothing but sensor noise
// still returns its best match, and a semi-global matcher (c2f, SGBM) carries its
// neighbours' disparities into such windows. Under low sun on smooth regolith that is
// most of the image: c2f kept ~1.6 % of a low-sun ramp's pixels, 93 % of them more than
// 1 px wrong, and every known cell of the map was a false hazard. The gate drops a
// disparity whose left-image window (the matcher's) has a grey-level variance below
// noise^2 (1 + snr^2), i.e. whose contrast above the noise is below snr times the noise.
// The noise is estimated per frame from the left image (image_noise_dn).

#include <opencv2/core.hpp>

namespace hazmap {

/// The standard deviation of a grey image's additive noise [DN], by Immerkaer's estimator
/// (1996): the mean absolute response to the 3 x 3 difference of two Laplacians, which
/// cancels planar and mostly smooth shading, times sqrt(pi / 2) / 6. Texture at the pixel
/// scale raises it: an upper bound on textured images. 8-bit single channel; 0 for an
/// image smaller than 3 x 3.
double image_noise_dn(const cv::Mat& grey);

class TextureGate {
 public:
  /// `min_snr` <= 0: off. `window`: the matcher's window (odd sides), centred on a pixel
  /// and clipped at the image's edges.
  TextureGate(double min_snr, cv::Size window);

  bool enabled() const { return min_snr_ > 0; }

  /// Sets to `invalid` every disparity of `disparity_x16` (CV_16S, the size of `left`)
  /// whose window in `left` (8-bit grey) is too flat. Returns the noise estimate used
  /// (0 when off: nothing is estimated).
  /// Buffers are kept: no allocation once the image size is fixed.
  double apply(const cv::Mat& left, cv::Mat& disparity_x16, short invalid);

 private:
  double min_snr_;
  cv::Size window_;
  cv::Mat sum_, sqsum_;  ///< integral images of the left image and of its squares
};

}  // namespace hazmap
