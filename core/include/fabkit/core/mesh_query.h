#pragma once
/// Spatial queries for every kit (CGAL AABB tree and kd-tree; fabkit::geometry): rays against a
/// fixed triangle mesh, and k nearest neighbours among points.

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "fabkit/core/mesh.h"

namespace fabkit {

/// Ray and distance queries against one triangle mesh (mm, the mesh's frame). Building costs
/// O(n log n); each query O(log n). Thread-safe for concurrent queries once built.
class MeshRayQuery {
 public:
  explicit MeshRayQuery(const TriangleMesh& mesh);
  ~MeshRayQuery();
  MeshRayQuery(MeshRayQuery&&) noexcept;
  MeshRayQuery& operator=(MeshRayQuery&&) noexcept;

  /// Distance along the unit `direction` from `origin` to the first triangle hit, or nullopt.
  std::optional<double> first_hit(const Vec3& origin, const Vec3& direction) const;
  /// Whether the ray from `origin` along `direction` hits any triangle.
  bool hits(const Vec3& origin, const Vec3& direction) const;
  /// Distance from `point` to the mesh surface (mm).
  double distance(const Vec3& point) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// For each point, the indices of its `k` nearest other points, in no particular order (fewer when
/// there are fewer points).
std::vector<std::vector<int>> nearest_neighbors(std::span<const Vec3> points, int k);

}  // namespace fabkit
