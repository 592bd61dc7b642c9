#pragma once
// A hazard test (SPEC 8) is a small type: the parameters it reads (taken from the layer's
// LayerHazardParams when the classifier is built), how far from a cell it reads (its
// reach, which the incremental stage needs, SPEC 8.6) and the evidence it adds for one
// cell (evidence.hpp: hazard needs evidence, traversable needs proof). A rule family's
// classifier runs a list of them, in order, on every cell; the family's cell type
// (hazard_classifier.hpp) gives the tests what they read. The shape of one:
//
//   struct MyTest {
//     static bool enabled(const LayerHazardParams& p);   // does this layer run it at all
//     explicit MyTest(const LayerHazardParams& p);        // keeps what it needs of p
//     int reach_cells(const TestReach& r) const;          // cells away from the cell it reads
//     template <class Cell> void add(const Cell& c, Evidence& ev) const;
//   };
//
// Adding one: the struct (kernel_tests.hpp, plane_tests.hpp, ring_tests.hpp or a header
// of its own), one entry in its family's list (hazard_classifier.hpp) and, when it has a
// setting, one key (docs/architecture.md, "Adding a hazard test").

#include <algorithm>
#include <array>
#include <cstddef>
#include <tuple>

#include "hazmap/hazard/evidence.hpp"
#include "hazmap/hazard/hazard_params.hpp"

namespace hazmap {

/// What a test's reach depends on beyond its own parameters.
struct TestReach {
  /// How far the family's wheel-ring sampler reads from a cell, in cells.
  int ring_cells = 0;
};

/// A family's hazard tests, run in the order listed; a test its `enabled` turns off for a
/// layer is skipped (and reaches nothing).
template <class... Tests>
class HazardTests {
 public:
  explicit HazardTests(const LayerHazardParams& params)
      : tests_(Tests(params)...), on_{Tests::enabled(params)...} {}

  /// The farthest any enabled test reads, in cells.
  int reach_cells(const TestReach& r) const {
    int reach = 0;
    std::size_t i = 0;
    std::apply([&](const auto&... t) {
      ((reach = on_[i++] ? std::max(reach, t.reach_cells(r)) : reach), ...);
    }, tests_);
    return reach;
  }

  /// Adds every enabled test's evidence for `cell`, in order.
  template <class Cell>
  void run(const Cell& cell, Evidence& ev) const {
    std::size_t i = 0;
    std::apply([&](const auto&... t) { ((on_[i++] ? t.add(cell, ev) : void()), ...); }, tests_);
  }

 private:
  std::tuple<Tests...> tests_;
  std::array<bool, sizeof...(Tests)> on_;
};

}  // namespace hazmap
