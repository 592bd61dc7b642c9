#pragma once
// The map core's ParallelFor (core/parallel_for.hpp) on OpenCV's thread pool, the one
// the stereo stages use: the pipeline hands it to the mapper.

#include "hazmap/core/parallel_for.hpp"

namespace hazmap {

/// The process's OpenCV-backed ParallelFor (lives as long as the process).
const ParallelFor& opencv_parallel_for();

}  // namespace hazmap
