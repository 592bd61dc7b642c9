// Map insertion cost: ns per point per layer, per rule and for whole layer stacks, with
// points in image scan-line order (640 x 520 frame, ground within 3 m or 5 m).
// Run: build/hazmap_bench --benchmark_min_time=1

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bench_layers.hpp"
#include "bench_points.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/map/map_points.hpp"

namespace hazmap {
namespace {

/// One frame's ground points within the shipped configs' z_max (3 m), or within 5 m
/// (far-field points: mostly one point per 1 cm cell, i.e. a cache miss each).
const PointCloud& frame_cloud(bool far) {
  static PointCloud near_cloud, far_cloud;
  PointCloud& c = far ? far_cloud : near_cloud;
  if (c.empty()) bench::scanline_ground_points(c, 640, 520, 0.0, far ? 5.0 : 3.0);
  return c;
}

/// The same points as the map reads them (made once per frame in the points stage), with
/// constant CCM weights (the shipped configs') or trace weights.
const MapPoints& frame_points(bool far, bool trace = false) {
  static MapPoints points[2][2];
  MapPoints& p = points[far][trace];
  if (p.size() == 0)
    p.assign(frame_cloud(far), trace ? CcmWeighting::trace : CcmWeighting::constant);
  return p;
}

MapConfig make_map(const std::vector<bench::LayerSpec>& layers,
                   Insertion insertion = Insertion::all_layers) {
  MapConfig map;
  map.insertion = insertion;
  bench::add_layers(map, layers);
  return map;
}

/// `whole_frame`: each iteration is a frame, begin_frame (roll, time inflation) included.
void run_insert(benchmark::State& state, const MapConfig& map, bool whole_frame = false,
                const RulesConfig& rules = RulesConfig{}, bool trace_weights = false) {
  LayerStack stack(map, rules);
  const MapPoints& points = frame_points(state.range(0) != 0, trace_weights);
  stack.begin_frame(0.0, 0.0);
  for (auto _ : state) {
    if (whole_frame) stack.begin_frame(0.0, 0.0);
    benchmark::DoNotOptimize(stack.insert(points));
  }
  const double point_layers = double(points.size()) * double(map.layers.size());
  state.counters["points"] = double(points.size());
  state.counters["ns_per_point_layer"] = benchmark::Counter(
      point_layers, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The points stage's conversion of a frame's Measurements into MapPoints (once per
/// point and frame, whatever the number of layers; not part of the figures below).
void BM_MapPointsAssign(benchmark::State& state) {
  const PointCloud& cloud = frame_cloud(state.range(0) != 0);
  MapPoints points;
  for (auto _ : state) {
    points.assign(cloud, CcmWeighting::constant);
    benchmark::DoNotOptimize(points.chunk(0, 1).x);
  }
  state.counters["ns_per_point"] = benchmark::Counter(
      double(cloud.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_Kalman1cm(benchmark::State& s) { run_insert(s, make_map({{RuleKind::kalman, 0.01, 1000}})); }
void BM_Omg1cm(benchmark::State& s) { run_insert(s, make_map({{RuleKind::omg, 0.01, 1000}})); }
void BM_Bananas1cm(benchmark::State& s) { run_insert(s, make_map({{RuleKind::bananas, 0.01, 1000}})); }
void BM_Ccm4cm(benchmark::State& s) { run_insert(s, make_map({{RuleKind::ccm, 0.04, 250}})); }
void BM_Ccm16cm(benchmark::State& s) { run_insert(s, make_map({{RuleKind::ccm, 0.16, 64}})); }
/// CCM with trace weights: a weight array to read and multiply by, which constant weights
/// (BM_Ccm4cm) skip.
void BM_Ccm4cmTraceWeights(benchmark::State& s) {
  run_insert(s, make_map({{RuleKind::ccm, 0.04, 250}}), false, RulesConfig{}, true);
}
/// The 1 cm Kalman layer with the SPEC 4 consistency gate on (gate_sigma 3): its extra
/// pass over the chunk, against BM_Kalman1cm (gate off).
void BM_Kalman1cmConsistencyGate(benchmark::State& s) {
  RulesConfig rules;
  rules.kalman.gate_sigma = 3.0;
  run_insert(s, make_map({{RuleKind::kalman, 0.01, 1000}}), false, rules);
}
/// 4096 consecutive points of the frame (six image rows, mid-field), inserted over and
/// over: the cells they touch stay in cache, so this is the 1 cm Kalman layer's compute
/// alone; the difference to BM_Kalman1cm/0 is what the whole frame's memory traffic adds.
void BM_Kalman1cmInCache(benchmark::State& state) {
  static PointCloud rows;
  if (rows.empty()) {
    const PointCloud& frame = frame_cloud(false);
    rows.assign(frame.begin() + 100000, frame.begin() + 100000 + 4096);
  }
  const MapPoints points(rows);
  RulesConfig rules;
  LayerStack stack(make_map({{RuleKind::kalman, 0.01, 1000}}), rules);
  stack.begin_frame(0.0, 0.0);
  for (auto _ : state) benchmark::DoNotOptimize(stack.insert(points));
  state.counters["ns_per_point_layer"] = benchmark::Counter(
      double(points.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
/// CADRE flight stack (SPEC 11): Kalman 1 cm + CCM 4, 16, 64 cm over 10 m x 10 m.
MapConfig flight_stack() {
  return make_map({{RuleKind::kalman, 0.01, 1000}, {RuleKind::ccm, 0.04, 250},
                   {RuleKind::ccm, 0.16, 64}, {RuleKind::ccm, 0.64, 16}});
}
void BM_FlightStack(benchmark::State& s) { run_insert(s, flight_stack()); }

/// The flight stack with each layer's share timed inside it (LayerStack::insert's
/// per-layer times: a tick read between layers), so that a layer is charged for what it
/// costs next to the others (cache traffic included).
/// Counters: ns per point of each layer (L0 = Kalman 1 cm, L1..L3 = CCM 4, 16, 64 cm).
void BM_FlightStackByLayer(benchmark::State& state) {
  const MapConfig map = flight_stack();
  RulesConfig rules;
  LayerStack stack(map, rules);
  const MapPoints& points = frame_points(state.range(0) != 0);
  stack.begin_frame(0.0, 0.0);
  const std::size_t n = stack.size();
  std::vector<double> frame_ms(n, 0.0), total_ms(n, 0.0);
  for (auto _ : state) {
    benchmark::DoNotOptimize(stack.insert(points, frame_ms.data()));
    for (std::size_t i = 0; i < n; ++i) total_ms[i] += frame_ms[i];
  }
  const double point_frames = double(points.size()) * double(state.iterations());
  for (std::size_t i = 0; i < n; ++i)
    state.counters["L" + std::to_string(i) + "_ns_per_point"] = total_ms[i] * 1e6 / point_frames;
  state.counters["points"] = double(points.size());
}
/// The flight stack frame by frame: begin_frame (the robot stands still, so no roll; the
/// Kalman layer's time inflation) and insertion.
void BM_FlightStackFrame(benchmark::State& s) {
  run_insert(s, flight_stack(), true);
}
/// The flight stack without its Kalman layer: the difference to BM_FlightStack is the
/// Kalman layer's marginal cost inside the stack (the shared chunk conversion excluded).
void BM_FlightStackCcmOnly(benchmark::State& s) {
  MapConfig map = flight_stack();
  map.layers.erase(map.layers.begin());
  run_insert(s, map);
}
/// Thesis CCM stack (Table 7.4) in both insertion modes.
void BM_ThesisCcmAllLayers(benchmark::State& s) {
  run_insert(s, make_map({{RuleKind::ccm, 0.04, 42}, {RuleKind::ccm, 0.08, 32}, {RuleKind::ccm, 0.16, 28},
                          {RuleKind::ccm, 0.32, 18}, {RuleKind::ccm, 0.64, 16}}));
}
void BM_ThesisCcmPooled(benchmark::State& s) {
  run_insert(s, make_map({{RuleKind::ccm, 0.04, 42}, {RuleKind::ccm, 0.08, 32}, {RuleKind::ccm, 0.16, 28},
                          {RuleKind::ccm, 0.32, 18}, {RuleKind::ccm, 0.64, 16}},
                         Insertion::finest_then_pool));
}

// Argument: 0 = points within 3 m (as the shipped configs' z_max), 1 = within 5 m.
BENCHMARK(BM_MapPointsAssign)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kalman1cm)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kalman1cmInCache)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Omg1cm)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Bananas1cm)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ccm4cm)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ccm16cm)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ccm4cmTraceWeights)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kalman1cmConsistencyGate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlightStack)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlightStackByLayer)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlightStackFrame)->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlightStackCcmOnly)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ThesisCcmAllLayers)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ThesisCcmPooled)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hazmap

BENCHMARK_MAIN();
