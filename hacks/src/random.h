#pragma once
// Seeded random numbers that are the same on every platform (std distributions are not).

#include <cstdint>

namespace fabkit::hacks::detail {

/// splitmix64: tiny and seedable; uniform() returns doubles in [0, 1).
class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  double uniform() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

}  // namespace fabkit::hacks::detail
