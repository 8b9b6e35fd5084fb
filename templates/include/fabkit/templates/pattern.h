#pragma once
/// The deformation function F of a pattern element (paper Appendix A): given the pattern's new
/// box, the number of parts l and the generator translation p along each direction.

#include <vector>

#include "fabkit/templates/template.h"

namespace fabkit::templates {

/// How a pattern fills a box.
struct PatternLayout {
  std::array<int, 2> count{1, 1};
  std::array<double, 2> step{0, 0};  ///< mm between neighbouring part centres
  Vec3 part_size = Vec3::Zero();     ///< mm (scaled along a direction where parts resize)
};

/// Recomputes count and spacing for `box`: the spacing stays as close to the design's as
/// possible; connecting patterns (screws) round the count up, so spacing never grows beyond
/// the design's (conservative, for holding power); no spacing ever drops below the part size,
/// so parts never intersect; parts resizable along a direction (planks cut to width) are
/// scaled with the spacing. `part_resizable` is per world axis.
PatternLayout layout_pattern(const Pattern& pattern,
                             const Box& box,
                             bool connecting,
                             const std::array<bool, 3>& part_resizable);

/// The part boxes of that layout (first part at the box's low corner), row by row.
std::vector<Box> pattern_part_boxes(const Pattern& pattern,
                                    const Box& box,
                                    bool connecting,
                                    const std::array<bool, 3>& part_resizable);

}  // namespace fabkit::templates
