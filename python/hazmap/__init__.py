"""hazmap: stereo-to-hazard terrain mapping, from Python.

A thin layer over the C++ library (the extension module hazmap._hazmap): the same
configuration, pipeline, map and evaluation as the `hazmap` command line.

    import hazmap
    config = hazmap.load_config("config/default.yaml", ["map.layers.0.size=64"])
    pipeline = hazmap.Pipeline(config, "data/sample/calibration.yaml")
    pipeline.process(left, right, T_W_B)        # numpy images, 4 x 4 pose
    layer = pipeline.layers[0]
    layer.height, layer.variance, layer.hazard  # numpy views (float32)

Errors from the library raise hazmap.Error (a RuntimeError) with its one-line message;
wrong argument types and shapes raise TypeError and ValueError.
"""

from ._hazmap import (  # noqa: F401
    HAZARD,
    TRAVERSABLE,
    UNKNOWN,
    Calibration,
    Config,
    Error,
    Layer,
    LayerStack,
    Pipeline,
    PlannerMaps,
    __version__,
    evaluate,
    load_calibration,
    load_config,
    load_sequence,
    parse_config,
    read_image,
    read_jdem,
    set_log_level,
    simulate,
)

__all__ = [
    "HAZARD", "TRAVERSABLE", "UNKNOWN", "Calibration", "Config", "Error", "Layer",
    "LayerStack", "Pipeline", "PlannerMaps", "evaluate", "load_calibration", "load_config",
    "load_sequence", "parse_config", "read_image", "read_jdem", "set_log_level", "simulate",
]
