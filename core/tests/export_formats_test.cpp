#include "fabkit/core/export_formats.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "fabkit/core/mesh_io.h"

namespace fabkit {
namespace {

std::vector<SceneObject> two_boxes() {
  SceneObject a{"a", shapes::box(Vec3(10, 20, 30))};
  SceneObject b{"b", shapes::box(Vec3(5, 5, 5))};
  b.transform = translation(100.0, 0.0, 0.0);
  return {a, b};
}

TEST(ExportFormats, EveryFormatWritesAndMeshFormatsReadBack) {
  const auto dir = std::filesystem::temp_directory_path() / "fabkit_export_formats_test";
  std::filesystem::create_directories(dir);
  const std::vector<SceneObject> scene = two_boxes();
  for (const ExportFormat& f : export_formats()) {
    const auto path = dir / (std::string("scene") + std::string(f.extension));
    Diagnostics d;
    ASSERT_TRUE(write_scene(f.name, scene, path, d)) << f.name << d.format();
    EXPECT_GT(std::filesystem::file_size(path), 0u) << f.name;
    EXPECT_EQ(find_export_format(f.extension), &f);
    if (f.name == "stl" || f.name == "obj") {
      const auto mesh = read_mesh(path, d);
      ASSERT_TRUE(mesh) << d.format();
      // Both boxes, placed: 6000 + 125 mm³, the second 100 mm along x.
      EXPECT_NEAR(mesh->volume(), 6125.0, 1e-3) << f.name;
      EXPECT_NEAR(mesh->bounds_max().x(), 102.5, 1e-6) << f.name;
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(ExportFormats, UnknownFormatIsNamed) {
  Diagnostics d;
  EXPECT_FALSE(write_scene("stp", two_boxes(), "x.stp", d));
  ASSERT_TRUE(d.has_errors());
  EXPECT_NE(d.items()[0].message.find("unknown export format 'stp' (known: glb, stl, obj, svg)"),
            std::string::npos)
      << d.format();
}

}  // namespace
}  // namespace fabkit
