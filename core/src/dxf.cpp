// dxflib writes to a named file only; we let it write a private temporary file and hand the
// bytes to write_file_atomically, so a failed write never leaves a partial DXF behind.
#include "fabkit/core/dxf.h"

#include <dxflib/dl_dxf.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "fabkit/core/file_io.h"

namespace fabkit {
namespace {

// dxflib opens its file by name: in a directory only this process may write in (mkdtemp: mode
// 0700, an unpredictable name), so no other user can plant a link where it writes, as they
// could at a predictable name in a shared /tmp.
class PrivateDirectory {
 public:
  PrivateDirectory() {
    std::error_code ec;
    std::filesystem::path base = std::filesystem::temp_directory_path(ec);
    if (ec) base = ".";
    std::string pattern = (base / "fabkit-dxf-XXXXXX").string();
    if (::mkdtemp(pattern.data())) path_ = pattern;
  }
  ~PrivateDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  PrivateDirectory(const PrivateDirectory&) = delete;
  PrivateDirectory& operator=(const PrivateDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

void write_sheet(DL_Dxf& dxf, DL_WriterA& dw, const CutSheet& sheet, const DxfOptions& o) {
  dxf.writeHeader(dw);
  dw.dxfString(9, "$INSUNITS");
  dw.dxfInt(70, 4);  // millimetres
  dw.dxfString(9, "$MEASUREMENT");
  dw.dxfInt(70, 1);  // metric
  dw.sectionEnd();

  dw.sectionTables();
  dxf.writeVPort(dw);
  dw.tableLinetypes(3);
  dxf.writeLinetype(dw, DL_LinetypeData("BYBLOCK", "BYBLOCK", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("BYLAYER", "BYLAYER", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("CONTINUOUS", "Continuous", 0, 0, 0.0));
  dw.tableEnd();
  dw.tableLayers(o.sheet_border ? 4 : 3);
  dxf.writeLayer(dw, DL_LayerData("0", 0), DL_Attributes("", 7, 0x00ffffff, 0, "CONTINUOUS"));
  dxf.writeLayer(
      dw, DL_LayerData(o.cut_layer, 0), DL_Attributes("", o.cut_color, -1, 0, "CONTINUOUS"));
  dxf.writeLayer(
      dw, DL_LayerData(o.label_layer, 0), DL_Attributes("", o.label_color, -1, 0, "CONTINUOUS"));
  if (o.sheet_border)
    dxf.writeLayer(dw, DL_LayerData("SHEET", 0), DL_Attributes("", 8, -1, 0, "CONTINUOUS"));
  dw.tableEnd();
  dw.tableStyle(1);
  dxf.writeStyle(dw, DL_StyleData("standard", 0, 0.0, 1.0, 0.0, 0, 2.5, "txt", ""));
  dw.tableEnd();
  dxf.writeView(dw);
  dxf.writeUcs(dw);
  dw.tableAppid(1);
  dxf.writeAppid(dw, "ACAD");
  dw.tableEnd();
  dxf.writeDimStyle(dw, 1, 1, 1, 1, 1);
  dxf.writeBlockRecord(dw);
  dw.tableEnd();
  dw.sectionEnd();

  dw.sectionBlocks();
  dxf.writeBlock(dw, DL_BlockData("*Model_Space", 0, 0.0, 0.0, 0.0));
  dxf.writeEndBlock(dw, "*Model_Space");
  dxf.writeBlock(dw, DL_BlockData("*Paper_Space", 0, 0.0, 0.0, 0.0));
  dxf.writeEndBlock(dw, "*Paper_Space");
  dxf.writeBlock(dw, DL_BlockData("*Paper_Space0", 0, 0.0, 0.0, 0.0));
  dxf.writeEndBlock(dw, "*Paper_Space0");
  dw.sectionEnd();

  dw.sectionEntities();
  auto polyline = [&](const Ring& ring, const DL_Attributes& a) {
    dxf.writePolyline(dw, DL_PolylineData(static_cast<int>(ring.size()), 0, 0, 1), a);  // 1: closed
    for (const Vec2& p : ring) dxf.writeVertex(dw, DL_VertexData(p.x(), p.y(), 0.0, 0.0));
    dxf.writePolylineEnd(dw);
  };
  const DL_Attributes cut(o.cut_layer, 256, -1, -1, "BYLAYER");  // colour and width by layer
  const DL_Attributes label(o.label_layer, 256, -1, -1, "BYLAYER");
  for (const SheetOutline& outline : sheet.outlines) {
    if (outline.points.size() >= 2)
      polyline(outline.points, outline.layer == SheetLayer::kCut ? cut : label);
  }
  if (o.sheet_border) {
    polyline({{0, 0}, {sheet.width_mm, 0}, {sheet.width_mm, sheet.height_mm}, {0, sheet.height_mm}},
             DL_Attributes("SHEET", 256, -1, -1, "BYLAYER"));
  }
  for (const SheetLabel& l : sheet.labels) {
    // Justification middle-centre (h = 1, v = 2) at the alignment point.
    dxf.writeText(dw,
                  DL_TextData(l.position.x(),
                              l.position.y(),
                              0.0,
                              l.position.x(),
                              l.position.y(),
                              0.0,
                              l.height_mm,
                              1.0,
                              0,
                              1,
                              2,
                              l.text,
                              "standard",
                              l.rotation_deg * M_PI / 180),
                  l.layer == SheetLayer::kCut ? cut : label);
  }
  dw.sectionEnd();
  dxf.writeObjects(dw);
  dxf.writeObjectsEnd(dw);
  dw.dxfEOF();
}

}  // namespace

std::optional<std::string> dxf_sheet(const CutSheet& sheet,
                                     Diagnostics& diags,
                                     const DxfOptions& options) {
  const PrivateDirectory dir;
  if (dir.path().empty()) {
    diags.error(codes::kWriteFailed, "cannot create a private temporary directory for a DXF");
    return std::nullopt;
  }
  const std::filesystem::path tmp = dir.path() / "sheet.dxf";
  {
    DL_Dxf dxf;
    std::unique_ptr<DL_WriterA> dw(dxf.out(tmp.c_str(), DL_Codes::AC1015));
    if (!dw) {
      diags.error(codes::kWriteFailed,
                  fmt::format("cannot create a temporary DXF file {}", tmp.string()));
      return std::nullopt;
    }
    write_sheet(dxf, *dw, sheet, options);
    dw->close();
  }
  Diagnostics read;
  const std::optional<std::string> bytes =
      read_input_file(tmp, "temporary DXF file", read, std::size_t{1} << 30);
  if (!bytes) {
    diags.append(read);
    return std::nullopt;
  }
  std::string text = *bytes;
  if (text.size() < 16) {
    diags.error(codes::kInternalError, "dxflib produced an empty DXF");
    return std::nullopt;
  }
  return text;
}

bool write_dxf(const std::filesystem::path& path,
               const CutSheet& sheet,
               Diagnostics& diags,
               const DxfOptions& options) {
  const auto text = dxf_sheet(sheet, diags, options);
  return text && write_file_atomically(path, *text, diags);
}

}  // namespace fabkit
