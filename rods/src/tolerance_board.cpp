#include "fabkit/rods/tolerance_board.h"

#include <fmt/format.h>

#include <cmath>

#include "fabkit/core/extrude.h"
#include "fabkit/core/glyph_outline.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/rods/joint_geometry.h"

namespace fabkit::rods {

std::optional<ToleranceBoard> make_tolerance_board(const Parameters& p,
                                                   const ToleranceBoardOptions& o,
                                                   Diagnostics& diags) {
  const std::size_t before = diags.size();
  if (!(o.step > 0) || !std::isfinite(o.from) || !std::isfinite(o.to) || o.to < o.from) {
    diags.error(
        codes::kInvalidValue,
        fmt::format("tolerance board from {:g} to {:g} mm in steps of {:g} mm: the step must be "
                    "positive and 'to' at least 'from'",
                    o.from,
                    o.to,
                    o.step));
    return std::nullopt;
  }
  const int count = static_cast<int>(std::floor((o.to - o.from) / o.step + 1e-9)) + 1;
  if (count > 60) {
    diags.error(
        codes::kLimitExceeded,
        fmt::format("tolerance board with {} sockets; at most 60 (use a larger step)", count));
  }
  if (p.radius + o.from <= 0) {
    diags.error(
        codes::kInvalidValue,
        fmt::format(
            "tolerance board: r + ε = {:g} + {:g} mm must stay positive", p.radius, o.from));
  }
  if (o.from >= p.wall || o.to >= p.wall + p.radius) {
    diags.error(
        codes::kInvalidValue,
        fmt::format(
            "tolerance board: ε up to {:g} mm leaves no wall around the sockets (σ = {:g} mm)",
            o.to,
            p.wall));
  }
  if (diags.size() > before) return std::nullopt;

  ToleranceBoard board;
  const double depth = o.depth > 0 ? o.depth : p.socket;
  const double hole =
      (p.radius + o.to) / (p.circular() ? std::cos(std::numbers::pi / p.circle_sides) : 1);
  const double label = std::clamp(0.8 * hole, 3.0, 6.0);  // text height, mm
  board.pitch = 2 * hole + std::max(3.0, p.wall) + 1;
  const double row = board.pitch + label + 2;
  const int columns = std::max(1, std::min(o.columns, count));
  const int rows = (count + columns - 1) / columns;
  const double margin = std::max(3.0, p.wall);
  const Vec3 size(columns * board.pitch + 2 * margin - (board.pitch - 2 * hole),
                  rows * row + 2 * margin - (row - 2 * hole - label - 2),
                  depth + p.wall);
  TriangleMesh plate = shapes::box(size);
  plate.transform(translation(size.x() / 2, size.y() / 2, size.z() / 2));

  std::vector<SolidInput> cut;
  const int sides = p.profile_sides();
  TextOutlineOptions text;
  text.em_size = label / 0.73;  // digits are 0.73 em tall
  for (int k = 0; k < count; ++k) {
    const double eps = o.from + k * o.step;
    const int c = k % columns, r = k / columns;
    const Vec3 centre(
        margin + hole + c * board.pitch, size.y() - margin - hole - r * row, size.z());
    Parameters q = p;
    q.tolerance = eps;
    TriangleMesh socket = local_prism(q.socket_circumradius(), sides, -depth, 1.0);
    cut.push_back(
        SolidInput{std::move(socket), translation(centre.x(), centre.y(), centre.z()), {}});
    board.tolerances.push_back(eps);
    board.socket_centres.push_back(centre);
    const std::string caption = fmt::format("{:+.2f}", eps);
    auto outline = text_outline(caption, text, diags);
    if (!outline) return std::nullopt;
    const double width = outline->max.x() - outline->min.x();
    std::vector<Ring2> rings;
    const double scale = std::min(1.0, (board.pitch - 1) / width);
    for (const auto& ring : outline->rings) {
      Ring2 rr;
      for (const auto& q2 : ring)
        rr.push_back(scale * (q2 - Eigen::Vector2d((outline->min.x() + outline->max.x()) / 2,
                                                   outline->min.y())));
      rings.push_back(std::move(rr));
    }
    TriangleMesh engraved = extrude_rings(rings, -0.6, 0.6);
    cut.push_back(
        SolidInput{std::move(engraved),
                   translation(centre.x(), centre.y() - hole - 1.5 - label * scale, size.z()),
                   {}});
  }
  std::vector<SolidInput> add = {SolidInput{std::move(plate), Mat4::Identity(), {}}};
  auto mesh = mesh_boolean(
      std::span<const SolidInput>(add), std::span<const SolidInput>(cut), "tolerance board", diags);
  if (!mesh) return std::nullopt;
  board.mesh = std::move(*mesh);
  return board;
}

}  // namespace fabkit::rods
