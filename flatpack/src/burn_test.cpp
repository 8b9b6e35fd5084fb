// The burn-test sheet: fingers, dents and slots drawn with fabkit's joint widths for a grid of
// kerfs and interferences.
#include "fabkit/flatpack/burn_test.h"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "fabkit/core/dxf.h"
#include "fabkit/core/file_io.h"
#include "fabkit/flatpack/build.h"
#include "fabkit/flatpack/diagnostic_codes.h"
#include "fabkit/flatpack/joint_widths.h"

namespace fabkit::flatpack {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

// A whole token as a finite number, or nullopt.
std::optional<double> number(const std::string& token) {
  const std::string t = trim(token);
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (errno != 0 || end != t.c_str() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string list_of(const std::vector<double>& v) {
  std::vector<std::string> parts;
  for (double x : v) parts.push_back(fmt::format("{:g}", x));
  return fmt::format("{}", fmt::join(parts, ", "));
}

}  // namespace

std::vector<double> parse_value_list(const std::string& text,
                                     const std::string& what,
                                     Diagnostics& diags) {
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    std::vector<std::string> parts;
    for (std::size_t p = 0;;) {
      const std::size_t colon = item.find(':', p);
      parts.push_back(item.substr(p, colon == std::string::npos ? std::string::npos : colon - p));
      if (colon == std::string::npos) break;
      p = colon + 1;
    }
    std::vector<double> values;
    for (const std::string& p : parts) {
      if (auto v = number(p)) values.push_back(*v);
    }
    if (values.size() != parts.size() || (parts.size() != 1 && parts.size() != 3)) {
      diags.error(codes::kInvalidValue,
                  fmt::format("{}: '{}' is not a value in mm, a list '0.1,0.15' or a range "
                              "'start:stop:step' like '0.05:0.25:0.05'",
                              what,
                              trim(item)));
      return {};
    }
    if (parts.size() == 1) {
      out.push_back(values[0]);
    } else {
      const double from = values[0], to = values[1], step = values[2];
      if (!(step > 0) || to < from) {
        diags.error(
            codes::kInvalidValue,
            fmt::format(
                "{}: the range '{}' needs start ≤ stop and a step > 0 mm", what, trim(item)));
        return {};
      }
      const double n = std::floor((to - from) / step + 1e-9);
      if (n >= BurnTestOptions::kMaxValues) {
        diags.error(codes::kLimitExceeded,
                    fmt::format("{}: the range '{}' has {:g} values; at most {} fit a sheet",
                                what,
                                trim(item),
                                n + 1,
                                BurnTestOptions::kMaxValues));
        return {};
      }
      for (int k = 0; k <= static_cast<int>(n); ++k) {
        // Rounded to 0.1 µm so that labels read 0.15, not 0.15000000000000002.
        out.push_back(std::round((from + k * step) * 1e7) / 1e7);
      }
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

BurnTest burn_test(const BurnTestOptions& o) {
  BurnTest r;
  const double t = o.material.thickness_mm;
  if (!(t > 0 && t <= 50)) {
    r.diagnostics.error(
        codes::kInvalidValue,
        fmt::format("burn test: board thickness {:g} mm must be more than 0 and at most 50 mm", t));
  }
  const double w = o.finger_width_mm > 0 ? o.finger_width_mm : 3 * t;
  if (o.finger_width_mm < 0 || (o.finger_width_mm > 0 && o.finger_width_mm < 1) ||
      o.finger_width_mm > 200) {
    r.diagnostics.error(
        codes::kInvalidValue,
        fmt::format("burn test: finger width {:g} mm must be between 1 and 200 mm (0: 3 × the "
                    "thickness)",
                    o.finger_width_mm));
  }
  auto check_list = [&](const std::vector<double>& v, const char* what, double lo, double hi) {
    if (v.empty()) {
      r.diagnostics.error(codes::kInvalidValue, fmt::format("burn test: no {} values", what));
    } else if (static_cast<int>(v.size()) > BurnTestOptions::kMaxValues) {
      r.diagnostics.error(codes::kLimitExceeded,
                          fmt::format("burn test: {} {} values; at most {} fit a sheet",
                                      v.size(),
                                      what,
                                      BurnTestOptions::kMaxValues));
    }
    for (double x : v) {
      if (!(x >= lo && x <= hi)) {
        r.diagnostics.error(codes::kInvalidValue,
                            fmt::format("burn test: {} {:g} mm is outside {:g} … {:g} mm (the {} "
                                        "values are {})",
                                        what,
                                        x,
                                        lo,
                                        hi,
                                        what,
                                        list_of(v)));
        break;
      }
    }
  };
  check_list(o.kerfs_mm, "kerf", 0, 2);
  check_list(o.interferences_mm, "interference", -1, 1);
  if (r.diagnostics.has_errors()) return r;

  const double gap = std::max(4.0, t), label_h = std::clamp(t, 3.0, 5.0), spacing = 10, margin = 5;
  const double strip = 7 * w;
  const double cell_h = 3 * t + gap + 4 * t + 4 + label_h;
  const auto cols = static_cast<double>(o.interferences_mm.size());
  const auto rows = static_cast<double>(o.kerfs_mm.size());
  r.sheet.name = fmt::format("burn test, {} {:g} mm", o.material.name, t);
  r.sheet.width_mm = 2 * margin + cols * strip + (cols - 1) * spacing;
  r.sheet.height_mm = 2 * margin + rows * cell_h + (rows - 1) * spacing;
  for (std::size_t row = 0; row < o.kerfs_mm.size(); ++row) {
    for (std::size_t col = 0; col < o.interferences_mm.size(); ++col) {
      const double kerf = o.kerfs_mm[row], fit = o.interferences_mm[col];
      const DrawnWidths dw = finger_and_opening(w, kerf, fit);
      const double slot = slot_width(t, kerf, fit);
      if (dw.opening_mm < 0.2 || slot < 0.2) {
        r.diagnostics.error(
            codes::kInvalidValue,
            fmt::format("burn test: with kerf {:g} mm and interference {:g} mm a dent would be "
                        "drawn {:.2f} mm and a slot {:.2f} mm wide; use smaller values or wider "
                        "fingers",
                        kerf,
                        fit,
                        dw.opening_mm,
                        slot));
        r.sheet = {};
        r.cells.clear();
        return r;
      }
      const double x0 = margin + static_cast<double>(col) * (strip + spacing);
      const double y0 = margin + static_cast<double>(row) * (cell_h + spacing);
      const double yd = y0 + 3 * t + gap;  // the dent strip's lower edge
      Region2d comb{rectangle(x0, y0, x0 + strip, y0 + 2 * t)};
      Region2d dents{rectangle(x0, yd, x0 + strip, yd + 4 * t)};
      Region2d add, cut;
      for (int k = 0; k < 3; ++k) {
        const double c = x0 + w * (1.5 + 2 * k);  // finger k's centre line
        // Fingers reach 0.05 mm into the bar so the union is one piece.
        add.push_back(
            rectangle(c - dw.finger_mm / 2, y0 + 2 * t - 0.05, c + dw.finger_mm / 2, y0 + 3 * t));
        // Dents open past the strip's edge (1 mm) so the cut runs clean.
        cut.push_back(rectangle(c - dw.opening_mm / 2, yd - 1, c + dw.opening_mm / 2, yd + t));
      }
      const double c = x0 + strip / 2;
      cut.push_back(rectangle(c - slot / 2, yd + 2 * t, c + slot / 2, yd + 4 * t + 1));
      for (const Polygon2d& p : unite(comb, add)) r.sheet.add_cut(p);
      for (const Polygon2d& p : subtract(dents, cut)) r.sheet.add_cut(p);
      r.sheet.labels.push_back({fmt::format("Δ {:g} δ {:g}", kerf, fit),
                                Vec2(c, yd + 4 * t + 2 + label_h / 2),
                                label_h,
                                0});
      BurnTestCell cell{kerf, fit, dw.finger_mm, dw.opening_mm, slot, {}};
      cell.box.extend(Vec2(x0, y0));
      cell.box.extend(Vec2(x0 + strip, y0 + cell_h));
      r.cells.push_back(cell);
    }
  }
  return r;
}

std::vector<std::filesystem::path> write_burn_test(const BurnTest& test,
                                                   const std::filesystem::path& dir,
                                                   Diagnostics& diags) {
  std::vector<std::filesystem::path> written;
  if (!make_output_directory(dir, diags)) return written;
  const std::array<std::filesystem::path, 2> files{dir / "burn-test.svg", dir / "burn-test.dxf"};
  if (!outputs_writable(files, diags)) return written;
  if (write_svg_sheet(dir / "burn-test.svg", test.sheet, diags))
    written.push_back(dir / "burn-test.svg");
  if (write_dxf(dir / "burn-test.dxf", for_dxf(test.sheet), diags))
    written.push_back(dir / "burn-test.dxf");
  return written;
}

}  // namespace fabkit::flatpack
