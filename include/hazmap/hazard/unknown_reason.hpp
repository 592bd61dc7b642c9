#pragma once
// Why a cell stayed unknown (issue 34): what kept each test from proving it traversable
// or showing a hazard. A cell may have several reasons, so they are bits. Classifiers
// fill them only on request (HazardClassifier::explain), for `hazmap evaluate`'s counts:
// the per-frame path records the bits in Evidence but writes no grid.

#include <array>
#include <cstdint>

namespace hazmap {

enum UnknownReason : std::uint16_t {
  kReasonNoHeight = 1u << 0,          ///< the cell (or its whole kernel) has no height
  kReasonFewPoints = 1u << 1,         ///< CCM: fewer than min_points points
  kReasonKernelIncomplete = 1u << 2,  ///< kernel fill below min_kernel_fill or off the layer
  kReasonNotEvaluable = 1u << 3,      ///< CCM: no plane (not evaluable, or one axis only)
  kReasonRingIncomplete = 1u << 4,    ///< a wheel-ring sample is missing or not exact
  kReasonRoughnessMargin = 1u << 5,   ///< roughness within k sigma of its threshold
  kReasonSlopeMargin = 1u << 6,       ///< face or vehicle slope within k sigma
  kReasonStepMargin = 1u << 7,        ///< step above the ring within k sigma
  kReasonNoVouchingLayer = 1u << 8,   ///< fused: only layers with h_min > critical prove it
  kReasonOutside = 1u << 9,           ///< fused: no vouching layer covers the cell
};

constexpr int kUnknownReasonCount = 10;

/// Short names, bit i -> kUnknownReasonNames[i] (CSV / JSON keys).
constexpr std::array<const char*, kUnknownReasonCount> kUnknownReasonNames = {
    "no_height",       "few_points",      "kernel_incomplete", "not_evaluable",
    "ring_incomplete", "roughness_margin", "slope_margin",      "step_margin",
    "no_vouching_layer", "outside"};

}  // namespace hazmap
