#pragma once
// Fixtures of the simulator's tests: a small fast sequence, and a uniformly lit flat scene.

#include "hazmap/sim/renderer.hpp"
#include "hazmap/sim/simulate.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::testing {

constexpr double kTestScale = 0.1;  // 160 x 130 px: fast

/// Two frames at kTestScale over a 6 m terrain, every other option at its default.
inline sim::SimulationOptions small_options() {
  sim::SimulationOptions options;
  options.scale = kTestScale;
  options.frames = 2;
  options.terrain_size_m = 6.0;
  return options;
}

/// Flat ground rendered without albedo texture or sun shading: every ground ray has the
/// radiance exposure_dn * ground_albedo (100 DN by default), and what an image adds to it
/// is the camera's and the noise's.

struct UniformFlatScene {
  using Terrain = sim::Terrain;
  using RenderOptions = sim::RenderOptions;
  using Renderer = sim::Renderer;

  Terrain terrain;
  RenderOptions options;
  Renderer renderer;  ///< texture seed 1 (irrelevant: no texture)

  explicit UniformFlatScene(double noise_sigma_dn,
                            int samples_per_axis = RenderOptions{}.samples_per_axis)
      : terrain(flat_terrain()),
        options(uniform_options(noise_sigma_dn, samples_per_axis)),
        renderer(terrain, options, 1) {}
  // The renderer refers to `terrain`: the scene stays where it was made.
  UniformFlatScene(const UniformFlatScene&) = delete;
  UniformFlatScene& operator=(const UniformFlatScene&) = delete;

 private:
  static Terrain flat_terrain() {
    sim::TerrainOptions terrain_options;
    terrain_options.scenario = "flat";
    return sim::make_terrain(terrain_options);
  }
  static RenderOptions uniform_options(double noise_sigma_dn, int samples_per_axis) {
    RenderOptions o;
    o.texture_contrast = 0.0;
    o.sun_shading = false;
    o.noise_sigma_dn = noise_sigma_dn;
    o.samples_per_axis = samples_per_axis;
    return o;
  }
};

}  // namespace hazmap::testing
