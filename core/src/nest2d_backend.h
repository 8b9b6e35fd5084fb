#pragma once
// The libnest2d call, compiled as C++17 on its own (libnest2d's comparison operators are
// ambiguous under C++20): plain standard types only, so nothing of fabkit's C++20 headers is
// needed there.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace fabkit::detail {

struct Nest2dInput {
  /// Outer rings, counter-clockwise, in integer coordinates (1 unit = 1 nm).
  std::vector<std::vector<std::pair<std::int64_t, std::int64_t>>> outlines;
  std::int64_t bin_min_x = 0, bin_min_y = 0, bin_max_x = 0, bin_max_y = 0;
  std::int64_t spacing = 0;
  std::vector<double> rotations_rad;
  double accuracy = 0.65;
  std::function<bool()> stop;  ///< polled by the placer; true stops it
};

struct Nest2dPlacement {
  int bin = -1;
  double rotation_rad = 0;
  std::int64_t x = 0, y = 0;
};

struct Nest2dOutput {
  std::vector<Nest2dPlacement> placements;
  int bins = 0;
  std::string error;  ///< an exception's message; empty on success
};

Nest2dOutput run_nest2d(const Nest2dInput& input);

}  // namespace fabkit::detail
