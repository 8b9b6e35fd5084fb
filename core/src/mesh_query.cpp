// AABB-tree rays and kd-tree neighbours with CGAL; the only translation unit including them.
#include "fabkit/core/mesh_query.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <tuple>

namespace fabkit {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = K::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
}  // namespace

struct MeshRayQuery::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

MeshRayQuery::MeshRayQuery(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(f[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(f[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(f[2])];
    Triangle t(K::Point_3(a.x(), a.y(), a.z()),
               K::Point_3(b.x(), b.y(), b.z()),
               K::Point_3(c.x(), c.y(), c.z()));
    if (!t.is_degenerate()) impl_->triangles.push_back(t);
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.build();
  if (!impl_->triangles.empty()) impl_->tree.accelerate_distance_queries();
}

MeshRayQuery::~MeshRayQuery() = default;
MeshRayQuery::MeshRayQuery(MeshRayQuery&&) noexcept = default;
MeshRayQuery& MeshRayQuery::operator=(MeshRayQuery&&) noexcept = default;

std::optional<double> MeshRayQuery::first_hit(const Vec3& origin, const Vec3& direction) const {
  if (impl_->triangles.empty()) return std::nullopt;
  const K::Ray_3 ray(K::Point_3(origin.x(), origin.y(), origin.z()),
                     K::Vector_3(direction.x(), direction.y(), direction.z()));
  const auto hit = impl_->tree.first_intersection(ray);
  if (!hit) return std::nullopt;
  if (const K::Point_3* p = boost::get<K::Point_3>(&hit->first)) {
    return (Vec3(p->x(), p->y(), p->z()) - origin).norm();
  }
  if (const K::Segment_3* s = boost::get<K::Segment_3>(&hit->first)) {
    const auto& p = s->source();
    return (Vec3(p.x(), p.y(), p.z()) - origin).norm();
  }
  return std::nullopt;
}

bool MeshRayQuery::hits(const Vec3& origin, const Vec3& direction) const {
  if (impl_->triangles.empty()) return false;
  const K::Ray_3 ray(K::Point_3(origin.x(), origin.y(), origin.z()),
                     K::Vector_3(direction.x(), direction.y(), direction.z()));
  return impl_->tree.do_intersect(ray);
}

double MeshRayQuery::distance(const Vec3& point) const {
  if (impl_->triangles.empty()) return std::numeric_limits<double>::infinity();
  return std::sqrt(impl_->tree.squared_distance(K::Point_3(point.x(), point.y(), point.z())));
}

std::vector<std::vector<int>> nearest_neighbors(std::span<const Vec3> points, int k) {
  using Point = K::Point_3;
  // The tree holds indices and reads their points through a property map (CGAL's "index as
  // key" idiom): small nodes, and the neighbours come out as indices directly.
  using PointMap = CGAL::Pointer_property_map<Point>::type;
  using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<K>>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  using SearchTree = Search::Tree;
  using Distance = Search::Distance;
  std::vector<std::vector<int>> result(points.size());
  if (points.size() < 2 || k <= 0) return result;
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  const PointMap map = CGAL::make_property_map(pts);
  std::vector<std::size_t> indices(points.size());
  for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = i;
  SearchTree tree(indices.begin(), indices.end(), typename SearchTree::Splitter(), Traits(map));
  const Distance distance(map);
  const unsigned want =
      static_cast<unsigned>(std::min<std::size_t>(static_cast<std::size_t>(k), points.size() - 1)) +
      1;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Search search(tree, pts[i], want, 0, true, distance, false);
    auto& out = result[i];
    out.reserve(want);
    for (const auto& [j, d2] : search) {
      if (j != i && static_cast<int>(out.size()) < k) out.push_back(static_cast<int>(j));
    }
  }
  return result;
}

}  // namespace fabkit
