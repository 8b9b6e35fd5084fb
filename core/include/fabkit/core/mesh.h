#pragma once
/// Triangle meshes and procedural shapes for display, mass properties and export.

#include <string>
#include <vector>

#include "fabkit/core/frame.h"

namespace fabkit {

/// An indexed triangle mesh; vertices in mm, faces counter-clockwise seen from outside.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3i> faces;

  bool empty() const { return faces.empty(); }
  /// Appends `other`'s triangles (indices shifted).
  void append(const TriangleMesh& other);
  /// Applies a rigid homogeneous transform to every vertex.
  void transform(const Mat4& m);
  /// Copy transformed by `m`.
  TriangleMesh transformed(const Mat4& m) const;
  /// Signed enclosed volume in mm³ (sum of origin tetrahedra; exact for closed meshes).
  double volume() const;
  /// Volume-weighted centroid in mm (centre of mass at uniform density); falls back to the
  /// vertex average when the volume is ~0.
  Vec3 centroid() const;
  /// Axis-aligned bounds; both zero for an empty mesh.
  Vec3 bounds_min() const;
  Vec3 bounds_max() const;
};

/// Procedural shapes, each centred as documented, in its own local frame.
namespace shapes {

/// Box of extents `size` (x, y, z) centred at the origin.
TriangleMesh box(const Vec3& size);
/// Closed cylinder of `radius`, `length` along z, centred at the origin.
TriangleMesh cylinder(double radius, double length, int segments = 24);
/// Cylindrical shell (inner radius, outer radius) of `length` along z, centred, closed by rings.
TriangleMesh tube(double inner_radius, double outer_radius, double length, int segments = 24);
/// Sphere of `radius` centred at the origin.
TriangleMesh sphere(double radius, int segments = 16);
/// Lower half (z <= 0) of a sphere, closed by a disc at z = 0.
TriangleMesh hemisphere(double radius, int segments = 16);
/// Torus arc in the y–z plane around the x axis: centreline radius `arc_radius`, wire radius
/// `wire_radius`, starting at (0, 0, -arc_radius) and sweeping `angle_deg` towards -y (the
/// FabHaL hook convention). Open arcs are capped.
TriangleMesh torus_arc(double arc_radius,
                       double wire_radius,
                       double angle_deg,
                       int segments = 32,
                       int wire_segments = 10);

}  // namespace shapes

}  // namespace fabkit
