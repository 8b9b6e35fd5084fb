#pragma once
/// A rod-and-joint structure (RodSteward Appendix A): nodes in mm joined by straight rods, and
/// the per-design parameters r, p, σ, h, ε, materials and stock.
///
/// Joints are numbered as the input numbers its nodes (1-based in design and OBJ files); that
/// number is the joint's engraved ID and the name of its STL file (joint_07.stl).

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/cut_plan.h"
#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"

namespace fabkit::rods {

/// A node of the network: where a joint is printed.
struct Node {
  Vec3 position = Vec3::Zero();  ///< mm, world frame (z up; the lowest nodes stand on the floor)
  int id = 0;                    ///< joint number as the input numbers it (1-based)
  SourceLocation where;          ///< where the input wrote it (if from a file)
};

/// An undirected edge: one rod between nodes `a` and `b` (indices into Structure::nodes). Its
/// canonical direction a → b fixes the rod's profile orientation at both ends.
struct Rod {
  int a = 0;
  int b = 0;
  SourceLocation where;
};

struct Structure {
  std::vector<Node> nodes;
  std::vector<Rod> rods;

  /// "joint 07" for node index i (the joint's ID, two digits, three beyond 99).
  std::string joint_name(int node) const;
  /// "rod 03–07" (its joints' IDs).
  std::string rod_name(int rod) const;
  /// The ID text engraved on joint `node` ("07").
  std::string joint_label(int node) const;
  /// Rods meeting at each node.
  std::vector<std::vector<int>> rods_at_nodes() const;
};

/// A force applied at a node (N, world axes; z up, so weight is −z).
struct PointLoad {
  int node = 0;
  Vec3 force = Vec3::Zero();
  SourceLocation where;
};

/// A node held in place: translations always; rotations too when `fixed`.
struct Support {
  int node = 0;
  bool fixed = false;
  SourceLocation where;
};

/// Mechanical properties of a rod material.
struct RodMaterial {
  std::string name = "hardwood";  ///< preset name, or "custom"
  double density = 680;           ///< kg/m³
  double youngs_modulus = 12000;  ///< MPa (N/mm²), along the grain
  double shear_modulus = 750;     ///< MPa
  double strength = 80;           ///< MPa, design bending/axial strength
};

/// A printing material (only its density matters: joint mass for balance and self-weight).
struct JointMaterial {
  std::string name = "pla";
  double density = 1240;  ///< kg/m³ of solid print
};

/// Presets: "hardwood" (birch/beech dowel), "oak", "pine", "bamboo", "aluminium", "steel".
std::span<const RodMaterial> rod_material_presets();
/// Presets: "pla", "petg", "abs", "asa", "nylon".
std::span<const JointMaterial> joint_material_presets();
std::optional<RodMaterial> find_rod_material(std::string_view name);
std::optional<JointMaterial> find_joint_material(std::string_view name);

/// Everything that shapes joints and rods (Appendix A, Fig. 16) plus materials and stock.
struct Parameters {
  double radius = 3.175;  ///< r, mm: the rod's radius (a polygon's circumradius)
  int sides = 0;          ///< p: sides of a polygonal profile; 0 = a circular rod
  /// Sides of the polygon that stands for a circle. 32: its facets stray 0.015 mm from a
  /// 6.35 mm dowel and 0.05 mm from a 19 mm one, below a printer's resolution.
  int circle_sides = 32;
  double wall = 2.0;              ///< σ, mm: joint wall thickness
  double socket = 15.0;           ///< h, mm: how far a joint overhangs each rod
  double tolerance = 0.15;        ///< ε, mm: socket clearance (negative: press fit)
  double leaf_offset = 0.0;       ///< g, mm, at a node with a single rod (flat end cap)
  double min_rod_length = 20;     ///< mm; shorter rods are reported (rod-too-short)
  double merge_tolerance = 0.01;  ///< mm; nodes closer than this are one node
  RodMaterial rod_material;
  JointMaterial joint_material;
  StockSpec stock{.length = 914.4, .end_padding = 10, .kerf = 0.2};

  /// Sides of the mesh polygon (sides, or circle_sides for a circle).
  int profile_sides() const { return sides > 0 ? sides : circle_sides; }
  bool circular() const { return sides == 0; }
  /// Circumradius of the socket polygon: r + ε, or for a circle the polygon that contains the
  /// true circle of radius r + ε (so a round dowel fits however the circle is faceted).
  double socket_circumradius() const;
  /// Cross-section area (mm²), second moment of area I (mm⁴, any axis through the centre) and
  /// torsion constant J (mm⁴) of the rod's profile.
  double section_area() const;
  double section_inertia() const;
  double section_torsion() const;
  /// Checks every value; input diagnostics naming the parameter and the bounds.
  Diagnostics validate() const;
};

/// A node as read: position and where it was written.
struct NodeInput {
  Vec3 position = Vec3::Zero();
  SourceLocation where;
};
/// An edge as read: two node numbers in the input's numbering.
struct EdgeInput {
  long long a = 0;
  long long b = 0;
  SourceLocation where;
};

/// Builds a structure from node and edge lists, numbered from `first_index` (1 in files, 0 in
/// Python). Merges nodes within `merge_tolerance` mm (a note says which), and rejects with
/// input diagnostics (file:line when known): non-finite or absurd coordinates, edges naming no
/// node, zero-length edges, duplicate edges, isolated nodes, and edges leaving a node in the
/// same direction. nullopt on any error.
std::optional<Structure> build_structure(std::span<const NodeInput> nodes,
                                         std::span<const EdgeInput> edges,
                                         int first_index,
                                         double merge_tolerance,
                                         Diagnostics& diags);

/// The same structure with every node position multiplied by `factor` about the origin.
Structure scaled(const Structure& s, double factor);

}  // namespace fabkit::rods
