// libnest2d (header-only: Boost.Geometry, Clipper and NLopt underneath) is included here and
// nowhere else.
#include "nest2d_backend.h"

#include <exception>
#include <libnest2d/libnest2d.hpp>

namespace fabkit::detail {

Nest2dOutput run_nest2d(const Nest2dInput& input) {
  namespace ln = libnest2d;
  Nest2dOutput out;
  std::vector<ln::Item> items;
  items.reserve(input.outlines.size());
  for (const auto& outline : input.outlines) {
    // libnest2d's clipper backend wants clockwise, explicitly closed contours.
    ClipperLib::Path path;
    for (auto it = outline.rbegin(); it != outline.rend(); ++it)
      path.emplace_back(it->first, it->second);
    if (!path.empty()) path.push_back(path.front());
    // The clipper backend's no-fit polygons are exact for convex shapes only: nesting the
    // convex hull is conservative (nothing goes into an L's corner) but never overlaps.
    items.emplace_back(ln::sl::convexHull(ClipperLib::Polygon(path)));
  }
  using Placer = ln::NfpPlacer;
  ln::NestConfig<Placer, ln::FirstFitSelection> config;
  config.placer_config.rotations.clear();
  for (double r : input.rotations_rad) config.placer_config.rotations.emplace_back(r);
  config.placer_config.alignment = Placer::Config::Alignment::BOTTOM_LEFT;
  config.placer_config.starting_point = Placer::Config::Alignment::BOTTOM_LEFT;
  config.placer_config.accuracy = static_cast<float>(input.accuracy);
  config.placer_config.parallel = false;  // same input, same layout
  ln::NestControl control;
  if (input.stop) control.stopcond = input.stop;
  const ln::Box bin(ln::Point(input.bin_min_x, input.bin_min_y),
                    ln::Point(input.bin_max_x, input.bin_max_y));
  try {
    if (!items.empty()) {
      out.bins = static_cast<int>(
          ln::nest<Placer, ln::FirstFitSelection>(items, bin, input.spacing, config, control));
    }
  } catch (const std::exception& e) {
    out.error = e.what();
    return out;
  }
  for (const ln::Item& item : items) {
    Nest2dPlacement p;
    p.bin = item.binId();
    p.rotation_rad = static_cast<double>(item.rotation());
    const auto t = item.translation();
    p.x = ln::getX(t);
    p.y = ln::getY(t);
    out.placements.push_back(p);
  }
  return out;
}

}  // namespace fabkit::detail
