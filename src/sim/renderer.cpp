#include "hazmap/sim/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <opencv2/core/utility.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxMarchSteps = 1000000;  // only a guard; typical rays take < 100 steps
constexpr int kMaxBisections = 100;

// Standard deviation of value_noise_2d/3d over the plane (quintic-faded uniform[-1, 1]
// lattice values), measured numerically; it normalises the texture to unit variance.
constexpr double kValueNoise2dStd = 0.455;
constexpr double kValueNoise3dStd = 0.40;

// Regolith albedo: octaves from the correlation length upwards, each twice the amplitude
// of the next shorter one (a red spectrum: little contrast at small scales).
constexpr int kRegolithOctaves = 6;

// Shadow rays start this far off the surface along its normal, so that the surface they
// leave does not shadow itself through rounding (0.1 mm: far below a terrain cell).
constexpr double kShadowBiasM = 1e-4;

// Band-limiting: an octave of wavelength lambda is fully present when lambda >= 3
// footprints and absent below 1.5 footprints (linear fade between).
inline double octave_weight(double wavelength_m, double footprint_m) {
  return std::clamp((wavelength_m / footprint_m - 1.5) / 1.5, 0.0, 1.0);
}

// Gaussian sample from a 64-bit hash (Box-Muller on two derived uniforms).
inline double gaussian_from_hash(std::uint64_t h) {
  const double u1 = 1.0 - unit_double(h);  // (0, 1]
  const double u2 = unit_double(mix64(h));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// First entry t > 0 of the ray o + t d (d unit) into the sphere (c, r); +inf if none or
// if o is inside. Stable form of the quadratic root (no cancellation).
inline double ray_sphere_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                               const Eigen::Vector3d& c, double r) {
  const Eigen::Vector3d oc = o - c;
  const double b = oc.dot(d);
  const double cc = oc.squaredNorm() - r * r;
  if (cc <= 0.0 || b >= 0.0) return std::numeric_limits<double>::infinity();
  const double disc = b * b - cc;
  if (disc < 0.0) return std::numeric_limits<double>::infinity();
  return cc / (-b + std::sqrt(disc));
}

}  // namespace

AlbedoModel parse_albedo_model(const std::string& name, const std::string& what) {
  if (name == "value_noise") return AlbedoModel::value_noise;
  if (name == "regolith") return AlbedoModel::regolith;
  throw Error(what + ": unknown albedo model '" + name + "' (value_noise | regolith)");
}

const char* albedo_model_name(AlbedoModel model) {
  return model == AlbedoModel::regolith ? "regolith" : "value_noise";
}

void validate(const CameraResponse& response) {
  check(response.bits == 8 || response.bits == 12, "camera: bits must be 8 or 12");
  check(response.gain > 0.0 && response.exposure > 0.0 && std::isfinite(response.gain) &&
            std::isfinite(response.exposure),
        "camera: camera gain and exposure must be positive");
  check(std::isfinite(response.offset_dn), "camera: camera offset must be finite");
  check(response.electrons_per_dn >= 0.0 && std::isfinite(response.electrons_per_dn),
        "camera: electrons_per_dn must be >= 0");
  check(response.vignetting >= 0.0 && response.vignetting < 1.0,
        "camera: vignetting must be in [0, 1)");
}

std::optional<RayHit> cast_ray(const Terrain& terrain, const Eigen::Vector3d& origin_W,
                               const Eigen::Vector3d& direction_W,
                               const RayCastOptions& options) {
  const double norm = direction_W.norm();
  check(norm > 0.0 && std::isfinite(norm), "cast_ray: direction must be non-zero and finite");
  const Eigen::Vector3d d = direction_W / norm;
  const Eigen::Vector3d& o = origin_W;

  // Rocks first: their nearest visible hit caps how far the ground march must go.
  double t_best = options.max_range_m;
  int best_rock = -1;
  const auto& rocks = terrain.rocks();
  terrain.rock_grid().traverse(o, d, t_best, [&](const int* begin, const int* end, double t_exit) {
    for (const int* i = begin; i != end; ++i) {
      const Eigen::Vector3d c = terrain.rock_center_W(static_cast<std::size_t>(*i));
      const double t = ray_sphere_entry(o, d, c, rocks[static_cast<std::size_t>(*i)].radius_m);
      if (!(t < t_best)) continue;
      const Eigen::Vector3d p = o + t * d;
      if (p.z() < terrain.ground_height_m(p.x(), p.y())) continue;  // buried part
      t_best = t;
      best_rock = *i;
    }
    return t_exit < t_best;  // a later cell can only hold a nearer hit if t_best lies beyond
  });

  // Ground: h(t) = z(t) - ground(x(t), y(t)) falls at most at `rate` per metre of t.
  const double G = terrain.max_ground_gradient();
  const double d_xy = std::sqrt(d.x() * d.x() + d.y() * d.y());
  const double rate = std::abs(d.z()) + G * d_xy;
  auto height_above_ground = [&](double t) {
    const Eigen::Vector3d p = o + t * d;
    return p.z() - terrain.ground_height_m(p.x(), p.y());
  };
  auto ground_hit = [&](double t) {
    RayHit hit;
    hit.range_m = t;
    hit.p_W = o + t * d;
    hit.normal_W = terrain.ground_normal_W(hit.p_W.x(), hit.p_W.y());
    hit.rock_index = -1;
    return hit;
  };

  double t = 0.0;
  double h = height_above_ground(0.0);
  if (h <= 0.0) return ground_hit(0.0);
  // A ray that climbs faster than the steepest ground, or climbs above the highest
  // ground, never meets it.
  const bool may_hit_ground =
      d.z() - G * d_xy < 0.0 && !(d.z() >= 0.0 && o.z() > terrain.max_ground_height_m());
  if (may_hit_ground) {
    for (int step = 0; step < kMaxMarchSteps && t < t_best; ++step) {
      // Conservative while h >= march tolerance; then overshoot by at most the tolerance.
      const double t_next = std::min(t + std::max(h, options.march_tolerance_m) / rate, t_best);
      const double h_next = height_above_ground(t_next);
      if (h_next > 0.0) {
        t = t_next;
        h = h_next;
        continue;
      }
      // Bracket [t, t_next] with h(t) > 0 >= h(t_next): bisect.
      double lo = t;
      double hi = t_next;
      double t_hit = t_next;
      if (-h_next >= options.surface_tolerance_m) {
        for (int k = 0; k < kMaxBisections; ++k) {
          t_hit = 0.5 * (lo + hi);
          const double h_mid = height_above_ground(t_hit);
          if (std::abs(h_mid) < options.surface_tolerance_m) break;
          (h_mid > 0.0 ? lo : hi) = t_hit;
        }
      }
      return ground_hit(t_hit);
    }
  }

  if (best_rock < 0) return std::nullopt;
  RayHit hit;
  hit.range_m = t_best;
  hit.p_W = o + t_best * d;
  hit.normal_W = (hit.p_W - terrain.rock_center_W(best_rock)).normalized();
  hit.rock_index = best_rock;
  return hit;
}

Renderer::Renderer(const Terrain& terrain, const RenderOptions& options,
                   std::uint64_t texture_seed)
    : terrain_(terrain), options_(options), texture_seed_(texture_seed) {
  check(options.samples_per_axis >= 1 && options.samples_per_axis <= 8,
        "render: samples_per_axis must be in [1, 8]");
  check(options.ray_cast.max_range_m > 0.0, "render: max_range_m must be positive");
  check(options.ray_cast.march_tolerance_m > 0.0 && options.ray_cast.surface_tolerance_m > 0.0,
        "render: ray-casting tolerances must be positive");
  check(options.texture_min_wavelength_m > 0.0, "render: texture_min_wavelength_m must be > 0");
  check(options.texture_octaves >= 0 && options.texture_octaves <= 24,
        "render: texture_octaves must be in [0, 24]");
  check(options.texture_contrast >= 0.0, "render: texture_contrast must be >= 0");
  check(options.ambient >= 0.0 && options.ambient <= 1.0, "render: ambient must be in [0, 1]");
  check(options.sun_elevation_deg > 0.0 && options.sun_elevation_deg <= 90.0,
        "render: sun_elevation_deg must be in (0, 90]");
  check(options.noise_sigma_dn >= 0.0, "render: noise_sigma_dn must be >= 0");
  check(options.exposure_dn > 0.0, "render: exposure_dn must be positive");
  check(options.regolith_contrast >= 0.0 && std::isfinite(options.regolith_contrast),
        "render: regolith_contrast must be >= 0");
  check(options.regolith_correlation_m > 0.0 && options.regolith_correlation_m <= 100.0,
        "render: regolith_correlation_m must be in (0, 100] m");
  check(options.opposition_surge >= 0.0 && options.opposition_surge <= 10.0,
        "render: opposition_surge must be in [0, 10]");
  check(options.opposition_width_deg > 0.0 && options.opposition_width_deg <= 90.0,
        "render: opposition_width_deg must be in (0, 90]");

  const double el = options.sun_elevation_deg * kPi / 180.0;
  const double az = options.sun_azimuth_deg * kPi / 180.0;
  sun_W_ = Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                           std::sin(el));
  flat_shading_ = options.ambient + (1.0 - options.ambient) * std::sin(el);
}

double Renderer::albedo(const RayHit& hit, double footprint_m) const {
  const bool rock = hit.rock_index >= 0;
  // Rocks and ground get unrelated patterns; each rock is offset so rocks differ.
  const std::uint64_t key =
      rock ? hash_combine(texture_seed_, 1000 + static_cast<std::uint64_t>(hit.rock_index))
           : texture_seed_;
  const bool regolith = options_.albedo_model == AlbedoModel::regolith;
  const int octaves = regolith ? kRegolithOctaves : options_.texture_octaves;
  double wavelength_m =
      regolith ? options_.regolith_correlation_m : options_.texture_min_wavelength_m;
  // Octave amplitudes: equal (value_noise) or doubling with the wavelength (regolith);
  // normalised so that the sum has unit variance when every octave is present.
  double amplitude = 1.0;
  double sum = 0.0;
  double sum_sq_amplitudes = 0.0;
  for (int k = 0; k < octaves; ++k, wavelength_m *= 2.0) {
    if (regolith && k > 0) amplitude *= 2.0;
    sum_sq_amplitudes += amplitude * amplitude;
    const double w = octave_weight(wavelength_m, footprint_m);
    if (w <= 0.0) continue;
    const std::uint64_t octave_key = hash_combine(key, static_cast<std::uint64_t>(k));
    const Eigen::Vector3d q = hit.p_W / wavelength_m;
    sum += amplitude * w *
           (rock ? value_noise_3d(q.x(), q.y(), q.z(), octave_key) / kValueNoise3dStd
                 : value_noise_2d(q.x(), q.y(), octave_key) / kValueNoise2dStd);
  }
  const double mean = rock ? options_.rock_albedo : options_.ground_albedo;
  if (regolith) {
    const double n = std::sqrt(sum_sq_amplitudes);
    return std::max(0.0, mean * (1.0 + options_.regolith_contrast * sum / n));
  }
  const double n = options_.texture_octaves > 0 ? std::sqrt(options_.texture_octaves) : 1.0;
  return std::max(0.0, mean * (1.0 + options_.texture_contrast * sum / n));
}

bool Renderer::in_rock_shadow(const RayHit& hit) const {
  const auto& rocks = terrain_.rocks();
  const RockGrid& grid = terrain_.rock_grid();
  // Above the highest rock top the sun ray cannot meet a rock: that bounds its length.
  if (rocks.empty() || hit.p_W.z() >= grid.max_top_z_m()) return false;
  const double t_max = (grid.max_top_z_m() - hit.p_W.z()) / sun_W_.z();
  bool shadowed = false;
  grid.traverse(hit.p_W, sun_W_, t_max, [&](const int* begin, const int* end, double) {
    for (const int* i = begin; i != end; ++i) {
      if (*i == hit.rock_index) continue;  // self-shadow is n . s < 0
      const auto k = static_cast<std::size_t>(*i);
      const double t = ray_sphere_entry(hit.p_W, sun_W_, terrain_.rock_center_W(k),
                                        rocks[k].radius_m);
      if (!std::isfinite(t)) continue;
      const Eigen::Vector3d p = hit.p_W + t * sun_W_;
      if (p.z() >= terrain_.ground_height_m(p.x(), p.y())) {
        shadowed = true;
        return false;
      }
    }
    return true;
  });
  return shadowed;
}

bool Renderer::in_terrain_shadow(const RayHit& hit) const {
  const Eigen::Vector3d o = hit.p_W + kShadowBiasM * hit.normal_W;
  // Above the highest ground and rock top nothing can block the sun: that bounds the ray.
  const double top_z =
      std::max(terrain_.max_ground_height_m(), terrain_.rock_grid().max_top_z_m());
  RayCastOptions shadow_ray = options_.ray_cast;
  if (std::isfinite(top_z)) {
    if (o.z() >= top_z) return false;
    shadow_ray.max_range_m = std::min(shadow_ray.max_range_m, (top_z - o.z()) / sun_W_.z());
  }
  return cast_ray(terrain_, o, sun_W_, shadow_ray).has_value();
}

bool Renderer::in_shadow(const RayHit& hit) const {
  if (options_.terrain_shadows) return in_terrain_shadow(hit);
  return options_.cast_shadows && in_rock_shadow(hit);
}

double Renderer::radiance(const RayHit& hit, double footprint_m,
                          const Eigen::Vector3d* view_W) const {
  double shading = flat_shading_;
  if (options_.sun_shading) {
    double direct = std::max(0.0, hit.normal_W.dot(sun_W_));
    if (direct > 0.0 && in_shadow(hit)) direct = 0.0;
    shading = options_.ambient + (1.0 - options_.ambient) * direct;
  }
  double value = options_.exposure_dn * albedo(hit, footprint_m) * shading / flat_shading_;
  if (options_.opposition_surge > 0.0 && view_W != nullptr) {
    const double phase_rad = std::acos(std::clamp(view_W->dot(sun_W_), -1.0, 1.0));
    const double width_rad = options_.opposition_width_deg * kPi / 180.0;
    value *= 1.0 + options_.opposition_surge * std::exp(-phase_rad / width_rad);
  }
  return value;
}

cv::Mat Renderer::render(const PinholeCamera& camera, const Pose3d& T_W_C,
                         std::uint64_t noise_key, const CameraResponse& response) const {
  check(camera.width_px > 0 && camera.height_px > 0 && camera.fx_px > 0.0 && camera.fy_px > 0.0,
        "render: camera needs a positive size and focal length");
  validate(response);
  const bool legacy = response.is_identity();
  const bool twelve_bit = response.bits == 12;
  cv::Mat image(camera.height_px, camera.width_px, twelve_bit ? CV_16UC1 : CV_8UC1);
  const int n = options_.samples_per_axis;
  const Eigen::Matrix3d R_W_C = T_W_C.linear();
  const Eigen::Vector3d o_W = T_W_C.translation();
  const double sample_angle_rad = 1.0 / (std::min(camera.fx_px, camera.fy_px) * n);
  const double max_dn = twelve_bit ? 4095.0 : 255.0;
  const double scale = response.gain * response.exposure;
  // Vignetting: radius squared of the farthest image corner from the principal point.
  const double corner_x = std::max(camera.cx_px + 0.5, camera.width_px - 0.5 - camera.cx_px);
  const double corner_y = std::max(camera.cy_px + 0.5, camera.height_px - 0.5 - camera.cy_px);
  const double corner_r2 = corner_x * corner_x + corner_y * corner_y;
  const double read_var = options_.noise_sigma_dn * options_.noise_sigma_dn;

  cv::parallel_for_(cv::Range(0, camera.height_px), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < camera.width_px; ++u) {
        double sum_dn = 0.0;
        for (int sy = 0; sy < n; ++sy) {
          for (int sx = 0; sx < n; ++sx) {
            const Eigen::Vector3d d_C =
                camera.ray_C(u + (sx + 0.5) / n - 0.5, v + (sy + 0.5) / n - 0.5);
            const Eigen::Vector3d d_W = (R_W_C * d_C).normalized();
            const auto hit = cast_ray(terrain_, o_W, d_W, options_.ray_cast);
            if (!hit) continue;  // sky: black
            // Ray footprint: angular spacing (smaller off-axis by 1/|d_C|), stretched
            // by the incidence angle; capped at grazing incidence.
            const double cos_incidence = std::max(std::abs(d_W.dot(hit->normal_W)), 0.05);
            const double footprint_m =
                hit->range_m * sample_angle_rad / d_C.norm() / cos_incidence;
            const Eigen::Vector3d view_W = -d_W;
            sum_dn += radiance(*hit, footprint_m, &view_W);
          }
        }
        const std::uint64_t pixel = static_cast<std::uint64_t>(v) * camera.width_px + u;
        const double gauss = gaussian_from_hash(hash_combine(noise_key, pixel));
        if (legacy) {  // the images of earlier versions, bit for bit
          image.ptr<unsigned char>(v)[u] =
              cv::saturate_cast<unsigned char>(sum_dn / (n * n) + options_.noise_sigma_dn * gauss);
          continue;
        }
        double signal_dn = scale * sum_dn / (n * n);
        if (response.vignetting > 0.0) {
          const double du = u - camera.cx_px;
          const double dv = v - camera.cy_px;
          signal_dn *= 1.0 - response.vignetting * (du * du + dv * dv) / corner_r2;
        }
        const double shot_var =
            response.electrons_per_dn > 0.0 ? signal_dn / response.electrons_per_dn : 0.0;
        const double dn = std::clamp(
            std::round(signal_dn + response.offset_dn + std::sqrt(read_var + shot_var) * gauss),
            0.0, max_dn);
        if (twelve_bit)  // left-justified in 16 bits, as 12-bit cameras deliver them
          image.ptr<std::uint16_t>(v)[u] = static_cast<std::uint16_t>(dn * 16.0);
        else
          image.ptr<unsigned char>(v)[u] = static_cast<unsigned char>(dn);
      }
    }
  });
  return image;
}

cv::Mat Renderer::render_depth(const PinholeCamera& camera, const Pose3d& T_W_C) const {
  check(camera.width_px > 0 && camera.height_px > 0 && camera.fx_px > 0.0 && camera.fy_px > 0.0,
        "render_depth: camera needs a positive size and focal length");
  cv::Mat depth(camera.height_px, camera.width_px, CV_32FC1);
  const Eigen::Matrix3d R_W_C = T_W_C.linear();
  const Eigen::Vector3d o_W = T_W_C.translation();
  cv::parallel_for_(cv::Range(0, camera.height_px), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      auto* out = depth.ptr<float>(v);
      for (int u = 0; u < camera.width_px; ++u) {
        const Eigen::Vector3d d_C = camera.ray_C(u, v);
        const auto hit = cast_ray(terrain_, o_W, R_W_C * d_C, options_.ray_cast);
        // Z of the hit in C: range along the unit ray times that ray's z component.
        out[u] = hit ? static_cast<float>(hit->range_m / d_C.norm())
                     : std::numeric_limits<float>::quiet_NaN();
      }
    }
  });
  return depth;
}

}  // namespace hazmap::sim
