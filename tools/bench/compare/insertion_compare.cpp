// Map insertion timed on real point clouds, for tools/bench/compare.sh: one driver that
// compiles against the library of any revision since ba7e030, so that two revisions are
// timed with the same code on the same clouds (docs/benchmarks.md).
//
// It uses only API that exists at ba7e030 and after: LayerStack(map, rules),
// begin_frame(x, y), insert(MapPoints), MapPoints::assign(cloud, CcmWeighting), and the
// MapConfig / LayerConfig / RulesConfig structs (map.insertion was a string at ba7e030, an
// enum since: set_pooled below handles both). It reads the clouds itself (binary PLY as
// `hazmap stereo` writes them), since ba7e030 has no PLY reader.
//
//   insertion_compare --clouds DIR [--label L] [--warmup N] [--passes N] [--case SUBSTR]
//
// Each case builds its layer stack, runs `warmup` passes over every frame of DIR (its
// *.ply files, subfolders included, in path order: `hazmap stereo`'s frames/*/cloud.ply),
// then `passes` timed passes; a pass inserts each frame once (begin_frame at the
// frame's mean x, y, then the insertion). Prints one line per timed pass:
//   <label> <case> <ns per point and layer, CPU> <the same, wall clock> <points per frame>
// CPU time is the thread's (CLOCK_THREAD_CPUTIME_ID): on a machine shared with other
// work, time the process spends waiting for a core does not count (its caches shared
// with the others still do); wall time counts everything.
// The windows are large enough (10 m at 1 cm) to hold a frame's points, so each case
// measures insertion proper, not dropping points outside the window.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "../bench_layers.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/map/map_points.hpp"

namespace {

using namespace hazmap;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Clouds

/// Reads a binary little-endian PLY whose vertex element has float x y z and float
/// cov_xx cov_xy cov_xz cov_yy cov_yz cov_zz (what `hazmap stereo` writes), any other
/// scalar properties skipped.
PointCloud read_cloud(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::string line;
  std::size_t count = 0;
  bool in_vertex = false, binary = false;
  std::size_t stride = 0;
  std::vector<std::pair<std::string, std::size_t>> offsets;  // float properties
  auto type_size = [](const std::string& t) -> std::size_t {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
      return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
  };
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string f;
      words >> f;
      binary = f == "binary_little_endian";
    } else if (word == "element") {
      std::string name;
      words >> name;
      in_vertex = name == "vertex";
      if (in_vertex) words >> count;
    } else if (word == "property" && in_vertex) {
      std::string type, name;
      words >> type >> name;
      if (type == "float" || type == "float32") offsets.emplace_back(name, stride);
      stride += type_size(type);
    } else if (word == "end_header") {
      break;
    }
  }
  if (!binary) throw std::runtime_error(path.string() + ": not a binary little-endian PLY");
  const char* names[9] = {"x", "y", "z", "cov_xx", "cov_xy", "cov_xz", "cov_yy", "cov_yz", "cov_zz"};
  std::size_t at[9];
  for (int k = 0; k < 9; ++k) {
    auto it = std::find_if(offsets.begin(), offsets.end(),
                           [&](const auto& p) { return p.first == names[k]; });
    if (it == offsets.end())
      throw std::runtime_error(path.string() + ": no float vertex property " + names[k]);
    at[k] = it->second;
  }
  std::vector<char> body(count * stride);
  in.read(body.data(), static_cast<std::streamsize>(body.size()));
  if (static_cast<std::size_t>(in.gcount()) != body.size())
    throw std::runtime_error(path.string() + ": truncated");
  PointCloud cloud(count);
  for (std::size_t i = 0; i < count; ++i) {
    float v[9];
    for (int k = 0; k < 9; ++k) std::memcpy(&v[k], body.data() + i * stride + at[k], sizeof(float));
    Measurement& m = cloud[i];
    m.p_W = Eigen::Vector3f(v[0], v[1], v[2]);
    m.cov_xx = v[3];
    m.cov_xy = v[4];
    m.cov_xz = v[5];
    m.cov_yy = v[6];
    m.cov_yz = v[7];
    m.cov_zz = v[8];
  }
  return cloud;
}

struct Frame {
  PointCloud cloud;
  MapPoints points;  ///< the cloud converted once (the "points" cases)
  double cx = 0, cy = 0;  ///< mean x, y: the window's centre
};

// ---------------------------------------------------------------------------------------
// Stacks

/// map.insertion = finest_then_pool: a std::string at ba7e030, an enum class since.
template <class M>
void set_pooled(M& map) {
  using T = std::decay_t<decltype(map.insertion)>;
  if constexpr (std::is_same_v<T, std::string>)
    map.insertion = "finest_then_pool";
  else
    map.insertion = T::finest_then_pool;
}

MapConfig make_map(const std::vector<bench::LayerSpec>& layers, bool pooled = false) {
  MapConfig map;
  if (pooled) set_pooled(map);
  bench::add_layers(map, layers);
  return map;
}

struct Case {
  std::string name;
  MapConfig map;
  bool from_cloud;  ///< conversion (MapPoints::assign) timed with the insertion
  bool convert_only = false;
};

std::vector<Case> cases() {
  const auto K = RuleKind::kalman, O = RuleKind::omg, C = RuleKind::ccm;
  // Windows of ~10 m: 1000 cells at 1 cm, 250 at 4 cm, ...
  const MapConfig kalman1 = make_map({{K, 0.01, 1000}});
  const MapConfig kalman4 = make_map({{K, 0.04, 250}});
  const MapConfig omg1 = make_map({{O, 0.01, 1000}});
  const MapConfig ccm4 = make_map({{C, 0.04, 250}});
  // SPEC 11 flight stack (config/cadre_flight.yaml's rules, windows grown to ~10 m).
  const MapConfig flight = make_map({{K, 0.01, 1000}, {C, 0.04, 250}, {C, 0.16, 64}, {C, 0.64, 16}});
  // The same with cadre_flight's hole-free 4 cm layer (map.layers.1.hole_free_coverage),
  // which keeps the cells' 4 x 4 occupancy masks (revisions before 2026-12-03: no mask).
  MapConfig flight_hole_free = flight;
  flight_hole_free.layers[1].hole_free_coverage = 0.5;
  // Thesis stacks (config/thesis_pwc.yaml, thesis_ccm.yaml: finest_then_pool).
  const MapConfig pwc = make_map({{O, 0.01, 1000}, {O, 0.04, 250}, {O, 0.16, 64}, {O, 0.64, 16}}, true);
  const MapConfig tccm =
      make_map({{C, 0.04, 250}, {C, 0.08, 128}, {C, 0.16, 64}, {C, 0.32, 32}, {C, 0.64, 16}}, true);
  return {
      {"convert", kalman1, true, true},
      {"kalman1", kalman1, false},
      {"kalman4", kalman4, false},
      {"omg1", omg1, false},
      {"ccm4", ccm4, false},
      {"flight", flight, false},
      {"flight_hole_free", flight_hole_free, false},
      {"thesis_pwc", pwc, false},
      {"thesis_ccm", tccm, false},
      {"kalman1_cloud", kalman1, true},
      {"kalman4_cloud", kalman4, true},
      {"flight_cloud", flight, true},
  };
}

using Clock = std::chrono::steady_clock;

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Seconds {
  double cpu = 0, wall = 0;
};

/// One pass over every frame: the time spent converting and inserting.
Seconds pass(LayerStack& stack, std::vector<Frame>& frames, const Case& c, MapPoints& scratch) {
  Seconds spent;
  for (Frame& f : frames) {
    stack.begin_frame(f.cx, f.cy);
    const double cpu0 = thread_seconds();
    const Clock::time_point t0 = Clock::now();
    if (c.convert_only) {
      scratch.assign(f.cloud, CcmWeighting::constant);
    } else if (c.from_cloud) {
      scratch.assign(f.cloud, CcmWeighting::constant);
      stack.insert(scratch);
    } else {
      stack.insert(f.points);
    }
    spent.wall += std::chrono::duration<double>(Clock::now() - t0).count();
    spent.cpu += thread_seconds() - cpu0;
  }
  return spent;
}

int usage() {
  std::cerr << "usage: insertion_compare --clouds DIR [--label L] [--warmup N] [--passes N] "
               "[--case SUBSTR] [--list]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, label = "run", only;
  int warmup = 2, passes = 3;
  bool list = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--clouds") dir = value();
    else if (a == "--label") label = value();
    else if (a == "--warmup") warmup = std::stoi(value());
    else if (a == "--passes") passes = std::stoi(value());
    else if (a == "--case") only = value();
    else if (a == "--list") list = true;
    else return usage();
  }
  if (list) {
    for (const Case& c : cases()) std::cout << c.name << "\n";
    return 0;
  }
  if (dir.empty()) return usage();
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".ply") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::cerr << dir << ": no .ply files\n";
    return 1;
  }
  std::vector<Frame> frames(files.size());
  double points = 0;
  for (std::size_t k = 0; k < files.size(); ++k) {
    Frame& f = frames[k];
    f.cloud = read_cloud(files[k]);
    f.points.assign(f.cloud, CcmWeighting::constant);
    double sx = 0, sy = 0;
    for (const Measurement& m : f.cloud) {
      sx += m.p_W.x();
      sy += m.p_W.y();
    }
    const double n = std::max<double>(1.0, static_cast<double>(f.cloud.size()));
    f.cx = sx / n;
    f.cy = sy / n;
    points += static_cast<double>(f.cloud.size());
  }
  MapPoints scratch;
  for (const Case& c : cases()) {
    if (!only.empty() && c.name.find(only) == std::string::npos) continue;
    LayerStack stack(c.map, RulesConfig{});
    const double layers = c.convert_only ? 1.0 : static_cast<double>(c.map.layers.size());
    for (int k = 0; k < warmup; ++k) pass(stack, frames, c, scratch);
    for (int k = 0; k < passes; ++k) {
      const Seconds s = pass(stack, frames, c, scratch);
      std::printf("%s %s %.4f %.4f %.0f\n", label.c_str(), c.name.c_str(),
                  s.cpu * 1e9 / (points * layers), s.wall * 1e9 / (points * layers),
                  points / static_cast<double>(frames.size()));
    }
    std::fflush(stdout);
  }
  return 0;
}
