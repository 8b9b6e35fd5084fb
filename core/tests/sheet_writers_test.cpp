#include <gtest/gtest.h>

#include "fabkit/core/dxf.h"
#include "fabkit/core/svg_sheet.h"

namespace fabkit {
namespace {

CutSheet sample_sheet() {
  CutSheet s;
  s.name = "sheet 1";
  s.width_mm = 600;
  s.height_mm = 400;
  s.add_cut(subtract({rectangle(10, 20, 110, 70)}, {rectangle(50, 40, 53, 50)})[0]);
  s.labels.push_back({"side <left>", Vec2(30, 45), 5, 90});
  return s;
}

TEST(SvgSheet, HasMillimetreSizeAViewBoxInMmAndTwoColouredLayers) {
  const std::string svg = svg_sheet(sample_sheet());
  EXPECT_NE(svg.find("width=\"600mm\" height=\"400mm\" viewBox=\"0 0 600 400\""),
            std::string::npos);
  EXPECT_NE(svg.find("inkscape:document-units=\"mm\""), std::string::npos);
  EXPECT_NE(svg.find("stroke=\"#ff0000\""), std::string::npos);
  EXPECT_NE(svg.find("fill=\"#0000ff\""), std::string::npos);
  // y is flipped: the rectangle's lower-left corner (10, 20) is at SVG y = 380.
  for (const char* corner : {"10 380", "110 380", "110 330", "10 330"}) {
    EXPECT_NE(svg.find(corner), std::string::npos) << corner << "\n" << svg;
  }
  EXPECT_NE(svg.find("side &lt;left&gt;"), std::string::npos);
  EXPECT_NE(svg.find("rotate(-90 30 355)"), std::string::npos);
}

TEST(Dxf, WritesClosedPolylinesOnTheCutLayerAndTextOnTheLabelLayer) {
  Diagnostics d;
  const auto dxf = dxf_sheet(sample_sheet(), d);
  ASSERT_TRUE(dxf) << d.format();
  EXPECT_NE(dxf->find("LWPOLYLINE"), std::string::npos);
  EXPECT_NE(dxf->find("$INSUNITS"), std::string::npos);
  EXPECT_NE(dxf->find("CUT"), std::string::npos);
  EXPECT_NE(dxf->find("LABELS"), std::string::npos);
  EXPECT_NE(dxf->find("side <left>"), std::string::npos);
  // Independent read-back of coordinates is python/tests/test_flatpack_outputs.py (ezdxf).
}

TEST(Dxf, AFailedWriteLeavesNoFile) {
  Diagnostics d;
  EXPECT_FALSE(write_dxf("/nonexistent-dir/out.dxf", sample_sheet(), d));
  EXPECT_TRUE(d.has_errors_of(DiagnosticClass::kIo));
}

}  // namespace
}  // namespace fabkit
