"""Tests of the Python bindings (python/), run by ctest with PYTHONPATH=<build>/python.

Each TestCase is one ctest (python.<Case>): `test_bindings.py <Case>` runs it alone.
Environment: HAZMAP_SOURCE_DIR (the repository), HAZMAP_CLI (the hazmap executable).
"""

import gc
import os
import subprocess
import sys
import tempfile
import unittest
import weakref

import numpy as np

import hazmap

SOURCE_DIR = os.environ.get("HAZMAP_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.environ.get("HAZMAP_CLI", os.path.join(SOURCE_DIR, "build", "hazmap"))
SAMPLE = os.path.join(SOURCE_DIR, "data", "sample")
DEFAULT_CONFIG = os.path.join(SOURCE_DIR, "config", "default.yaml")

# Points are stored as float32 (Measurement): a coordinate near 1 m carries ~1e-7 m of
# rounding, a cell mean of 16 such points about as much; 10 um is far above that and far
# below any error the map could make by placing a point in the wrong cell (>= 1 mm here).
HEIGHT_TOLERANCE_M = 1e-5
# A CCM plane's slope from 256 float32 points spread over 8 cm: rounding of 1e-7 m over a
# lever of centimetres.
SLOPE_TOLERANCE = 1e-4
# Relative float32 rounding of a variance accumulated in float (precision sums).
VARIANCE_RELATIVE_TOLERANCE = 1e-5

# Two layers, a piecewise-constant (Kalman) one and a plane (CCM) one; no time inflation,
# so that a cell's variance is exactly that of its points' weighted mean.
STACK_YAML = """
map:
  layers:
    - {resolution: 0.02, size: 64, rule: kalman, hazard: {kernel: 5}}
    - {resolution: 0.08, size: 16, rule: ccm}
rules:
  kalman: {time_inflation: 0, min_variance: 1.0e-9}
"""
POINTS_PER_CELL_SIDE = 4  # lattice points per fine cell and axis, symmetric about its centre


def cell_centres(layer):
    """W (x, y) of every cell centre, from the layer's extent (row 0 = largest y)."""
    x_min, _, _, y_max = layer.extent_m
    rows, cols = layer.shape
    r = layer.resolution_m
    x = x_min + (np.arange(cols) + 0.5) * r
    y = y_max - (np.arange(rows) + 0.5) * r
    return np.meshgrid(x, y)


def plane_points(height_of, half_extent_m, spacing_m):
    """A square lattice of points on z = height_of(x, y): coordinates (k + 1/2) spacing, so
    that each cell (boundaries at multiples of the resolution) holds a block of points
    symmetric about its centre."""
    k = np.arange(-int(round(half_extent_m / spacing_m)), int(round(half_extent_m / spacing_m)))
    x, y = np.meshgrid((k + 0.5) * spacing_m, (k + 0.5) * spacing_m)
    x, y = x.ravel(), y.ravel()
    return np.column_stack([x, y, height_of(x, y)])


class Plane(unittest.TestCase):
    """Points inserted straight into a LayerStack, on analytic surfaces."""

    A, B, C = 0.05, 0.04, -0.03  # z = A + B x + C y: 2.3 and 1.7 deg, far below max_slope
    VARIANCE_M2 = 1e-4           # every point's isotropic variance

    def plane(self, x, y):
        return self.A + self.B * x + self.C * y

    def insert_plane(self, height_of):
        stack = hazmap.LayerStack(hazmap.parse_config(STACK_YAML))
        fine = stack.config.layers[0]["resolution_m"]
        coarse_extent = stack.config.layers[1]["resolution_m"] * stack.config.layers[1]["size"]
        points = plane_points(height_of, coarse_extent / 2, fine / POINTS_PER_CELL_SIDE)
        report = stack.insert(points, np.full(len(points), self.VARIANCE_M2), robot_xy=(0.0, 0.0))
        self.assertEqual(report["points"], len(points))
        return stack

    def test_heights_equal_the_plane(self):
        stack = self.insert_plane(self.plane)
        kalman, ccm = stack.layers
        self.assertEqual((kalman.rule, ccm.rule), ("kalman", "ccm"))
        self.assertEqual(kalman.shape, (64, 64))
        self.assertAlmostEqual(kalman.resolution_m, 0.02)
        # Every cell of both windows is covered by the lattice.
        for layer in (kalman, ccm):
            x, y = cell_centres(layer)
            self.assertFalse(np.isnan(layer.height).any(), layer)
            np.testing.assert_allclose(layer.height, self.plane(x, y), rtol=0,
                                       atol=HEIGHT_TOLERANCE_M, err_msg=repr(layer))
        # Kalman: the variance of a mean of n points of variance v is v / n.
        n = POINTS_PER_CELL_SIDE ** 2
        np.testing.assert_allclose(kalman.variance, self.VARIANCE_M2 / n,
                                   rtol=VARIANCE_RELATIVE_TOLERANCE)
        # CCM: every cell's plane is the true one.
        self.assertTrue((ccm.evaluable == 1).all())
        np.testing.assert_allclose(ccm.slope_x, self.B, atol=SLOPE_TOLERANCE)
        np.testing.assert_allclose(ccm.slope_y, self.C, atol=SLOPE_TOLERANCE)
        self.assertIsNone(kalman.slope_x)  # a piecewise-constant layer has no plane
        # A gentle plane is traversable wherever the map knows it, and nowhere a hazard.
        for layer in (kalman, ccm):
            self.assertFalse((layer.hazard == hazmap.HAZARD).any(), layer)
            self.assertTrue((layer.hazard == hazmap.TRAVERSABLE).any(), layer)
        self.assertFalse((stack.planner.fused == hazmap.HAZARD).any())

    def test_step_is_a_hazard_at_its_edge(self):
        step_m, step_x_m = 0.10, 0.11  # a 10 cm step up at x = 0.11 m (mid-cell at 2 cm)
        stack = self.insert_plane(lambda x, y: self.plane(x, y) + step_m * (x > step_x_m))
        kalman = stack.layer(0)
        x, _ = cell_centres(kalman)
        hazard = kalman.hazard == hazmap.HAZARD
        self.assertTrue(hazard.any())
        # Hazards only within the roughness kernel's reach of the step (kernel 5: 2 cells)
        # plus the wheel ring's (half the wheelbase) for the ring tests.
        reach_m = 2 * kalman.resolution_m + 0.30 / 2
        self.assertLessEqual(np.abs(x[hazard] - step_x_m).max(), reach_m + kalman.resolution_m)
        # Every row whose kernel lies inside the window sees the step (the classifier leaves
        # the kernel radius at the window's edge unknown).
        radius = 5 // 2
        self.assertTrue(hazard[radius:-radius].any(axis=1).all())


def read_poses(path):
    """poses.txt (SPEC 2) parsed here, independently of the library: {name: 7 numbers}."""
    poses = {}
    with open(path) as f:
        for line in f:
            fields = line.split("#")[0].split()
            if fields:
                poses[fields[0]] = np.array([float(v) for v in fields[2:9]])
    return poses


def assert_same_grid(test, array, jdem_path):
    """`array` equals the CLI's JDEM cell for cell (NaN where it is NaN), geometry too."""
    values, header = hazmap.read_jdem(jdem_path)
    test.assertEqual(array.shape, values.shape, jdem_path)
    np.testing.assert_array_equal(array, values, err_msg=jdem_path)
    return header


class PipelineVsCli(unittest.TestCase):
    """Frames of data/sample fed as numpy images give the grids `hazmap run` writes."""

    FRAMES = 3
    # Two layers (a list value through the --set syntax), PNGs off to keep the run short.
    OVERRIDES = [
        "map.layers=[{resolution: 0.01, size: 96, rule: kalman, hazard: {kernel: 7}},"
        " {resolution: 0.04, size: 32, rule: ccm}]",
        "output.png=false",
    ]

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.run_dir = os.path.join(cls.tmp.name, "run")
        command = [CLI, "run", "--config", DEFAULT_CONFIG, "--sequence", SAMPLE, "--out",
                   cls.run_dir, "--frames", f"0:{cls.FRAMES}", "--quiet"]
        for o in cls.OVERRIDES:
            command += ["--set", o]
        subprocess.run(command, check=True)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_same_grids_as_the_cli(self):
        config = hazmap.load_config(DEFAULT_CONFIG, self.OVERRIDES)
        self.assertEqual([l["rule"] for l in config.layers], ["kalman", "ccm"])
        pipeline = hazmap.Pipeline(config, os.path.join(SAMPLE, "calibration.yaml"))
        stack = hazmap.LayerStack(config)  # fed the pipeline's own points
        poses = read_poses(os.path.join(SAMPLE, "poses.txt"))
        frames = hazmap.load_sequence(SAMPLE)["frames"][:self.FRAMES]
        for i, frame in enumerate(frames):
            left, right = hazmap.read_image(frame["left"]), hazmap.read_image(frame["right"])
            self.assertEqual(left.dtype, np.uint8)
            # Each input form must give the CLI's 8-bit grey frame exactly: grey uint8 with
            # the pose as x y z q; uint16 (v * 256, scaled back by 1/256) with the 4 x 4
            # pose; equal-channel BGR (luminance of (v, v, v) is v) with x y z q.
            if i == 0:
                report = pipeline.process(left, right, poses[frame["name"]])
            elif i == 1:
                report = pipeline.process(left.astype(np.uint16) * 256,
                                          right.astype(np.uint16) * 256, frame["T_W_B"])
            else:
                report = pipeline.process(np.dstack([left] * 3), np.dstack([right] * 3),
                                          poses[frame["name"]])
            self.assertGreater(report["points"], 0)

            out = os.path.join(self.run_dir, "frames", frame["name"])
            for k, layer in enumerate(pipeline.layers):
                stem = os.path.join(out, f"L{k}_")
                header = assert_same_grid(self, layer.height, stem + "height.jdem")
                assert_same_grid(self, layer.published_variance(), stem + "variance.jdem")
                assert_same_grid(self, layer.hazard, stem + "hazard.jdem")
                if layer.rule == "ccm":
                    assert_same_grid(self, layer.slope_x, stem + "slope_x.jdem")
                    assert_same_grid(self, layer.slope_y, stem + "slope_y.jdem")
                self.assertEqual(header["resolution_m"], layer.resolution_m)
                self.assertEqual(header["center_m"], layer.center_m)
                self.assertEqual(header["frame"], frame["name"])
            planner = pipeline.planner
            assert_same_grid(self, planner.fused, os.path.join(out, "fused_hazard.jdem"))
            assert_same_grid(self, planner.clearance, os.path.join(out, "fused_clearance.jdem"))
            assert_same_grid(self, planner.footprint, os.path.join(out, "footprint_hazard.jdem"))
            assert_same_grid(self, planner.hazard_distance, os.path.join(out, "hazard_distance.jdem"))

            # The same points through a LayerStack give the same map: the stack is the
            # pipeline's map half. The pipeline computes its points in float straight
            # from the disparities (axis model); points() gives them with double
            # covariances, so the grids agree to float rounding (positions within 2 um,
            # variances within 1e-5 relative: tests/stereo/map_points_path_test.cpp).
            points, covariances = pipeline.points()
            self.assertEqual(points.shape, (report["points"], 3))
            stack.insert(points, covariances, robot_xy=frame["T_W_B"][:2, 3])
            # A gate or a class flips where a statistic sits on its threshold: at most
            # 0.2 % of a grid's cells may differ by more than that rounding.
            for mine, theirs in zip(stack.layers, pipeline.layers):
                for name, grid in theirs.grids().items():
                    a, b = mine.grids()[name], grid
                    if name == "hazard" or grid.dtype != np.float32:
                        differ = np.count_nonzero(a != b)
                    else:
                        same = np.isclose(a, b, rtol=1e-4, atol=1e-6, equal_nan=True)
                        differ = np.count_nonzero(~same)
                    self.assertLessEqual(differ, max(1, grid.size // 500), name)
            differ = np.count_nonzero(stack.planner.fused != planner.fused)
            self.assertLessEqual(differ, max(1, planner.fused.size // 500))


class ViewMasks(unittest.TestCase):
    """The hazard stage's view masks as Layer properties: `viewed` where
    hazard.partial_ring_proof is view_edge, `seen_whole` on layers with
    hole_free_coverage (cadre_flight's 4 cm layer), None elsewhere."""

    def test_masks_of_the_flight_stack(self):
        config = hazmap.load_config(os.path.join(SOURCE_DIR, "config", "cadre_flight.yaml"), [])
        sequence = hazmap.load_sequence(SAMPLE)
        pipeline = hazmap.Pipeline(config, sequence["calibration"])
        for frame in sequence["frames"][:3]:
            pipeline.process(hazmap.read_image(frame["left"]), hazmap.read_image(frame["right"]),
                             frame["T_W_B"])
        for k, layer in enumerate(pipeline.layers):
            viewed = layer.viewed
            self.assertEqual(viewed.shape, layer.shape)
            self.assertTrue(set(np.unique(viewed)) <= {0.0, 1.0, 2.0}, k)
            self.assertGreater((viewed == 2).sum(), 0, k)  # three frames saw some cells whole
            if k != 1:  # only the 4 cm layer has hole_free_coverage
                self.assertIsNone(layer.seen_whole, k)
                continue
            marks = layer.seen_whole
            self.assertTrue(set(np.unique(marks)) <= {0.0, 1.0, 2.0})
            self.assertGreater((marks == 1).sum(), 0)
            # Only known cells are tested.
            self.assertTrue(np.isfinite(layer.height[marks != 0]).all())


class BadInput(unittest.TestCase):
    """Wrong input raises a Python exception with one clear line, never a crash."""

    @classmethod
    def setUpClass(cls):
        cls.config = hazmap.load_config(DEFAULT_CONFIG, ["map.layers.0.size=32"])
        cls.pipeline = hazmap.Pipeline(cls.config, os.path.join(SAMPLE, "calibration.yaml"))
        cls.image = hazmap.read_image(os.path.join(SAMPLE, "left", "000000.png"))

    def raises(self, exception, fragment, call, *args, **kwargs):
        with self.assertRaises(exception) as caught:
            call(*args, **kwargs)
        message = str(caught.exception)
        self.assertIn(fragment, message)
        self.assertNotIn("\n", message)
        return message

    def test_config_errors(self):
        self.raises(hazmap.Error, "unknown key 'map.nonexistent'",
                    hazmap.load_config, DEFAULT_CONFIG, ["map.nonexistent=1"])
        self.raises(hazmap.Error, "key 'stereo.block_size': expected an integer",
                    hazmap.load_config, DEFAULT_CONFIG, ["stereo.block_size=abc"])
        self.raises(hazmap.Error, "expected KEY=VALUE",
                    hazmap.load_config, DEFAULT_CONFIG, ["stereo.block_size"])
        self.raises(hazmap.Error, "key 'map.layers': at least one layer is required",
                    hazmap.parse_config, "stereo: {block_size: 11}")  # map.layers missing
        self.raises(hazmap.Error, "cannot open configuration file",
                    hazmap.load_config, os.path.join(SAMPLE, "no_such.yaml"))
        self.raises(hazmap.Error, "no_such.yaml", hazmap.Pipeline, self.config,
                    os.path.join(SAMPLE, "no_such.yaml"))
        self.assertTrue(issubclass(hazmap.Error, RuntimeError))

    def test_image_errors(self):
        pose = np.eye(4)
        process = self.pipeline.process
        self.raises(TypeError, "dtype float32", process, self.image.astype(np.float32),
                    self.image.astype(np.float32), pose)
        self.raises(TypeError, "expected a numpy array", process, [[1, 2]], self.image, pose)
        self.raises(ValueError, "shape (520, 640, 2)", process,
                    np.dstack([self.image] * 2), self.image, pose)
        # The library's own checks: a size that is not the calibrated one, mixed pairs.
        self.raises(hazmap.Error, "image size", process, self.image[:100], self.image[:100], pose)
        self.raises(hazmap.Error, "differ in depth", process, self.image,
                    self.image.astype(np.uint16), pose)

    def test_pose_and_point_errors(self):
        process = self.pipeline.process
        self.raises(ValueError, "expected a 4 x 4 T_W_B or 7 numbers", process, self.image,
                    self.image, np.eye(3))
        self.raises(ValueError, "not a rotation", process, self.image, self.image,
                    np.diag([2.0, 2.0, 2.0, 1.0]))
        self.raises(ValueError, "not a unit quaternion", process, self.image, self.image,
                    [0, 0, 0, 0, 0, 0, 2])
        self.raises(ValueError, "noise", process, self.image, self.image, np.eye(4), [1, 2])
        stack = hazmap.LayerStack(self.config)
        self.raises(hazmap.Error, "no frame processed yet", getattr, stack, "layers")
        points = np.zeros((5, 3))
        self.raises(ValueError, "expected N x 3", stack.insert, np.zeros((5, 2)), np.ones(5), (0, 0))
        self.raises(ValueError, "covariances: shape (4,)", stack.insert, points, np.ones(4), (0, 0))
        self.raises(ValueError, "variance <= 0", stack.insert, points, np.zeros(5), (0, 0))
        self.raises(ValueError, "robot_xy", stack.insert, points, np.ones(5), (0, 0, 0))
        self.raises(TypeError, "points", stack.insert, "abc", np.ones(5), (0, 0))
        self.raises(IndexError, "layer 3 of 1", lambda: (stack.insert(points, np.ones(5), (0, 0)),
                                                         stack.layer(3)))


class Lifetime(unittest.TestCase):
    """Grids are views without a copy that keep their owner alive."""

    def test_view_outlives_the_stack(self):
        stack = hazmap.LayerStack(hazmap.parse_config(STACK_YAML))
        points = plane_points(lambda x, y: 0.02 + 0.0 * x, 0.3, 0.005)
        stack.insert(points, np.full(len(points), 1e-4), robot_xy=(0.0, 0.0))
        height = stack.layer(0).height
        expected = height.copy()
        self.assertFalse(height.flags.owndata)  # a view of the map's buffer, not a copy
        self.assertFalse(height.flags.writeable)
        with self.assertRaises(ValueError):
            height[0, 0] = 1.0  # the map's state is read-only from Python
        # The same buffer on every read: no copy per access.
        self.assertEqual(height.ctypes.data, stack.layer(0).height.ctypes.data)
        owner = weakref.ref(stack)
        del stack
        gc.collect()
        self.assertIsNotNone(owner())  # kept alive by the array
        np.testing.assert_array_equal(height, expected)
        del height
        gc.collect()
        self.assertIsNone(owner())  # and released with it

    def test_view_shows_the_next_frame(self):
        stack = hazmap.LayerStack(hazmap.parse_config(STACK_YAML))
        points = plane_points(lambda x, y: 0.02 + 0.0 * x, 0.3, 0.005)
        stack.insert(points, np.full(len(points), 1e-4), robot_xy=(0.0, 0.0))
        height = stack.layer(0).height
        stack.insert(points + [0.0, 0.0, 0.02], np.full(len(points), 1e-4), robot_xy=(0.0, 0.0))
        # Kalman: two equal-weight frames at 2 and 4 cm average to 3 cm.
        np.testing.assert_allclose(height[np.isfinite(height)], 0.03, atol=HEIGHT_TOLERANCE_M)


class Evaluate(unittest.TestCase):
    """evaluate() on a simulated run: its metrics dict, the files it writes, the window."""

    def test_metrics_of_a_simulated_run(self):
        with tempfile.TemporaryDirectory() as tmp:
            seq, run = os.path.join(tmp, "seq"), os.path.join(tmp, "run")
            summary = hazmap.simulate(seq, scenario="rocks", frames=2, scale=0.4, ground_truth=True)
            self.assertEqual((summary["frames"], summary["width_px"]), (2, 640))
            subprocess.run([CLI, "run", "--config", DEFAULT_CONFIG, "--sequence", seq, "--out",
                            run, "--set", "output.png=false", "--set", "map.layers.0.size=128",
                            "--quiet"], check=True)
            hazmap.set_log_level("warn")
            metrics = hazmap.evaluate(run, seq, write_report=False, near_radius_m=1.0)
            self.assertEqual(metrics["frames"], ["000000", "000001"])
            self.assertEqual([l["layer"] for l in metrics["layers"]], ["L0", "fused", "footprint"])
            L0 = metrics["layers"][0]
            # Each frame's scored extent is the layer's window (128 cells of 1 cm, all
            # inside the ground truth), to within a row and a column of 1 cm GT pixels;
            # the pooled one their sum.
            window_m, pixel_m = 1.28, 0.01
            for frame in metrics["per_frame"]:
                self.assertLessEqual(abs(frame["L0"]["extent_m2"] - window_m ** 2),
                                     2 * window_m * pixel_m)
            self.assertAlmostEqual(L0["extent_m2"],
                                   sum(f["L0"]["extent_m2"] for f in metrics["per_frame"]))
            self.assertEqual(str(metrics["out_dir"]), os.path.join(run, "eval"))
            self.assertTrue(0 <= L0["hazard_recall"] <= 1)
            self.assertLess(L0["height_rms_m"], 0.01)  # a few mm on the sample's terrain
            self.assertIn("hazard_recall", L0["near"])
            self.assertEqual(set(metrics["per_frame"][1]), {"L0", "fused", "footprint"})
            # The dict holds what metrics.json (written by the same call) says.
            import json
            with open(os.path.join(run, "eval", "metrics.json")) as f:
                written = {l["layer"]: l for l in json.load(f)["layers"]}
            for layer in metrics["layers"]:
                for key, value in layer.items():
                    if key == "near":
                        continue
                    if isinstance(value, float) and np.isnan(value):
                        self.assertIsNone(written[layer["layer"]][key])  # JSON null
                    elif isinstance(value, float):
                        self.assertAlmostEqual(value, written[layer["layer"]][key], places=9)
                    else:
                        self.assertEqual(value, written[layer["layer"]][key], key)
            self.raises_on_missing_ground_truth(run, seq)

    def raises_on_missing_ground_truth(self, run, seq):
        # The run's own sequence (same poses, so the fingerprint check passes) without its
        # ground-truth grids.
        import shutil
        bare = seq + "_no_gt"
        shutil.copytree(seq, bare)
        for name in os.listdir(bare):
            if name.startswith("gt_"):
                os.remove(os.path.join(bare, name))
        with self.assertRaises(hazmap.Error) as caught:
            hazmap.evaluate(run, bare, write_report=False)
        self.assertIn("gt_height.jdem", str(caught.exception))
        # Another sequence is refused first, by its poses.
        with self.assertRaises(hazmap.Error) as caught:
            hazmap.evaluate(run, SAMPLE, write_report=False)
        self.assertIn("poses fingerprint", str(caught.exception))


if __name__ == "__main__":
    unittest.main(argv=sys.argv, verbosity=2)
