// FreeType outlines, flattened to rings; the only translation unit including FreeType.
#include "fabkit/core/glyph_outline.h"

#include <fmt/format.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

#include <algorithm>
#include <cmath>

#include "fabkit/core/text.h"

namespace fabkit {
namespace {

using Point = Eigen::Vector2d;

struct Flattener {
  double scale = 1;      // mm per font unit
  double tolerance = 0;  // mm
  Point offset = Point::Zero();
  std::vector<std::vector<Point>> rings;
  Point last = Point::Zero();

  Point at(const FT_Vector* v) const {
    return offset + scale * Point(static_cast<double>(v->x), static_cast<double>(v->y));
  }
  // Enough segments that a curve spanning `extent` mm stays within the tolerance.
  int segments(double extent) const {
    return std::clamp(static_cast<int>(std::ceil(std::sqrt(extent / (8 * tolerance)) * 2)), 1, 64);
  }
  void add(const Point& p) {
    if (rings.back().empty() || (rings.back().back() - p).norm() > 1e-9) rings.back().push_back(p);
    last = p;
  }
};

int move_to(const FT_Vector* to, void* user) {
  auto* f = static_cast<Flattener*>(user);
  f->rings.emplace_back();
  f->add(f->at(to));
  return 0;
}
int line_to(const FT_Vector* to, void* user) {
  auto* f = static_cast<Flattener*>(user);
  f->add(f->at(to));
  return 0;
}
int conic_to(const FT_Vector* control, const FT_Vector* to, void* user) {
  auto* f = static_cast<Flattener*>(user);
  const Point p0 = f->last, p1 = f->at(control), p2 = f->at(to);
  const int n = f->segments((p1 - p0).norm() + (p2 - p1).norm());
  for (int i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    f->add((1 - t) * (1 - t) * p0 + 2 * (1 - t) * t * p1 + t * t * p2);
  }
  return 0;
}
int cubic_to(const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* user) {
  auto* f = static_cast<Flattener*>(user);
  const Point p0 = f->last, p1 = f->at(c1), p2 = f->at(c2), p3 = f->at(to);
  const int n = f->segments((p1 - p0).norm() + (p2 - p1).norm() + (p3 - p2).norm());
  for (int i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) / n, u = 1 - t;
    f->add(u * u * u * p0 + 3 * u * u * t * p1 + 3 * u * t * t * p2 + t * t * t * p3);
  }
  return 0;
}

// Decodes UTF-8 (already validated) into code points.
std::vector<char32_t> code_points(std::string_view s) {
  std::vector<char32_t> out;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80 ? 1 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
    char32_t cp = n == 1 ? c : n == 2 ? (c & 0x1F) : n == 3 ? (c & 0x0F) : (c & 0x07);
    for (int k = 1; k < n && i + static_cast<std::size_t>(k) < s.size(); ++k) {
      cp = (cp << 6) | (static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]) & 0x3F);
    }
    out.push_back(cp);
    i += static_cast<std::size_t>(n);
  }
  return out;
}

double ring_area(const std::vector<Point>& ring) {
  double a = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point& p = ring[i];
    const Point& q = ring[(i + 1) % ring.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return a / 2;
}

bool inside(const Point& p, const std::vector<Point>& ring) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Point& a = ring[i];
    const Point& b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      in = !in;
    }
  }
  return in;
}

}  // namespace

std::string default_font_file() {
  return "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf";
}

double TextOutline::area() const {
  // A ring inside an odd number of others is a hole.
  double total = 0;
  for (std::size_t i = 0; i < rings.size(); ++i) {
    int depth = 0;
    for (std::size_t j = 0; j < rings.size(); ++j) {
      if (i != j && !rings[i].empty() && inside(rings[i].front(), rings[j])) ++depth;
    }
    total += (depth % 2 == 0 ? 1 : -1) * std::abs(ring_area(rings[i]));
  }
  return total;
}

std::optional<TextOutline> text_outline(std::string_view text,
                                        const TextOutlineOptions& options,
                                        Diagnostics& diags) {
  if (!is_valid_utf8(text)) {
    diags.error(codes::kInvalidValue, "text to outline is not valid UTF-8");
    return std::nullopt;
  }
  if (!(options.em_size > 0) || !(options.tolerance > 0) || !std::isfinite(options.em_size)) {
    diags.error(codes::kInvalidValue,
                fmt::format("text size {} mm and tolerance {} mm must be positive",
                            options.em_size,
                            options.tolerance));
    return std::nullopt;
  }
  const std::string font = options.font_file.empty() ? default_font_file() : options.font_file;
  FT_Library library = nullptr;
  if (FT_Init_FreeType(&library) != 0) {
    diags.error(codes::kInternalError, "FreeType cannot start");
    return std::nullopt;
  }
  FT_Face face = nullptr;
  if (FT_New_Face(library, font.c_str(), 0, &face) != 0) {
    FT_Done_FreeType(library);
    diags.error(
        codes::kUnreadableFile,
        fmt::format("cannot open font '{}' (Debian: apt-get install fonts-dejavu-core)", font));
    return std::nullopt;
  }
  Flattener flat;
  flat.scale = options.em_size / static_cast<double>(face->units_per_EM);
  flat.tolerance = options.tolerance;
  FT_Outline_Funcs funcs{};
  funcs.move_to = move_to;
  funcs.line_to = line_to;
  funcs.conic_to = conic_to;
  funcs.cubic_to = cubic_to;
  bool ok = true;
  double pen = 0;
  for (const char32_t cp : code_points(text)) {
    const FT_UInt glyph = FT_Get_Char_Index(face, cp);
    if (glyph == 0 || FT_Load_Glyph(face, glyph, FT_LOAD_NO_SCALE) != 0 ||
        face->glyph->format != FT_GLYPH_FORMAT_OUTLINE) {
      diags.error(
          codes::kInvalidValue,
          fmt::format(
              "font '{}' has no outline for character U+{:04X}", font, static_cast<unsigned>(cp)));
      ok = false;
      break;
    }
    flat.offset = Point(pen, 0);
    FT_Outline_Decompose(&face->glyph->outline, &funcs, &flat);
    pen += flat.scale * static_cast<double>(face->glyph->advance.x);
  }
  FT_Done_Face(face);
  FT_Done_FreeType(library);
  if (!ok) return std::nullopt;

  TextOutline out;
  out.advance = pen;
  out.min = Point::Constant(1e300);
  out.max = Point::Constant(-1e300);
  for (auto& ring : flat.rings) {
    if (ring.size() > 1 && (ring.front() - ring.back()).norm() < 1e-9) ring.pop_back();
    if (ring.size() < 3 || std::abs(ring_area(ring)) < 1e-12) continue;
    for (const Point& p : ring) {
      out.min = out.min.cwiseMin(p);
      out.max = out.max.cwiseMax(p);
    }
    out.rings.push_back(std::move(ring));
  }
  if (out.rings.empty()) out.min = out.max = Point::Zero();
  return out;
}

}  // namespace fabkit
