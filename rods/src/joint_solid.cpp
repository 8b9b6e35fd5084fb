#include "fabkit/rods/joint_solid.h"

#include <fmt/format.h>

#include <chrono>

#include "fabkit/rods/diagnostic_codes.h"
#include "fabkit/rods/joint_geometry.h"

namespace fabkit::rods {

std::optional<JointSolid> make_joint_solid(const Structure& s,
                                           const Parameters& p,
                                           const Layout& l,
                                           int node,
                                           const JointSolidOptions& options,
                                           Diagnostics& diags) {
  const auto started = std::chrono::steady_clock::now();
  const std::string name = s.joint_name(node);
  // Rounding the exact result to double can, in rare near-degenerate configurations, fold a
  // sliver that mesh_boolean cannot repair; a different (still sub-micrometre) separation of
  // the cylinders avoids it.
  std::optional<TriangleMesh> joint;
  JointPieces pieces;
  Diagnostics attempt;
  for (const double separation : {1.0 / 1024, 3.0 / 1024, 7.0 / 1024}) {
    pieces = joint_pieces(s, p, l, node, separation);
    attempt = Diagnostics{};
    BooleanOptions boolean;
    boolean.deadline = options.deadline;
    joint = mesh_boolean(std::span<const SolidInput>(pieces.add),
                         std::span<const SolidInput>(pieces.subtract),
                         name,
                         attempt,
                         boolean);
    if (joint || attempt.has_errors_of(DiagnosticClass::kTimeout)) break;
  }
  if (!joint) {
    diags.append(attempt);
    return std::nullopt;
  }

  JointSolid out;
  out.node = node;
  out.label = s.joint_label(node);
  if (options.engrave) {
    // Occluders: the rods in their sockets, as far as they matter for what can be seen.
    TriangleMesh rods;
    for (const RodEnd* end : l.ends_at(node)) {
      const double length = std::max(
          1e-3, std::min(l.rod_length[static_cast<std::size_t>(end->rod)], 2 * pieces.reach));
      rods.append(profile_prism(end->frame,
                                Vec3::Zero(),
                                p.radius,
                                p.profile_sides(),
                                end->offset,
                                end->offset + length));
    }
    const auto spot = choose_engraving_spot(*joint, rods, Vec3::UnitZ(), options.engraving);
    if (spot) {
      Diagnostics text_diags;
      const auto cutter = engraving_cutter(out.label,
                                           *spot,
                                           p.wall / 2,
                                           options.engraving,
                                           text_diags,
                                           &out.text_height,
                                           &out.text_area);
      if (cutter) {
        const double before = joint->volume();
        const std::vector<TriangleMesh> cut = {*cutter};
        auto engraved = mesh_difference(*joint, cut, name + " (engraving)", text_diags);
        if (engraved) {
          out.engraved_volume = before - engraved->volume();
          out.engraving = spot;
          joint = std::move(engraved);
        }
      }
      if (!out.engraving) {
        for (const Diagnostic& d : text_diags) {
          diags.warning(d.code, fmt::format("{}: not engraved: {}", name, d.message));
        }
      }
      if (out.engraving && out.text_height < 2.5) {
        diags.warning(
            codes::kSmallEngraving,
            fmt::format("{}: its ID is engraved only {:.1f} mm tall (little flat surface); "
                        "a thicker wall σ or longer sockets h give it more room",
                        name,
                        out.text_height));
      }
    }
  }
  // An independent check of the finished joint (closed, manifold, no self-intersections).
  out.solid = check_solid(*joint);
  if (!out.solid.valid_solid()) {
    diags.error(codes::kBooleanFailed,
                fmt::format("{} is not a valid solid: {}", name, out.solid.problems()));
    return std::nullopt;
  }
  out.mesh = std::move(*joint);
  out.volume = out.solid.volume;
  out.centroid = out.mesh.centroid();
  out.print_pose = print_pose(l, node, out.mesh);
  out.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return out;
}

}  // namespace fabkit::rods
