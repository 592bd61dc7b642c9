#pragma once
// Exact per-pixel ray casting of a synthetic Terrain into a pinhole camera, with or
// without lens distortion (camera_model.hpp). Geometry is exact to the ray-casting
// tolerance, so an ideal rectified pair rendered with this module has true disparity
// f B / Z at every pixel: tests and evaluations can compare a stereo pipeline against it.
//
// Frames: W world (z up); C camera, OpenCV convention (x right, y down, z forward).
// Pixel centres are at integer (u, v); pixel (u, v) covers [u - 0.5, u + 0.5).

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/sim/camera_model.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::sim {

/// Where a ray meets the terrain.
struct RayHit {
  double range_m = 0.0;       ///< distance from the ray origin along the unit direction
  Eigen::Vector3d p_W;        ///< hit point, exactly origin + range * direction
  Eigen::Vector3d normal_W;   ///< unit outward surface normal
  int rock_index = -1;        ///< index into Terrain::rocks(), or -1 for the ground
};

struct RayCastOptions {
  double max_range_m = 20.0;  ///< rays that hit nothing closer see the sky
  /// Below this height above the ground, marching switches from conservative steps to
  /// steps that may overshoot by at most this much (then bisection brackets the hit).
  /// Surface features thinner than this can be missed.
  double march_tolerance_m = 5e-4;
  /// The returned ground hit satisfies |z - ground_height_m(x, y)| < this.
  double surface_tolerance_m = 1e-5;
};

/// Nearest intersection of the ray origin_W + t direction_W (t > 0) with the terrain
/// within max_range_m. Ground: conservative marching with step h / (|d_z| + G |d_xy|)
/// (G = Terrain::max_ground_gradient(), h = height above ground), then bisection.
/// Rocks: analytic ray-sphere intersection with the rocks the terrain's RockGrid lists
/// along the ray, counting only hits above the ground (a rock containing the origin is
/// ignored); the same answer as testing every rock. `direction_W` need not be unit. Returns nullopt for
/// sky. The origin should be above the ground; from below, the result is "hit at once".
/// Thread-safe.
std::optional<RayHit> cast_ray(const Terrain& terrain, const Eigen::Vector3d& origin_W,
                               const Eigen::Vector3d& direction_W,
                               const RayCastOptions& options = RayCastOptions());

/// The albedo pattern of the ground and rocks.
///   value_noise : equal-amplitude octaves from texture_min_wavelength_m upwards (strong
///                 texture at every scale: what block matching likes; the default);
///   regolith    : dull lunar soil: relative std regolith_contrast, correlated over
///                 regolith_correlation_m (octaves from that wavelength upwards, each half
///                 the amplitude of the next longer one), so there is little albedo
///                 contrast at the few-pixel scales a matcher's window sees; what texture
///                 the images have then comes from the relief and its shadows.
enum class AlbedoModel { value_noise, regolith };

/// "value_noise" | "regolith"; throws Error naming `what` otherwise.
AlbedoModel parse_albedo_model(const std::string& name, const std::string& what);
const char* albedo_model_name(AlbedoModel model);

/// What a camera does to the light (per camera: the two cameras of a pair differ).
/// Signal S = vignette(u, v) * gain * exposure * L + offset_dn, with L the renderer's
/// noise-free radiance in DN; then shot noise (Gaussian approximation of Poisson, variance
/// (S - offset) / electrons_per_dn DN^2) and read noise (RenderOptions::noise_sigma_dn, DN),
/// rounded and clipped to [0, 2^bits - 1].
/// vignette = 1 - vignetting * (r / r_corner)^2, r from the principal point.
struct CameraResponse {
  double gain = 1.0;
  double exposure = 1.0;         ///< relative exposure time (1: the renderer's exposure_dn)
  double offset_dn = 0.0;        ///< black level
  double electrons_per_dn = 0.0; ///< conversion gain for shot noise; 0: no shot noise
  double vignetting = 0.0;       ///< fall-off at the image corner, in [0, 1)
  int bits = 8;                  ///< 8 (CV_8UC1) or 12 (CV_16UC1 holding 0..4095)

  bool is_identity() const {
    return gain == 1.0 && exposure == 1.0 && offset_dn == 0.0 && electrons_per_dn == 0.0 &&
           vignetting == 0.0 && bits == 8;
  }
};

/// Throws Error naming the setting if a response is unusable (gain or exposure <= 0,
/// vignetting outside [0, 1), bits not 8 or 12, ...).
void validate(const CameraResponse& response);

struct RenderOptions {
  RayCastOptions ray_cast;
  /// Rays per pixel along each axis (box filter over the pixel): 2 => 2 x 2 rays. Anti-
  /// aliases rock silhouettes; texture is band-limited separately (see Renderer).
  int samples_per_axis = 2;
  AlbedoModel albedo_model = AlbedoModel::value_noise;
  /// Texture: octave k of value noise has wavelength texture_min_wavelength_m * 2^k.
  /// Equal amplitudes give texture at every scale, which is what block matching needs
  /// from 0.2 m (mm detail) to several metres (cm to dm detail).
  double texture_min_wavelength_m = 0.002;
  int texture_octaves = 9;
  double texture_contrast = 0.45;  ///< relative std of the albedo: mean * (1 + c * N(0, 1))
  double regolith_contrast = 0.05;       ///< regolith: relative std of the albedo
  double regolith_correlation_m = 0.05;  ///< regolith: shortest wavelength with contrast
  double ground_albedo = 0.5;      ///< mean albedo of the ground
  double rock_albedo = 0.45;       ///< mean albedo of rocks
  /// Lambertian sun; when off, every surface shows its albedo as if lit like flat ground.
  bool sun_shading = true;
  double sun_elevation_deg = 30.0;
  double sun_azimuth_deg = 110.0;  ///< from W +x towards +y (110: from the left, behind)
  bool cast_shadows = true;        ///< shadows of rocks
  /// Shadows cast by the ground too (craters, ridges, slopes facing away), traced towards
  /// the sun over the height field and the rocks. Off by default (the images of earlier
  /// versions); needed for a low sun.
  bool terrain_shadows = false;
  double ambient = 0.25;           ///< fraction of light that reaches shaded surfaces
  /// Opposition surge: radiance times 1 + amplitude exp(-phase / width), phase = angle
  /// between the directions to the sun and to the camera (brighter looking away from
  /// the sun). 0: none.
  double opposition_surge = 0.0;
  double opposition_width_deg = 6.0;
  double exposure_dn = 200.0;      ///< DN of albedo 1 on flat ground in full sun
  double noise_sigma_dn = 1.0;     ///< additive Gaussian image noise (read noise)
};

/// Renders 8-bit grey images of a terrain. Holds a reference to the terrain, which must
/// outlive it. All methods are const and thread-safe.
///
/// Radiance = exposure * albedo(p) * shading * surge / shading(flat ground in sun), with
/// shading = ambient + (1 - ambient) max(0, n . s) (0 in a cast shadow for the second
/// term; a low sun makes slopes facing it brighter than flat ground by up to
/// 1 / sin(elevation): lower the camera's exposure to keep them below saturation). Albedo is multi-octave value noise of the hit point (2-D in W x, y on the
/// ground, 3-D on rocks), band-limited per ray: octaves whose wavelength is below about
/// three ray footprints fade out, so distant ground does not alias.
class Renderer {
 public:
  /// `texture_seed` chooses the albedo pattern. Throws Error on invalid options
  /// (samples_per_axis < 1, negative noise, ...).
  Renderer(const Terrain& terrain, const RenderOptions& options, std::uint64_t texture_seed);

  /// Renders the camera at pose T_W_C (camera C in W), through its lens distortion if
  /// any. Returns CV_8UC1, height_px x width_px. Sky is black. Image noise comes from a counter-based hash of
  /// (noise_key, pixel), so the image is bit-identical for any thread count.
  /// Parallel over rows (cv::parallel_for_).
  /// `response` models the camera (gain, exposure, offset, shot noise, vignetting, bit
  /// depth); the default one reproduces the images of earlier versions bit for bit.
  /// CV_16UC1 for a 12-bit response.
  cv::Mat render(const PinholeCamera& camera, const Pose3d& T_W_C, std::uint64_t noise_key,
                 const CameraResponse& response = CameraResponse()) const;

  /// True depth: CV_32FC1 with Z in C of the surface seen through each pixel centre, NaN
  /// for sky. With a rectified pair, true disparity = fx * baseline / Z.
  cv::Mat render_depth(const PinholeCamera& camera, const Pose3d& T_W_C) const;

  /// Noise-free radiance (DN, unclipped) seen along a ray that hit `hit`;
  /// `footprint_m` is the ray's footprint on the surface, for band-limiting the texture.
  /// `view_W`, when given, is the unit direction from the hit towards the camera (for the
  /// opposition surge).
  double radiance(const RayHit& hit, double footprint_m,
                  const Eigen::Vector3d* view_W = nullptr) const;

  /// True if the sun is hidden from `hit` by the terrain (with terrain_shadows) or a rock
  /// (with cast_shadows).
  bool in_shadow(const RayHit& hit) const;

  /// Unit vector towards the sun, in W.
  const Eigen::Vector3d& sun_W() const { return sun_W_; }

  const RenderOptions& options() const { return options_; }

 private:
  double albedo(const RayHit& hit, double footprint_m) const;
  bool in_rock_shadow(const RayHit& hit) const;
  bool in_terrain_shadow(const RayHit& hit) const;

  const Terrain& terrain_;
  RenderOptions options_;
  std::uint64_t texture_seed_;
  Eigen::Vector3d sun_W_;     ///< unit vector towards the sun
  double flat_shading_ = 1.0; ///< shading of flat ground in full sun (normalises radiance)
};

}  // namespace hazmap::sim
