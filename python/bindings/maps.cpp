// Config, Calibration, Pipeline, LayerStack and their grids as numpy views.

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/hazard/mapper.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/pipeline/pipeline.hpp"
#include "hazmap/rules/rule_registry.hpp"

namespace hazmap::python {
namespace {

/// "Update rule: bananas, kalman, omg or ccm.": the registry's names (rule_registry.hpp).
const char* rule_doc() {
  static const std::string doc = [] {
    const std::vector<const char*> names = rule_names();
    std::string d = "Update rule: ";
    for (std::size_t i = 0; i < names.size(); ++i)
      d += std::string(i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return d + ".";
  }();
  return doc.c_str();
}

/// What Layer and PlannerMaps objects read: the grids of a Pipeline or a LayerStack as
/// they stand after its last frame. The grids are allocated by the first frame and
/// overwritten in place by every later one (HazardStage keeps its buffers), so a numpy
/// view of them stays valid for the owner's lifetime.
class MapSource {
 public:
  virtual ~MapSource() = default;
  virtual const Config& config() const = 0;
  virtual const HazardStage& hazards() const = 0;
  int frames() const { return frames_.load(); }
  /// Before the first frame every grid is empty: say so rather than hand out nothing.
  void require_frame() const {
    if (frames() == 0)
      throw Error("no frame processed yet: the grids exist after the first process() or insert()");
  }

 protected:
  /// One frame at a time per object: the GIL is released while a frame runs, so another
  /// Python thread could otherwise start a second one on the same buffers.
  std::mutex frame_mutex_;
  std::atomic<int> frames_{0};
};

class PyPipeline : public MapSource {
 public:
  PyPipeline(const Config& config, const StereoCalibration& calibration)
      : pipeline_(config, calibration) {}
  const Config& config() const override { return pipeline_.config(); }
  const HazardStage& hazards() const override { return pipeline_.hazard_stage(); }
  const Pipeline& pipeline() const { return pipeline_; }

  FrameReport process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B,
                      const PoseNoise& noise) {
    std::lock_guard<std::mutex> lock(frame_mutex_);
    const FrameReport report = pipeline_.process(left, right, T_W_B, noise);
    ++frames_;
    return report;
  }

 private:
  Pipeline pipeline_;
};

/// The map half of Pipeline::process for points that come from elsewhere: the core's
/// Mapper (hazard/mapper.hpp), the object Pipeline itself uses after stereo.
class PyLayerStack : public MapSource {
 public:
  explicit PyLayerStack(const Config& config)
      : config_(config), mapper_(config, config.pose_uncertainty.enabled) {}
  const Config& config() const override { return config_; }
  const HazardStage& hazards() const override { return mapper_.hazards(); }
  const Mapper& mapper() const { return mapper_; }

  std::size_t insert(const PointCloud& cloud, double robot_x_m, double robot_y_m,
                     const PoseNoise& noise) {
    std::lock_guard<std::mutex> lock(frame_mutex_);
    const std::size_t updates = mapper_.insert(cloud, robot_x_m, robot_y_m, noise);
    mapper_.classify();
    ++frames_;
    return updates;
  }

 private:
  Config config_;
  Mapper mapper_;
};

/// A Python Layer: layer `index` of `source`, holding `owner` (the Pipeline or LayerStack
/// object) so that the layer and every array it hands out keep the grids alive.
struct LayerHandle {
  py::object owner;
  const MapSource* source;
  std::size_t index;
  const LayerView& view() const { return source->hazards().layers()[index]; }
  const LayerHazardParams& params() const { return source->hazards().params().layers[index]; }
};

struct PlannerHandle {
  py::object owner;
  const MapSource* source;
  const PlannerMaps& maps() const { return source->hazards().planner_maps(); }
};

struct LayerGridField {
  const char* name;
  DenseGrid LayerGrids::*grid;
  const char* doc;
};
/// Every grid a layer exports (layer.hpp's LayerGrids), one line each.
const LayerGridField kLayerGrids[] = {
    {"height", &LayerGrids::height, "Height at the cell centre [m]; NaN unknown. CCM: the cell plane there when evaluable."},
    {"variance", &LayerGrids::variance, "Height variance [m^2] as the map holds it (the CLI's L<i>_variance adds published_extra_variance_m2: see published_variance())."},
    {"count", &LayerGrids::count, "Points behind each cell."},
    {"slope_x", &LayerGrids::slope_x, "CCM: dz/dx of the cell plane, NaN when not evaluable; None for other rules."},
    {"slope_y", &LayerGrids::slope_y, "CCM: dz/dy of the cell plane; None for other rules."},
    {"roughness", &LayerGrids::roughness, "CCM: plane-normal variance rho [m^2]; None for other rules."},
    {"coverage", &LayerGrids::coverage, "CCM: coverage kappa; None for other rules."},
    {"evaluable", &LayerGrids::evaluable, "CCM: 1 evaluable, 0 not, 0.5 a plane from a hole-free view (map.layers.N.hole_free_coverage) for the cell's own tests only; None for other rules."},
    {"noise_variance", &LayerGrids::noise_variance, "CCM: mean measurement height variance of the cell's points [m^2]; None otherwise."},
    {"lateral_xx", &LayerGrids::lateral_xx, "CCM: lateral covariance S/W, xx [m^2]; None otherwise."},
    {"lateral_yy", &LayerGrids::lateral_yy, "CCM: lateral covariance, yy [m^2]; None otherwise."},
    {"lateral_xy", &LayerGrids::lateral_xy, "CCM: lateral covariance, xy [m^2]; None otherwise."},
    {"lateral_xz", &LayerGrids::lateral_xz, "CCM: lateral-height covariance Sxz/W [m^2]; None otherwise."},
    {"lateral_yz", &LayerGrids::lateral_yz, "CCM: lateral-height covariance Syz/W [m^2]; None otherwise."},
};

struct DiagnosticField {
  const char* name;
  DenseGrid HazardDiagnostics::*grid;
  const char* doc;
};
/// The classifier's intermediate grids (hazard_classifier.hpp).
const DiagnosticField kDiagnostics[] = {
    {"kernel_range", &HazardDiagnostics::kernel_range, "Piecewise constant: max - min of the heights in the kernel [m]."},
    {"kernel_sigma", &HazardDiagnostics::kernel_sigma, "Its standard deviation [m]."},
    {"kernel_fill", &HazardDiagnostics::kernel_fill, "Observed fraction of the kernel."},
    {"kernel_slope", &HazardDiagnostics::kernel_slope, "Detrended kernels: tan of the kernel plane's inclination; None otherwise."},
    {"kernel_slope_sigma", &HazardDiagnostics::kernel_slope_sigma, "Detrended kernels: its standard deviation; None otherwise."},
};

/// (x_min, x_max, y_min, y_max) of a grid in W [m]: matplotlib's imshow extent for the
/// grid's image order (row 0 = largest y, origin="upper").
py::tuple extent_of(const DenseGrid& g) {
  const double half_w = 0.5 * g.cols * g.resolution_m, half_h = 0.5 * g.rows * g.resolution_m;
  return py::make_tuple(g.center_x_m - half_w, g.center_x_m + half_w, g.center_y_m - half_h,
                        g.center_y_m + half_h);
}

/// Geometry properties shared by Layer and PlannerMaps, read from the grid `grid_of` returns.
template <class Handle, class Class, class GridOf>
void def_geometry(Class& cls, GridOf grid_of) {
  cls.def_property_readonly("resolution_m", [grid_of](const Handle& h) { return grid_of(h).resolution_m; },
                            "Cell side [m].");
  cls.def_property_readonly("shape", [grid_of](const Handle& h) {
        return py::make_tuple(grid_of(h).rows, grid_of(h).cols);
      }, "(rows, cols) of every grid.");
  cls.def_property_readonly("center_m", [grid_of](const Handle& h) {
        return py::make_tuple(grid_of(h).center_x_m, grid_of(h).center_y_m);
      }, "W (x, y) of the grids' geometric centre [m].");
  cls.def_property_readonly("extent_m", [grid_of](const Handle& h) { return extent_of(grid_of(h)); },
                            "(x_min, x_max, y_min, y_max) in W [m]. Row 0 holds the largest y and "
                            "column 0 the smallest x, so plt.imshow(grid, extent=extent_m) draws "
                            "it in W.");
}

/// layers, layer(i), planner, config, frames: what a Pipeline and a LayerStack share.
template <class T, class Class>
void def_map_source(Class& cls) {
  cls.def_property_readonly("frames", [](const T& s) { return s.frames(); },
                            "Frames processed so far.");
  cls.def_property_readonly("config", [](const T& s) { return s.config(); },
                            "A copy of the configuration in use.");
  cls.def("layer", [](py::object self, int i) {
        const T& s = self.cast<const T&>();
        s.require_frame();
        const int n = static_cast<int>(s.hazards().layers().size());
        if (i < 0) i += n;  // Python-like: -1 is the coarsest
        if (i < 0 || i >= n)
          throw py::index_error("layer " + std::to_string(i) + " of " + std::to_string(n));
        return LayerHandle{self, &s, static_cast<std::size_t>(i)};
      }, py::arg("index"), "Layer `index` (0 = finest; negative counts from the coarsest).");
  cls.def_property_readonly("layers", [](py::object self) {
        const T& s = self.cast<const T&>();
        s.require_frame();
        std::vector<LayerHandle> out;
        for (std::size_t i = 0; i < s.hazards().layers().size(); ++i)
          out.push_back(LayerHandle{self, &s, i});
        return out;
      }, "Every layer, finest first. Raises hazmap.Error before the first frame.");
  cls.def_property_readonly("planner", [](py::object self) {
        const T& s = self.cast<const T&>();
        s.require_frame();
        return PlannerHandle{self, &s};
      }, "The fused hazard, clearance, footprint and hazard-distance maps (SPEC 8.4, 8.5).");
}

py::dict report_dict(const FrameReport& r) {
  py::dict ms;
  ms["rectify"] = r.ms.rectify_ms;
  ms["disparity"] = r.ms.disparity_ms;
  ms["points"] = r.ms.points_ms;
  ms["map"] = r.ms.map_ms;
  ms["hazard"] = r.ms.hazard_ms;
  ms["total"] = r.ms.total();
  py::dict d;
  d["points"] = r.points;
  d["updates"] = r.updates;
  d["points_below_ground"] = r.points_below_ground;
  d["points_occluded"] = r.points_occluded;
  d["disparities_unsupported"] = r.disparities_unsupported;
  d["gated_std"] = r.gated.std_gate;
  d["gated_consistency"] = r.gated.consistency_gate;
  d["ms"] = ms;
  return d;
}

void bind_layer_classes(py::module_& m) {
  py::class_<LayerHandle> layer(m, "Layer", R"(One map layer after the owner's last frame.

Every grid is a read-only float32 numpy array of shape `shape` in image order (row 0 =
largest y, column 0 = smallest x), a view of the owner's buffer without a copy: the
layer's ring buffer is exported into these dense grids once per frame by the pipeline
itself (that copy is the library's, not the binding's). The arrays keep the owner alive,
and show its current frame: the next process()/insert() overwrites them in place, so
call .copy() on what you want to keep. Grids a rule does not fill are None.)");
  for (const LayerGridField& f : kLayerGrids) {
    const auto grid = f.grid;
    layer.def_property_readonly(f.name, [grid](const LayerHandle& h) {
      return grid_view(h.view().map.*grid, h.owner);
    }, f.doc);
  }
  for (const DiagnosticField& f : kDiagnostics) {
    const auto grid = f.grid;
    layer.def_property_readonly(f.name, [grid](const LayerHandle& h) {
      return grid_view(h.view().diagnostics.*grid, h.owner);
    }, f.doc);
  }
  layer.def_property_readonly("hazard", [](const LayerHandle& h) {
    return grid_view(h.view().hazard, h.owner);
  }, "Hazard class per cell: hazmap.UNKNOWN (0), TRAVERSABLE (1), HAZARD (2), as float32.");
  layer.def_property_readonly(
      "viewed", [](const LayerHandle& h) { return grid_view(h.view().viewed, h.owner); },
      "How much of each cell the stereo pair has looked at: 0 never, 1 partly, 2 wholly "
      "(hazard.partial_ring_proof: view_edge); None otherwise.");
  layer.def_property_readonly(
      "seen_whole", [](const LayerHandle& h) { return grid_view(h.view().seen_whole, h.owner); },
      "Hole-free marks: 0 none, 1 a frame's disparity image saw the cell whole, 2 a hole seen "
      "(final) (map.layers.N.hole_free_coverage); None otherwise.");
  layer.def("grids", [](const LayerHandle& h) {
    py::dict d;
    for (const LayerGridField& f : kLayerGrids)
      if ((h.view().map.*f.grid).rows > 0) d[f.name] = grid_view(h.view().map.*f.grid, h.owner);
    for (const DiagnosticField& f : kDiagnostics)
      if ((h.view().diagnostics.*f.grid).rows > 0)
        d[f.name] = grid_view(h.view().diagnostics.*f.grid, h.owner);
    d["hazard"] = grid_view(h.view().hazard, h.owner);
    return d;
  }, "Every grid this layer fills, by name (views, as the properties).");
  layer.def("published_variance", [](const LayerHandle& h) {
    // As the output writer publishes it: float(double(v) + extra), NaN stays NaN.
    const DenseGrid& v = h.view().map.variance;
    const double extra = h.params().published_extra_variance_m2;
    py::array_t<float> out({v.rows, v.cols});
    float* o = out.mutable_data();
    for (std::size_t i = 0; i < v.values.size(); ++i) o[i] = static_cast<float>(v.values[i] + extra);
    return out;
  }, "variance + published_extra_variance_m2 (a copy): what L<i>_variance.jdem holds.");
  def_geometry<LayerHandle>(layer, [](const LayerHandle& h) -> const DenseGrid& { return h.view().hazard; });
  layer.def_readonly("index", &LayerHandle::index, "0 = finest.");
  layer.def_property_readonly("rule", [](const LayerHandle& h) {
    return std::string(rule_name(h.source->config().map.layers[h.index].rule));
  }, rule_doc());
  layer.def_property_readonly("h_min_m", [](const LayerHandle& h) { return h.params().h_min_m; },
                              "Smallest obstacle this layer vouches for [m] (SPEC 8).");
  layer.def_property_readonly("published_extra_variance_m2", [](const LayerHandle& h) {
    return h.params().published_extra_variance_m2;
  }, "Added to the variance where it is published (hazard_params.hpp) [m^2].");
  layer.def("__repr__", [](const LayerHandle& h) {
    const DenseGrid& g = h.view().hazard;
    return "<hazmap.Layer " + std::to_string(h.index) + ": " +
           rule_name(h.source->config().map.layers[h.index].rule) + ", " + std::to_string(g.rows) +
           " x " + std::to_string(g.cols) + " cells of " + std::to_string(g.resolution_m) + " m>";
  });

  py::class_<PlannerHandle> planner(m, "PlannerMaps", R"(The maps a planner consumes (SPEC 8.4, 8.5),
at the finest layer's resolution; read-only views like Layer's grids, all of one geometry.)");
  planner.def_property_readonly("fused", [](const PlannerHandle& h) { return grid_view(h.maps().fused, h.owner); },
                                "Fused hazard class (hazmap.UNKNOWN / TRAVERSABLE / HAZARD).");
  planner.def_property_readonly("clearance", [](const PlannerHandle& h) { return grid_view(h.maps().clearance, h.owner); },
                                "[m], NaN where no layer proves the cell traversable.");
  planner.def_property_readonly("footprint", [](const PlannerHandle& h) { return grid_view(h.maps().footprint, h.owner); },
                                "Hazard class for the rover's centre.");
  planner.def_property_readonly("hazard_distance", [](const PlannerHandle& h) {
    return grid_view(h.maps().hazard_distance, h.owner);
  }, "[m] to the nearest fused hazard cell, capped.");
  def_geometry<PlannerHandle>(planner, [](const PlannerHandle& h) -> const DenseGrid& { return h.maps().fused; });
}

/// Config and the functions that make one.
void bind_config(py::module_& m) {
  py::class_<Config>(m, "Config", "A validated run configuration (SPEC 13); see load_config.")
      .def("to_yaml", [](const Config& c) { return to_yaml(c); },
           "The configuration as YAML, every key with the value in use.")
      .def_property_readonly("layers", [](const Config& c) {
        py::list out;
        for (const LayerConfig& l : c.map.layers) {
          py::dict d;
          d["resolution_m"] = l.resolution_m;
          d["size"] = l.size;
          d["rule"] = rule_name(l.rule);
          out.append(d);
        }
        return out;
      }, "map.layers in brief: resolution_m, size (cells per side) and rule of each.")
      .def("__repr__", [](const Config& c) {
        return "<hazmap.Config: " + std::to_string(c.map.layers.size()) + " layers>";
      });
  m.def("load_config", [](const std::filesystem::path& path, const std::vector<std::string>& overrides) {
    return load_config(path, overrides);
  }, py::arg("path"), py::arg("overrides") = std::vector<std::string>{},
        R"(Reads a YAML configuration and applies `overrides`, each "dotted.key=value" exactly
as `hazmap run --set` takes it (e.g. "map.layers.0.size=64"); validates the result.
Raises hazmap.Error naming the file, line or key.)");
  m.def("parse_config", [](const std::string& text, const std::vector<std::string>& overrides,
                           const std::string& source) { return parse_config(text, source, overrides); },
        py::arg("yaml_text"), py::arg("overrides") = std::vector<std::string>{},
        py::arg("source") = "<string>", "As load_config, from YAML text.");
}

/// Calibration and load_calibration.
void bind_calibration(py::module_& m) {
  py::class_<StereoCalibration>(m, "Calibration", "A stereo calibration (SPEC 2); see load_calibration.")
      .def_readonly("image_width", &StereoCalibration::image_width)
      .def_readonly("image_height", &StereoCalibration::image_height)
      .def_readonly("rectified", &StereoCalibration::rectified)
      .def_readonly("source", &StereoCalibration::source)
      .def("__repr__", [](const StereoCalibration& c) {
        return "<hazmap.Calibration " + std::to_string(c.image_width) + "x" +
               std::to_string(c.image_height) + " from " + c.source + ">";
      });
  m.def("load_calibration", &load_stereo_calibration, py::arg("path"),
        "Reads calibration.yaml (ours, or OpenCV's FileStorage layout).");
}

/// Pipeline: stereo pairs in, the maps out.
void bind_pipeline(py::module_& m) {
  py::class_<PyPipeline> pipeline(m, "Pipeline", R"(The per-frame path of `hazmap run`: grey
conversion, rectification, disparity, points, map insertion, hazards. Not for use by two
threads at once (a second process() waits for the first; reading grids meanwhile sees a
frame in the making).)");
  pipeline.def(py::init<const Config&, const StereoCalibration&>(), py::arg("config"), py::arg("calibration"));
  pipeline.def(py::init([](const Config& config, const std::filesystem::path& calibration) {
    return std::make_unique<PyPipeline>(config, load_stereo_calibration(calibration));
  }), py::arg("config"), py::arg("calibration"), "`calibration` may be a calibration.yaml path.");
  pipeline.def("process", [](PyPipeline& p, const py::handle& left, const py::handle& right,
                             const py::handle& pose, const py::handle& noise) {
    py::array keep_left, keep_right;
    const cv::Mat l = image_from_numpy(left, "left", keep_left);
    const cv::Mat r = image_from_numpy(right, "right", keep_right);
    const Pose3d T_W_B = pose_from_python(pose);
    const PoseNoise n = noise_from_python(noise);
    FrameReport report;
    {
      py::gil_scoped_release release;  // before taking the frame lock: see MapSource
      report = p.process(l, r, T_W_B, n);
    }
    return report_dict(report);
  }, py::arg("left"), py::arg("right"), py::arg("pose"), py::arg("noise") = py::none(),
     R"(Maps one stereo pair taken at body pose `pose` and returns the frame's report.

left, right: numpy uint8 or uint16 images of the calibrated size, H x W grey or
    H x W x 3 BGR (x 4 BGRA); both of one dtype and channel count.
pose: T_W_B as a 4 x 4 array, or 7 numbers x y z qx qy qz qw (poses.txt's order).
noise: None, or sx sy sz [m] syaw [rad]: pose noise added since the previous frame
    (used when pose_uncertainty.enabled).
Returns {points, updates, points_below_ground, points_occluded, disparities_unsupported,
gated_std, gated_consistency, ms: {rectify, disparity, points, map, hazard, total}}.)");
  pipeline.def("points", [](const PyPipeline& p) {
    return numpy_from_cloud(p.pipeline().cloud());
  }, "The last frame's points as (N x 3 p_W [m], N x 6 covariance xx xy xz yy yz zz [m^2]), "
     "float32 copies: what LayerStack.insert takes.");
  pipeline.def("disparity_x16", [](const PyPipeline& p) { return numpy_from_mat(p.pipeline().disparity_x16()); },
               "The last frame's disparity in 1/16 px (int16, a copy); invalid < 0.");
  pipeline.def("rectified", [](const PyPipeline& p) {
    return py::make_tuple(numpy_from_mat(p.pipeline().rectified_left()),
                          numpy_from_mat(p.pipeline().rectified_right()));
  }, "The last frame's rectified 8-bit grey pair (copies).");
  def_map_source<PyPipeline>(pipeline);
}

/// LayerStack: points in (no stereo), the same maps out.
void bind_layer_stack(py::module_& m) {
  py::class_<PyLayerStack> stack(m, "LayerStack", R"(The multi-resolution map and its hazard
stage without stereo: insert points from anywhere (a lidar, a simulation, a test) and read
the same grids a Pipeline gives. Same threading rules as Pipeline.)");
  stack.def(py::init<const Config&>(), py::arg("config"));
  stack.def("insert", [](PyLayerStack& s, const py::handle& points, const py::handle& covariances,
                         const py::handle& robot_xy, const py::handle& noise) {
    PointCloud cloud;
    cloud_from_numpy(points, covariances, cloud);
    std::vector<double> xy;
    try {
      xy = robot_xy.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
      throw py::type_error("robot_xy: expected 2 numbers (x, y) in W [m]");
    }
    if (xy.size() != 2 || !std::isfinite(xy[0]) || !std::isfinite(xy[1]))
      throw py::value_error("robot_xy: expected 2 finite numbers (x, y) in W [m]");
    const PoseNoise n = noise_from_python(noise);
    std::size_t updates;
    {
      py::gil_scoped_release release;
      updates = s.insert(cloud, xy[0], xy[1], n);
    }
    py::dict d;
    d["points"] = cloud.size();
    d["updates"] = updates;
    const GateCounts& gated = s.mapper().gated();
    d["gated_std"] = gated.std_gate;
    d["gated_consistency"] = gated.consistency_gate;
    return d;
  }, py::arg("points"), py::arg("covariances"), py::arg("robot_xy"), py::arg("noise") = py::none(),
     R"(One frame of points: rolls every layer's window to centre on robot_xy, inserts the
points into every layer (their rules, gates and insertion mode as configured) and
re-runs the hazard stage, exactly as Pipeline.process does after stereo.

points: N x 3 positions p_W [m].
covariances [m^2]: (N,) isotropic variance, (N, 3) diagonal, (N, 6) upper triangle
    xx xy xz yy yz zz, or (N, 3, 3); the diagonal must be > 0.
robot_xy: (x, y) of the body in W [m]: the windows' centre.
noise: as Pipeline.process.
Returns {points, updates, gated_std, gated_consistency}.)");
  def_map_source<PyLayerStack>(stack);
}

}  // namespace

void bind_maps(py::module_& m) {
  bind_config(m);
  bind_calibration(m);
  bind_layer_classes(m);
  bind_pipeline(m);
  bind_layer_stack(m);
}

}  // namespace hazmap::python
