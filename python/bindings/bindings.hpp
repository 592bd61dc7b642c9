#pragma once
// The parts of the hazmap._hazmap module, each registering its classes and functions.

#include <pybind11/pybind11.h>

namespace hazmap::python {

/// Config, Calibration, Pipeline, LayerStack, Layer, PlannerMaps (maps.cpp).
void bind_maps(pybind11::module_& m);
/// read_image, read_jdem, load_sequence, simulate, evaluate, set_log_level (eval_bindings.cpp).
void bind_io_and_eval(pybind11::module_& m);

}  // namespace hazmap::python
