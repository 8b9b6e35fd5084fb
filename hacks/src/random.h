#pragma once
// Seeded random numbers that are the same on every platform (std distributions are not).

#include <cmath>
#include <cstdint>
#include <string_view>

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

/// A uniform number in [0, 1) that depends only on `seed`, `start` and a name: the random
/// start a parameter gets is the same whatever its index in the assembly's vector, so the
/// order in which a design makes its connects does not change which starts are tried.
inline double keyed_uniform(std::uint64_t seed, int start, std::string_view key) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : key) h = (h ^ c) * 1099511628211ull;
  SplitMix rng(seed ^ h ^ (static_cast<std::uint64_t>(start) * 0x9E3779B97F4A7C15ull));
  rng.uniform();
  return rng.uniform();
}

/// A tiny, seeded nudge of a parameter (a millionth of its range): symmetric starts (a hook
/// exactly in the middle of its tilt range) leave the search to round-off, which differs with
/// the world's placement or a file's spelling of an angle; a nudge keyed by the parameter's name
/// breaks the tie the same way every time. `variant` 1, 2, ... draws other nudges (the
/// closure search's further stretching starts).
inline double symmetry_nudge(std::uint64_t seed,
                             std::string_view key,
                             double range,
                             int variant = 0) {
  return 1e-6 * range * (keyed_uniform(seed, -1 - variant, key) - 0.5);
}

/// The value a random start gives a parameter in [lo, hi] for a draw u in [0, 1): uniform
/// within the bounds, or for a turn with no ends (`unbounded`) turned from its current value
/// by u of a whole turn. Such a turn's zero is wherever the design's file put the primitive's
/// frame (a rod spun about its axis): drawn from the zero, the same draw would be another
/// physical start.
inline double drawn_value(double current, double u, double lo, double hi, bool unbounded) {
  const double range = hi - lo;
  if (!unbounded) return lo + u * range;
  return lo + std::fmod(std::fmod(current - lo + u * range, range) + range, range);
}

}  // namespace fabkit::hacks::detail
