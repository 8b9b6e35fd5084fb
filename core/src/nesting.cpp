// Nesting: validation, fit checks and bookkeeping here; the libnest2d call itself is in
// nest2d_backend.cpp.
#include "fabkit/core/nesting.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <optional>

#include "nest2d_backend.h"

namespace fabkit {
namespace {

constexpr double kCoordsPerMm = 1e6;  // libnest2d's clipper backend: 1 nm per coordinate

std::vector<std::pair<std::int64_t, std::int64_t>> to_coords(const Ring& ring) {
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  for (const Vec2& p : ring) {
    out.emplace_back(std::llround(p.x() * kCoordsPerMm), std::llround(p.y() * kCoordsPerMm));
  }
  return out;
}

// Size of the piece's bounding box when turned by `degrees`.
Vec2 turned_size(const Polygon2d& piece, double degrees) {
  return bounds(transformed(piece.outer, degrees, Vec2::Zero())).size();
}

}  // namespace

Diagnostics NestingOptions::validate() const {
  Diagnostics d;
  auto bad = [&](std::string message) { d.error(codes::kInvalidValue, std::move(message)); };
  if (!(sheet_width_mm > 0) || !(sheet_height_mm > 0) || sheet_width_mm > 1e5 ||
      sheet_height_mm > 1e5) {
    bad(fmt::format("sheet size {} × {} mm must be positive and at most 100 m",
                    sheet_width_mm,
                    sheet_height_mm));
  }
  if (!(spacing_mm >= 0) || !(margin_mm >= 0)) {
    bad(fmt::format(
        "sheet spacing {} mm and margin {} mm must not be negative", spacing_mm, margin_mm));
  }
  if (2 * margin_mm >= std::min(sheet_width_mm, sheet_height_mm)) {
    bad(fmt::format("sheet margin {} mm leaves no room on a {} × {} mm sheet",
                    margin_mm,
                    sheet_width_mm,
                    sheet_height_mm));
  }
  if (rotations_deg.empty()) bad("nesting needs at least one allowed rotation (e.g. [0])");
  for (double r : rotations_deg) {
    if (!std::isfinite(r)) bad("nesting rotations must be finite numbers of degrees");
  }
  if (!(accuracy > 0 && accuracy <= 1))
    bad(fmt::format("nesting accuracy {} must be in (0, 1]", accuracy));
  if (max_sheets < 1) bad(fmt::format("max sheets {} must be at least 1", max_sheets));
  return d;
}

Polygon2d placed(const Polygon2d& piece, const NestedPlacement& placement) {
  return transformed(piece, placement.rotation_deg, placement.translation);
}

NestingResult nest(const std::vector<Polygon2d>& pieces,
                   const std::vector<std::string>& names,
                   const NestingOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  NestingResult result;
  result.placements.resize(pieces.size());
  result.diagnostics = options.validate();
  if (result.diagnostics.has_errors()) return result;

  const double usable_w = options.sheet_width_mm - 2 * options.margin_mm;
  const double usable_h = options.sheet_height_mm - 2 * options.margin_mm;
  auto name_of = [&](std::size_t i) {
    return i < names.size() ? names[i] : fmt::format("piece {}", i + 1);
  };

  // Pieces that cannot fit at any allowed rotation are reported, not handed to the placer.
  detail::Nest2dInput input;
  std::vector<std::size_t> item_piece;
  std::vector<double> base_rotations;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (pieces[i].empty()) continue;
    bool fits = false;
    double base_rotation = 0;
    for (double r : options.rotations_deg) {
      const Vec2 s = turned_size(pieces[i], r);
      if (s.x() <= usable_w + 1e-9 && s.y() <= usable_h + 1e-9 && !fits) {
        fits = true;
        base_rotation = r;
      }
    }
    if (!fits) {
      const Vec2 s = turned_size(pieces[i], 0);
      result.unplaced.push_back(static_cast<int>(i));
      result.diagnostics.error(
          codes::kLimitExceeded,
          fmt::format(
              "{} ({:.1f} × {:.1f} mm) does not fit on a {:g} × {:g} mm sheet with a {:g} mm "
              "margin at any allowed rotation; use larger sheets or split the piece",
              name_of(i),
              s.x(),
              s.y(),
              options.sheet_width_mm,
              options.sheet_height_mm,
              options.margin_mm));
      continue;
    }
    // Holes are not offered to the placer: no piece is nested inside another's cut-out, so a
    // hole's scrap stays whole.
    // libnest2d drops pieces whose unturned box does not fit, so a piece that fits only turned
    // is handed over turned (allowed rotations are meant to compose: 0/90/180/270, 0/180).
    input.outlines.push_back(to_coords(transformed(pieces[i].outer, base_rotation, Vec2::Zero())));
    base_rotations.push_back(base_rotation);
    item_piece.push_back(i);
  }
  for (double r : options.rotations_deg) input.rotations_rad.push_back(r * M_PI / 180);
  input.accuracy = options.accuracy;
  const auto mm = [](double v) {
    return static_cast<std::int64_t>(std::llround(v * kCoordsPerMm));
  };
  input.bin_min_x = input.bin_min_y = mm(options.margin_mm);
  input.bin_max_x = mm(options.sheet_width_mm - options.margin_mm);
  input.bin_max_y = mm(options.sheet_height_mm - options.margin_mm);
  input.spacing = mm(options.spacing_mm);
  bool timed_out = false;
  // libnest2d asks between placements, and one placement (its no-fit polygons against what is
  // on the sheet) takes milliseconds: a placement that would not end before the deadline,
  // judged by the longest gap between two questions so far, is not started.
  using Clock = std::chrono::steady_clock;
  std::optional<Clock::time_point> asked;
  Clock::duration longest{};
  if (options.deadline) {
    const auto deadline = *options.deadline;
    input.stop = [deadline, &timed_out, &asked, &longest] {
      const auto now = Clock::now();
      if (asked) longest = std::max(longest, now - *asked);
      asked = now;
      timed_out = timed_out || now + longest > deadline;
      return timed_out;
    };
  }
  const detail::Nest2dOutput output = detail::run_nest2d(input);
  if (!output.error.empty()) {
    result.diagnostics.error(codes::kInternalError,
                             fmt::format("nesting failed: {}", output.error));
    return result;
  }
  const std::size_t bins = static_cast<std::size_t>(output.bins);
  std::vector<double> used_area(bins, 0.0);
  for (std::size_t k = 0; k < item_piece.size(); ++k) {
    const std::size_t i = item_piece[k];
    const int sheet = output.placements[k].bin;
    if (sheet < 0 || sheet >= options.max_sheets) {
      result.unplaced.push_back(static_cast<int>(i));
      if (!timed_out) {
        result.diagnostics.error(
            codes::kLimitExceeded,
            fmt::format("{} was not nested within {} sheets", name_of(i), options.max_sheets));
      }
      continue;
    }
    NestedPlacement& p = result.placements[i];
    p.sheet = sheet;
    p.rotation_deg =
        std::fmod(output.placements[k].rotation_rad * 180 / M_PI + base_rotations[k], 360.0);
    p.translation = Vec2(static_cast<double>(output.placements[k].x) / kCoordsPerMm,
                         static_cast<double>(output.placements[k].y) / kCoordsPerMm);
    used_area[static_cast<std::size_t>(sheet)] += pieces[i].area();
  }
  std::sort(result.unplaced.begin(), result.unplaced.end());
  if (timed_out && !result.unplaced.empty()) {
    // One finding, with the best result so far: what was placed stays placed.
    std::string not_nested;
    for (std::size_t k = 0; k < result.unplaced.size() && k < 8; ++k) {
      not_nested += (k ? ", " : "") + name_of(static_cast<std::size_t>(result.unplaced[k]));
    }
    if (result.unplaced.size() > 8)
      not_nested += fmt::format(" and {} more", result.unplaced.size() - 8);
    result.diagnostics.error(
        codes::kTimeLimit,
        fmt::format("nesting stopped at the deadline after placing {} of {} pieces on {} sheet{} "
                    "(the best result so far); not nested: {}",
                    item_piece.size() - result.unplaced.size(),
                    item_piece.size(),
                    output.bins,
                    output.bins == 1 ? "" : "s",
                    not_nested));
  }
  result.sheet_count = static_cast<int>(bins);
  const double sheet_area = options.sheet_width_mm * options.sheet_height_mm;
  double total = 0;
  for (double a : used_area) {
    result.sheet_utilisation.push_back(a / sheet_area);
    total += a;
  }
  result.utilisation = bins ? total / (sheet_area * static_cast<double>(bins)) : 0;
  result.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace fabkit
