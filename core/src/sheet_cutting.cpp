// Guillotine sheet cutting: free-rectangle heuristic over several orderings.
#include "fabkit/core/sheet_cutting.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "fabkit/core/text.h"

namespace fabkit {

namespace {

struct FreeRect {
  double x, y, l, w;  // in kerf-inflated coordinates
};

struct Packing {
  std::vector<SheetCut> sheets;
  std::vector<std::vector<FreeRect>> free;
};

// Places pieces in `order` (kerf-inflated sizes inside a kerf-inflated usable sheet).
Packing pack(std::span<const SheetPiece> pieces,
             const std::vector<int>& order,
             const SheetSpec& s) {
  const double k = s.kerf;
  const double L = s.usable_length() + k, W = s.usable_width() + k;
  const double off = s.edge_trim;
  Packing p;
  for (int i : order) {
    const SheetPiece& piece = pieces[i];
    const double pl = piece.length + k, pw = piece.width + k;
    // Best short-side fit over every sheet's free rectangles, both orientations allowed.
    int best_sheet = -1, best_rect = -1;
    bool best_rot = false;
    double best_short = std::numeric_limits<double>::infinity(), best_long = best_short;
    for (std::size_t sh = 0; sh < p.free.size(); ++sh) {
      for (std::size_t r = 0; r < p.free[sh].size(); ++r) {
        const FreeRect& f = p.free[sh][r];
        for (bool rot : {false, true}) {
          if (rot && !piece.may_rotate) continue;
          const double a = rot ? pw : pl, b = rot ? pl : pw;
          if (a > f.l + 1e-9 || b > f.w + 1e-9) continue;
          const double sshort = std::min(f.l - a, f.w - b), slong = std::max(f.l - a, f.w - b);
          if (sshort < best_short - 1e-9 ||
              (std::abs(sshort - best_short) <= 1e-9 && slong < best_long)) {
            best_short = sshort;
            best_long = slong;
            best_sheet = static_cast<int>(sh);
            best_rect = static_cast<int>(r);
            best_rot = rot;
          }
        }
      }
    }
    if (best_sheet < 0) {
      p.sheets.emplace_back();
      p.free.push_back({FreeRect{0, 0, L, W}});
      best_sheet = static_cast<int>(p.sheets.size()) - 1;
      best_rect = 0;
      best_rot = !(pl <= L + 1e-9 && pw <= W + 1e-9);
    }
    const FreeRect f = p.free[best_sheet][best_rect];
    p.free[best_sheet].erase(p.free[best_sheet].begin() + best_rect);
    const double a = best_rot ? pw : pl, b = best_rot ? pl : pw;
    SheetPlacement pl_out;
    pl_out.piece = i;
    pl_out.x = off + f.x;
    pl_out.y = off + f.y;
    pl_out.length = a - k;
    pl_out.width = b - k;
    pl_out.rotated = best_rot;
    SheetCut& sheet = p.sheets[best_sheet];
    sheet.pieces.push_back(pl_out);
    sheet.used_area += piece.length * piece.width;
    // Split the leftover along the shorter axis (two guillotine cuts at the kerf centres).
    const double right = f.l - a, top = f.w - b;
    const bool split_horizontal = right < top;  // cut across the full width first?
    const double cx = off + f.x + a - k / 2, cy = off + f.y + b - k / 2;
    if (split_horizontal) {
      // Horizontal cut over the free rectangle's whole length, then a vertical one beside the
      // piece.
      if (top > 1e-9) sheet.cuts.push_back({off + f.x, cy, off + f.x + f.l - k, cy});
      if (right > 1e-9) sheet.cuts.push_back({cx, off + f.y, cx, off + f.y + b - k});
      if (top > 1e-9) p.free[best_sheet].push_back({f.x, f.y + b, f.l, top});
      if (right > 1e-9) p.free[best_sheet].push_back({f.x + a, f.y, right, b});
    } else {
      if (right > 1e-9) sheet.cuts.push_back({cx, off + f.y, cx, off + f.y + f.w - k});
      if (top > 1e-9) sheet.cuts.push_back({off + f.x, cy, off + f.x + a - k, cy});
      if (right > 1e-9) p.free[best_sheet].push_back({f.x + a, f.y, right, f.w});
      if (top > 1e-9) p.free[best_sheet].push_back({f.x, f.y + b, a, top});
    }
  }
  return p;
}

double last_sheet_area(const Packing& p) {
  return p.sheets.empty() ? 0 : p.sheets.back().used_area;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace

double SheetPlan::utilisation(const SheetSpec& sheet) const {
  double used = 0;
  for (const SheetCut& s : sheets) used += s.used_area;
  const double total = sheet.usable_length() * sheet.usable_width() * std::max(1, sheet_count());
  return total > 0 ? used / total : 0;
}

std::optional<SheetPlan> plan_sheets(std::span<const SheetPiece> pieces,
                                     const SheetSpec& s,
                                     Diagnostics& diags,
                                     const SheetPlanOptions& options) {
  bool ok = true;
  auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!finite_positive(s.length) || !finite_positive(s.width) || !std::isfinite(s.kerf) ||
      s.kerf < 0 || !std::isfinite(s.edge_trim) || s.edge_trim < 0 || s.usable_length() <= 0 ||
      s.usable_width() <= 0) {
    diags.error(
        codes::kInvalidValue,
        fmt::format("sheet {:g} x {:g} mm with kerf {:g} mm and edge trim {:g} mm leaves no "
                    "usable area",
                    s.length,
                    s.width,
                    s.kerf,
                    s.edge_trim));
    return std::nullopt;
  }
  for (const SheetPiece& p : pieces) {
    if (!finite_positive(p.length) || !finite_positive(p.width)) {
      diags.error(codes::kInvalidValue,
                  fmt::format("piece '{}' has size {:g} x {:g} mm; sizes must be positive",
                              p.label,
                              p.length,
                              p.width));
      ok = false;
      continue;
    }
    const bool straight =
        p.length <= s.usable_length() + 1e-9 && p.width <= s.usable_width() + 1e-9;
    const bool turned =
        p.may_rotate && p.width <= s.usable_length() + 1e-9 && p.length <= s.usable_width() + 1e-9;
    if (!straight && !turned) {
      diags.error(
          codes::kPieceLargerThanSheet,
          fmt::format("piece '{}' ({:g} x {:g} mm{}) does not fit the usable {:g} x {:g} mm "
                      "of a {:g} x {:g} mm sheet",
                      p.label,
                      p.length,
                      p.width,
                      p.may_rotate ? "" : ", grain along the length",
                      s.usable_length(),
                      s.usable_width(),
                      s.length,
                      s.width));
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  SheetPlan plan;
  double area = 0;
  for (const SheetPiece& p : pieces) area += (p.length + s.kerf) * (p.width + s.kerf);
  plan.lower_bound =
      pieces.empty()
          ? 0
          : static_cast<int>(std::ceil(
                area / ((s.usable_length() + s.kerf) * (s.usable_width() + s.kerf)) - 1e-9));
  std::vector<std::vector<int>> orders;
  std::vector<int> base(pieces.size());
  std::iota(base.begin(), base.end(), 0);
  auto sorted = [&](auto key) {
    std::vector<int> o = base;
    std::stable_sort(
        o.begin(), o.end(), [&](int a, int b) { return key(pieces[a]) > key(pieces[b]); });
    return o;
  };
  orders.push_back(sorted([](const SheetPiece& p) { return p.length * p.width; }));
  orders.push_back(sorted([](const SheetPiece& p) { return std::max(p.length, p.width); }));
  orders.push_back(sorted([](const SheetPiece& p) { return p.length + p.width; }));
  orders.push_back(sorted([](const SheetPiece& p) { return std::min(p.length, p.width); }));
  std::mt19937 rng(options.seed);
  for (int i = 0; i < options.orderings; ++i) {
    std::vector<int> o = base;
    std::shuffle(o.begin(), o.end(), rng);
    orders.push_back(std::move(o));
  }
  std::optional<Packing> best;
  for (const auto& o : orders) {
    Packing p = pack(pieces, o, s);
    if (!best || p.sheets.size() < best->sheets.size() ||
        (p.sheets.size() == best->sheets.size() &&
         last_sheet_area(p) < last_sheet_area(*best) - 1e-6)) {
      best = std::move(p);
    }
    if (best->sheets.size() == static_cast<std::size_t>(plan.lower_bound) && plan.lower_bound <= 1)
      break;
  }
  plan.sheets = best ? best->sheets : std::vector<SheetCut>{};
  plan.meets_lower_bound = plan.sheet_count() == plan.lower_bound;
  plan.summary = fmt::format("{} sheet{} (lower bound {}), {:.0f} % of the usable area used",
                             plan.sheet_count(),
                             plan.sheet_count() == 1 ? "" : "s",
                             plan.lower_bound,
                             100 * plan.utilisation(s));
  return plan;
}

Diagnostics validate_sheet_plan(const SheetPlan& plan,
                                std::span<const SheetPiece> pieces,
                                const SheetSpec& s) {
  Diagnostics d;
  std::vector<int> seen(pieces.size(), 0);
  for (std::size_t sh = 0; sh < plan.sheets.size(); ++sh) {
    const auto& ps = plan.sheets[sh].pieces;
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const SheetPlacement& a = ps[i];
      if (a.piece < 0 || a.piece >= static_cast<int>(pieces.size())) {
        d.error(codes::kInternalError,
                fmt::format("sheet {}: piece index {} out of range", sh + 1, a.piece));
        continue;
      }
      ++seen[a.piece];
      const SheetPiece& p = pieces[a.piece];
      const double l = a.rotated ? p.width : p.length, w = a.rotated ? p.length : p.width;
      if (std::abs(a.length - l) > 1e-9 || std::abs(a.width - w) > 1e-9 ||
          (a.rotated && !p.may_rotate)) {
        d.error(codes::kInternalError,
                fmt::format("sheet {}: '{}' placed at the wrong size", sh + 1, p.label));
      }
      if (a.x < s.edge_trim - 1e-9 || a.y < s.edge_trim - 1e-9 ||
          a.x + a.length > s.length - s.edge_trim + 1e-9 ||
          a.y + a.width > s.width - s.edge_trim + 1e-9) {
        d.error(codes::kInternalError,
                fmt::format("sheet {}: '{}' outside the usable area", sh + 1, p.label));
      }
      for (std::size_t j = i + 1; j < ps.size(); ++j) {
        const SheetPlacement& b = ps[j];
        const bool apart =
            a.x + a.length + s.kerf <= b.x + 1e-9 || b.x + b.length + s.kerf <= a.x + 1e-9 ||
            a.y + a.width + s.kerf <= b.y + 1e-9 || b.y + b.width + s.kerf <= a.y + 1e-9;
        if (!apart) {
          d.error(codes::kInternalError,
                  fmt::format("sheet {}: '{}' and '{}' are closer than the {:g} mm kerf",
                              sh + 1,
                              p.label,
                              pieces[b.piece].label,
                              s.kerf));
        }
      }
    }
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (seen[i] != 1)
      d.error(codes::kInternalError, fmt::format("'{}' placed {} times", pieces[i].label, seen[i]));
  }
  return d;
}

std::string sheet_plan_svg(const SheetPlan& plan,
                           int index,
                           std::span<const SheetPiece> pieces,
                           const SheetSpec& s) {
  const double margin = 10;
  std::string out = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:g}mm\" height=\"{1:g}mm\" "
      "viewBox=\"{2:g} {2:g} "
      "{0:g} {1:g}\">\n",
      s.length + 2 * margin,
      s.width + 2 * margin,
      -margin);
  out += fmt::format(
      "  <rect x=\"0\" y=\"0\" width=\"{:g}\" height=\"{:g}\" fill=\"#f4e9d8\" stroke=\"#555\" "
      "stroke-width=\"0.5\"/>\n",
      s.length,
      s.width);
  if (s.edge_trim > 0) {
    out += fmt::format(
        "  <rect x=\"{0:g}\" y=\"{0:g}\" width=\"{1:g}\" height=\"{2:g}\" fill=\"none\" "
        "stroke=\"#999\" stroke-width=\"0.3\" stroke-dasharray=\"4 2\"/>\n",
        s.edge_trim,
        s.usable_length(),
        s.usable_width());
  }
  if (index < 0 || index >= plan.sheet_count()) return out + "</svg>\n";
  const SheetCut& sheet = plan.sheets[index];
  // SVG y runs down: flip so the sheet's origin is at the lower left, as in the plan.
  auto fy = [&](double y) { return s.width - y; };
  for (const SheetPlacement& p : sheet.pieces) {
    const SheetPiece& piece = pieces[p.piece];
    out += fmt::format(
        "  <rect x=\"{:g}\" y=\"{:g}\" width=\"{:g}\" height=\"{:g}\" fill=\"#d9c3a0\" "
        "stroke=\"#333\" stroke-width=\"0.3\"/>\n",
        p.x,
        fy(p.y + p.width),
        p.length,
        p.width);
    const double size = std::clamp(std::min(p.length, p.width) / 6, 3.0, 30.0);
    out += fmt::format(
        "  <text x=\"{:g}\" y=\"{:g}\" font-family=\"sans-serif\" font-size=\"{:g}\" "
        "text-anchor=\"middle\">{} {:g} x {:g}{}</text>\n",
        p.x + p.length / 2,
        fy(p.y + p.width / 2) + size / 3,
        size,
        xml_escape(piece.label),
        piece.length,
        piece.width,
        p.rotated ? " (turned)" : "");
  }
  for (const SheetCutLine& c : sheet.cuts) {
    out += fmt::format(
        "  <line x1=\"{:g}\" y1=\"{:g}\" x2=\"{:g}\" y2=\"{:g}\" stroke=\"#d00\" "
        "stroke-opacity=\"0.6\" stroke-width=\"{:g}\"/>\n",
        c.x0,
        fy(c.y0),
        c.x1,
        fy(c.y1),
        std::max(0.2, s.kerf));
  }
  return out + "</svg>\n";
}

std::string sheet_plan_csv(const SheetPlan& plan, std::span<const SheetPiece> pieces) {
  std::string out = "label,length_mm,width_mm,sheet,x_mm,y_mm,rotated\n";
  for (std::size_t sh = 0; sh < plan.sheets.size(); ++sh) {
    for (const SheetPlacement& p : plan.sheets[sh].pieces) {
      const SheetPiece& piece = pieces[p.piece];
      out += fmt::format("{},{:g},{:g},{},{:g},{:g},{}\n",
                         csv_field(piece.label),
                         piece.length,
                         piece.width,
                         sh + 1,
                         p.x,
                         p.y,
                         p.rotated ? "yes" : "no");
    }
  }
  return out;
}

}  // namespace fabkit
