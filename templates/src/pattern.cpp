#include "fabkit/templates/pattern.h"

#include <algorithm>
#include <cmath>

namespace fabkit::templates {

PatternLayout layout_pattern(const Pattern& pattern,
                             const Box& box,
                             bool connecting,
                             const std::array<bool, 3>& part_resizable) {
  PatternLayout out;
  out.part_size = pattern.part_size;
  for (int d = 0; d < pattern.dims; ++d) {
    const int k = pattern.axis[d];
    const double length = std::max(box.size[k], 0.0);
    const double part = pattern.part_size[k];
    const double step0 = pattern.step[d];
    if (step0 <= 0 || part <= 0) continue;
    // Number of parts if the spacing stayed as designed.
    const double ideal = (length - part) / step0 + 1.0;
    int n = 1;
    if (part_resizable[k]) {
      // Parts grow with the spacing (a row of planks): scale both, keep their ratio.
      n = std::max(1, static_cast<int>(std::lround(ideal)));
      const double step = length / ((n - 1) + part / step0);
      out.step[d] = n > 1 ? step : 0.0;
      out.part_size[k] = n > 1 ? part * step / step0 : length;
      out.count[d] = n;
      continue;
    }
    n = connecting ? static_cast<int>(std::ceil(ideal - 1e-9))
                   : static_cast<int>(std::lround(ideal));
    n = std::max(1, n);
    // Never so many that neighbours overlap: spacing at least one part.
    const int most = std::max(1, static_cast<int>(std::floor((length - part) / part + 1e-9)) + 1);
    n = std::min(n, most);
    out.count[d] = n;
    out.step[d] = n > 1 ? (length - part) / (n - 1) : 0.0;
  }
  return out;
}

std::vector<Box> pattern_part_boxes(const Pattern& pattern,
                                    const Box& box,
                                    bool connecting,
                                    const std::array<bool, 3>& part_resizable) {
  const PatternLayout layout = layout_pattern(pattern, box, connecting, part_resizable);
  std::vector<Box> out;
  const int n0 = layout.count[0];
  const int n1 = pattern.dims == 2 ? layout.count[1] : 1;
  for (int j = 0; j < n1; ++j) {
    for (int i = 0; i < n0; ++i) {
      Box b;
      b.size = box.size;  // across the pattern the part fills the box
      b.center = box.center;
      const std::array<int, 2> index{i, j};
      for (int d = 0; d < pattern.dims; ++d) {
        const int k = pattern.axis[d];
        const int n = layout.count[d];
        b.size[k] = layout.part_size[k];
        if (n == 1) {
          b.center[k] = box.center[k];
          if (part_resizable[k]) b.size[k] = box.size[k];
        } else {
          b.center[k] = box.min()[k] + 0.5 * layout.part_size[k] + index[d] * layout.step[d];
        }
      }
      out.push_back(b);
    }
  }
  return out;
}

}  // namespace fabkit::templates
