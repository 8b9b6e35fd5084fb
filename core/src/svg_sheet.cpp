#include "fabkit/core/svg_sheet.h"

#include <fmt/format.h>

#include "fabkit/core/file_io.h"
#include "fabkit/core/text.h"

namespace fabkit {

void CutSheet::add_cut(const Polygon2d& polygon) {
  outlines.push_back({polygon.outer, SheetLayer::kCut});
  for (const Ring& hole : polygon.holes) outlines.push_back({hole, SheetLayer::kCut});
}

std::string svg_sheet(const CutSheet& sheet, const SvgSheetOptions& options) {
  const int dp = options.decimals;
  auto num = [dp](double v) {
    std::string s = fmt::format("{:.{}f}", v + 0.0, dp);
    // Trim trailing zeros: smaller files, same numbers.
    if (s.find('.') != std::string::npos) {
      while (s.back() == '0') s.pop_back();
      if (s.back() == '.') s.pop_back();
    }
    return s == "-0" ? std::string("0") : s;
  };
  const double h = sheet.height_mm;
  std::string out;
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  out += fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" "
      "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" "
      "xmlns:sodipodi=\"http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd\" version=\"1.1\" "
      "width=\"{}mm\" height=\"{}mm\" viewBox=\"0 0 {} {}\">\n",
      num(sheet.width_mm),
      num(h),
      num(sheet.width_mm),
      num(h));
  out += fmt::format("  <title>{}</title>\n", xml_escape(sheet.name));
  // Inkscape reads its display units from here; the viewBox alone already fixes the scale.
  out += "  <sodipodi:namedview inkscape:document-units=\"mm\" units=\"mm\"/>\n";
  for (SheetLayer layer : {SheetLayer::kCut, SheetLayer::kEngrave}) {
    const bool cut = layer == SheetLayer::kCut;
    const std::string& color = cut ? options.cut_color : options.engrave_color;
    out += fmt::format(
        "  <g id=\"{0}\" inkscape:label=\"{0}\" inkscape:groupmode=\"layer\" fill=\"none\" "
        "stroke=\"{1}\" stroke-width=\"{2}\">\n",
        cut ? "cut" : "engrave",
        color,
        num(options.stroke_width_mm));
    for (const SheetOutline& o : sheet.outlines) {
      if (o.layer != layer || o.points.size() < 2) continue;
      std::string d;
      for (std::size_t i = 0; i < o.points.size(); ++i) {
        d += fmt::format("{}{} {} ", i ? "L" : "M", num(o.points[i].x()), num(h - o.points[i].y()));
      }
      d += "Z";
      out += fmt::format("    <path d=\"{}\"/>\n", d);
    }
    for (const SheetLabel& l : sheet.labels) {
      if (l.layer != layer) continue;
      const std::string x = num(l.position.x()), y = num(h - l.position.y());
      out += fmt::format(
          "    <text x=\"{}\" y=\"{}\" font-family=\"{}\" font-size=\"{}\" text-anchor=\"middle\" "
          "dominant-baseline=\"central\" fill=\"{}\" stroke=\"none\"{}>{}</text>\n",
          x,
          y,
          xml_escape(options.font_family),
          num(l.height_mm),
          color,
          l.rotation_deg != 0
              ? fmt::format(" transform=\"rotate({} {} {})\"", num(-l.rotation_deg), x, y)
              : std::string(),
          xml_escape(l.text));
    }
    out += "  </g>\n";
  }
  out += "</svg>\n";
  return out;
}

bool write_svg_sheet(const std::filesystem::path& path,
                     const CutSheet& sheet,
                     Diagnostics& diags,
                     const SvgSheetOptions& options) {
  return write_file_atomically(path, svg_sheet(sheet, options), diags);
}

}  // namespace fabkit
