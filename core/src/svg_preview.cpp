#include "fabkit/core/svg_preview.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <system_error>

#include "fabkit/core/file_io.h"

namespace fabkit {

bool write_svg_preview(const std::vector<SceneObject>& objects,
                       const std::filesystem::path& path,
                       Diagnostics& diags,
                       const SvgPreviewOptions& options) {
  // Camera basis: right, up, forward.
  const Vec3 forward = options.view_direction.normalized();
  const Vec3 right = forward.cross(options.up).normalized();
  const Vec3 up = right.cross(forward);
  const Vec3 light = (-forward + 0.6 * up + 0.3 * right).normalized();

  struct Tri {
    double depth;
    Eigen::Vector2d p[3];
    std::array<float, 4> color;
    double shade;
  };
  std::vector<Tri> tris;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const SceneObject& o : objects) {
    const TriangleMesh world = o.mesh.transformed(o.transform);
    for (const auto& f : world.faces) {
      const Vec3 a = world.vertices[static_cast<std::size_t>(f[0])];
      const Vec3 b = world.vertices[static_cast<std::size_t>(f[1])];
      const Vec3 c = world.vertices[static_cast<std::size_t>(f[2])];
      Vec3 n = (b - a).cross(c - a);
      if (n.norm() < 1e-12) continue;
      n.normalize();
      if (n.dot(forward) > 0) continue;  // faces away from the camera
      Tri t;
      t.depth = ((a + b + c) / 3).dot(forward);
      int i = 0;
      for (const Vec3& v : {a, b, c}) {
        t.p[i] = Eigen::Vector2d(v.dot(right), -v.dot(up));
        lo = lo.cwiseMin(t.p[i]);
        hi = hi.cwiseMax(t.p[i]);
        ++i;
      }
      t.color = o.color;
      t.shade = 0.35 + 0.65 * std::max(0.0, n.dot(light));
      tris.push_back(t);
    }
  }
  if (tris.empty()) {
    diags.error(codes::kInternalError, fmt::format("{}: nothing to draw", path.string()));
    return false;
  }
  // Painter's algorithm: far triangles first.
  std::sort(tris.begin(), tris.end(), [](const Tri& x, const Tri& y) { return x.depth > y.depth; });
  const Eigen::Vector2d size = (hi - lo).cwiseMax(1e-9);
  const double w = options.width_px;
  const double scale = w * (1 - 2 * options.margin) / size.x();
  const double h = std::ceil(size.y() * scale + 2 * options.margin * w);
  const Eigen::Vector2d offset(options.margin * w, options.margin * w);

  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" "
      "viewBox=\"0 0 {0:.0f} {1:.0f}\">\n<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n",
      w,
      h);
  for (const Tri& t : tris) {
    auto px = [&](const Eigen::Vector2d& p) { return Eigen::Vector2d((p - lo) * scale + offset); };
    const Eigen::Vector2d a = px(t.p[0]), b = px(t.p[1]), c = px(t.p[2]);
    auto channel = [&](float v) {
      return static_cast<int>(std::clamp(v * t.shade, 0.0, 1.0) * 255);
    };
    const std::string fill = fmt::format(
        "#{:02x}{:02x}{:02x}", channel(t.color[0]), channel(t.color[1]), channel(t.color[2]));
    svg += fmt::format(
        "<path d=\"M{:.1f} {:.1f}L{:.1f} {:.1f}L{:.1f} {:.1f}Z\" fill=\"{}\" stroke=\"{}\" "
        "stroke-width=\"0.3\"/>\n",
        a.x(),
        a.y(),
        b.x(),
        b.y(),
        c.x(),
        c.y(),
        fill,
        fill);
  }
  svg += "</svg>\n";

  return write_file_atomically(path, svg, diags);
}

}  // namespace fabkit
