#pragma once
/// The primitive solids of Appendix A before any boolean: per joint the hull H_i, the prisms
/// C_ij and the sockets E_ij; per rod its prism. The preview (what the designer draws on every
/// edit) is made of these alone; joint_solid.h turns them into exact, closed joints.

#include <vector>

#include "fabkit/core/mesh.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/rods/check.h"
#include "fabkit/rods/layout.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

/// A closed prism in its own frame over the regular `sides`-gon of circumradius `radius` with
/// vertices at angles 2πk/sides, from z = t0 to z = t1 (mm). Caps are fans around their
/// centres; with `t1_ring_radius` > 0 the t1 cap also has a ring of that radius at the same
/// angles, so a coaxial socket leaves through the cap at exactly shared vertices.
TriangleMesh local_prism(double radius, int sides, double t0, double t1, double t1_ring_radius = 0);

/// A closed prism over the regular `sides`-gon of circumradius `radius` whose vertices sit at
/// angles 2πk/sides in the xy plane of `frame`, extruded along frame's z from t0 to t1 (mm),
/// relative to `origin`. Outward oriented.
TriangleMesh profile_prism(
    const Mat3& frame, const Vec3& origin, double radius, int sides, double t0, double t1);

/// The pieces of one joint in its local frame: the node at the origin, world axes, mm.
struct JointPieces {
  TriangleMesh hull;                  ///< H_i: hull of the node and each prism's inner ring
  std::vector<TriangleMesh> prisms;   ///< C_ij, radius r + σ, from g − σ to g + h
  std::vector<TriangleMesh> sockets;  ///< E_ij, radius r + ε, from g − ε (see socket_length)
  /// The same as exact boolean operands: prisms and sockets in their own frames with exact
  /// placements, the hull over exactly placed rings (add = hull then prisms; subtract =
  /// sockets of positive length).
  std::vector<SolidInput> add;
  std::vector<SolidInput> subtract;
  std::vector<double> socket_length;  ///< mm: ℓ + 2ε, cut short past the joint (same result)
  double reach = 0;                   ///< mm: every point of H_i ∪ C_ij is this close to the node
};

/// H_i, C_ij and E_ij of joint `node`. Each socket runs ℓ + 2ε from g − ε as Eq. (8), but
/// stops 1 mm beyond `reach` when the rod is longer: the joint is the same, and stays the same
/// when the design is rescaled (the scale invariance of §6).
///
/// `separation` (mm, default 2^-10 ≈ 1 µm) grows the prisms and sockets of the k-th rod at
/// the joint by k · separation in radius: far below any printer's resolution, it keeps equal
/// cylinders meeting at right angles (tangent to each other, a degenerate case for exact
/// booleans) apart, so the rounded result stays free of self-intersections.
JointPieces joint_pieces(const Structure& s,
                         const Parameters& p,
                         const Layout& l,
                         int node,
                         double separation = 1.0 / 1024,
                         bool exact_operands = true);

/// The preview: per joint H_i and its prisms in one mesh (overlapping, not unioned), per rod
/// its prism of radius r over its length ℓ; world frame, mm.
struct Preview {
  std::vector<TriangleMesh> joints;
  std::vector<TriangleMesh> rods;
  /// Estimated joint masses (hull + prisms − sockets), for check()'s balance.
  std::vector<JointMass> joint_masses;
};
Preview make_preview(const Structure& s, const Parameters& p, const Layout& l);

/// The estimated mass of a joint from its pieces (kg, centre in world mm): the hull plus each
/// prism's shell around its socket.
JointMass estimate_joint_mass(
    const Structure& s, const Parameters& p, const Layout& l, int node, const JointPieces& pieces);

/// Rod `rod` as cut: radius r, from g_ab to ‖p_b − p_a‖ − g_ba along the edge (world, mm).
TriangleMesh rod_mesh(const Structure& s, const Parameters& p, const Layout& l, int rod);

/// The rigid transform from a joint's local frame to its print pose: the sum of its unit rod
/// directions turned to +z (§4.1), then moved so it rests on z = 0 centred on the xy origin.
/// Identity rotation when the directions cancel out.
Mat4 print_pose(const Layout& l, int node, const TriangleMesh& local_mesh);

}  // namespace fabkit::rods
