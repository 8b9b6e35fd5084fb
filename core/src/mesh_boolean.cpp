// Exact booleans, hulls and solid checks with CGAL. The only translation unit that includes
// CGAL's corefinement (compile cost: see BUILD-NOTES).
#include "fabkit/core/mesh_boolean.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <fmt/format.h>

#include <array>
#include <exception>
#include <map>
#include <tuple>
#include <type_traits>

namespace fabkit {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactMesh = CGAL::Surface_mesh<Epeck::Point_3>;
using FloatMesh = CGAL::Surface_mesh<Epick::Point_3>;
using Polygon = std::array<std::size_t, 3>;

std::vector<Polygon> polygons_of(const TriangleMesh& mesh) {
  std::vector<Polygon> polygons;
  polygons.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    polygons.push_back({static_cast<std::size_t>(f[0]),
                        static_cast<std::size_t>(f[1]),
                        static_cast<std::size_t>(f[2])});
  }
  return polygons;
}

bool indices_valid(const TriangleMesh& mesh) {
  const auto n = static_cast<int>(mesh.vertices.size());
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      if (f[k] < 0 || f[k] >= n) return false;
    }
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return false;
  }
  return true;
}

template <class Mesh>
bool to_cgal(const TriangleMesh& mesh, Mesh& out) {
  using Point = typename Mesh::Point;
  if (!indices_valid(mesh)) return false;
  const std::vector<Polygon> polygons = polygons_of(mesh);
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) return false;
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  PMP::polygon_soup_to_polygon_mesh(points, polygons, out);
  return true;
}

using ExactTransform = CGAL::Aff_transformation_3<Epeck>;

ExactTransform exact_transform(const Mat4& m) {
  return ExactTransform(m(0, 0),
                        m(0, 1),
                        m(0, 2),
                        m(0, 3),
                        m(1, 0),
                        m(1, 1),
                        m(1, 2),
                        m(1, 3),
                        m(2, 0),
                        m(2, 1),
                        m(2, 2),
                        m(2, 3));
}

// A placed operand in exact arithmetic; false if it is not a closed solid.
bool to_exact(const SolidInput& in, ExactMesh& out) {
  if (!in.hull.empty()) {
    std::vector<Epeck::Point_3> points;
    for (const PlacedPoints& set : in.hull) {
      const ExactTransform t = exact_transform(set.placement);
      for (const Vec3& p : set.points)
        points.push_back(t.transform(Epeck::Point_3(p.x(), p.y(), p.z())));
    }
    if (points.size() < 4) return false;
    CGAL::convex_hull_3(points.begin(), points.end(), out);
    return out.number_of_faces() >= 4 && CGAL::is_closed(out);
  }
  if (!to_cgal(in.mesh, out) || !CGAL::is_closed(out)) return false;
  if (in.placement != Mat4::Identity()) {
    const ExactTransform t = exact_transform(in.placement);
    for (const auto v : out.vertices()) out.point(v) = t.transform(out.point(v));
  }
  return true;
}

// Vertices sorted by position and faces by their vertices: CGAL's corefinement emits the
// same solid in an order that depends on memory addresses, and the same input must give the
// same file (and the same engraving spot, which samples the faces in order).
TriangleMesh canonical(TriangleMesh m) {
  std::vector<int> order(m.vertices.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Vec3& p = m.vertices[static_cast<std::size_t>(a)];
    const Vec3& q = m.vertices[static_cast<std::size_t>(b)];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  });
  std::vector<int> new_index(order.size());
  std::vector<Vec3> vertices(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    new_index[static_cast<std::size_t>(order[k])] = static_cast<int>(k);
    vertices[k] = m.vertices[static_cast<std::size_t>(order[k])];
  }
  for (auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) f[k] = new_index[static_cast<std::size_t>(f[k])];
    // Rotate (keeping the orientation) so the smallest index comes first.
    while (f[0] > f[1] || f[0] > f[2]) f = Eigen::Vector3i(f[1], f[2], f[0]);
  }
  std::sort(m.faces.begin(), m.faces.end(), [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    return std::tie(a[0], a[1], a[2]) < std::tie(b[0], b[1], b[2]);
  });
  m.vertices = std::move(vertices);
  return m;
}

// The same exact solid with its vertices in lexicographic order of their exact coordinates
// and its faces in order of their vertices, so that what walks it in index order (the sliver
// removal) does the same on every run.
ExactMesh canonical_exact(const ExactMesh& mesh) {
  std::vector<ExactMesh::Vertex_index> order(mesh.vertices().begin(), mesh.vertices().end());
  std::sort(order.begin(), order.end(), [&](auto a, auto b) {
    return CGAL::compare_xyz(mesh.point(a), mesh.point(b)) == CGAL::SMALLER;
  });
  std::map<ExactMesh::Vertex_index, int> new_index;
  for (std::size_t k = 0; k < order.size(); ++k) new_index[order[k]] = static_cast<int>(k);
  std::vector<std::array<int, 3>> faces;
  faces.reserve(mesh.number_of_faces());
  for (const auto f : mesh.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) tri[static_cast<std::size_t>(k)] = new_index[v];
      ++k;
    }
    while (tri[0] > tri[1] || tri[0] > tri[2]) tri = {tri[1], tri[2], tri[0]};
    faces.push_back(tri);
  }
  std::sort(faces.begin(), faces.end());
  ExactMesh out;
  std::vector<ExactMesh::Vertex_index> added;
  added.reserve(order.size());
  for (const auto v : order) added.push_back(out.add_vertex(mesh.point(v)));
  for (const auto& f : faces) {
    out.add_face(added[static_cast<std::size_t>(f[0])],
                 added[static_cast<std::size_t>(f[1])],
                 added[static_cast<std::size_t>(f[2])]);
  }
  return out;
}

// A lazy exact coordinate's double is the midpoint of whatever interval it holds, which is
// tighter once something forced its exact value: for the same double every run, round the
// exact value itself.
double rounded_exactly(const Epeck::FT& x) {
  return CGAL::to_double(CGAL::exact(x));
}

// `exact_rounding`: vertices rounded from their exact values (deterministic, slower).
template <class Mesh>
TriangleMesh from_cgal(const Mesh& mesh, bool exact_rounding = false) {
  TriangleMesh out;
  std::map<typename Mesh::Vertex_index, int> index;
  out.vertices.reserve(mesh.number_of_vertices());
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    index[v] = static_cast<int>(out.vertices.size());
    if constexpr (std::is_same_v<Mesh, ExactMesh>) {
      if (exact_rounding) {
        out.vertices.emplace_back(
            rounded_exactly(p.x()), rounded_exactly(p.y()), rounded_exactly(p.z()));
        continue;
      }
    }
    out.vertices.emplace_back(
        CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  out.faces.reserve(mesh.number_of_faces());
  for (const auto f : mesh.faces()) {
    Eigen::Vector3i tri;
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) tri[k] = index[v];
      ++k;
    }
    if (k == 3) out.faces.push_back(tri);
  }
  return out;
}

// Whether a rounded mesh intersects itself (or is no longer a manifold).
bool rounding_folds(const TriangleMesh& m) {
  FloatMesh sm;
  if (!to_cgal(m, sm)) return true;
  return PMP::does_self_intersect(sm);
}

bool boxes_overlap(const ExactMesh& a, const ExactMesh& b) {
  const auto ba = PMP::bbox(a);
  const auto bb = PMP::bbox(b);
  return CGAL::do_overlap(ba, bb);
}

}  // namespace

std::string SolidCheck::problems() const {
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  if (!manifold) add("not manifold");
  if (!closed) add(fmt::format("not closed ({} boundary edges)", boundary_edges));
  if (self_intersecting) {
    add(fmt::format(
        "self-intersecting ({} pairs of triangles, first near [{:.3f}, {:.3f}, {:.3f}])",
        intersecting_pairs,
        intersection_at.x(),
        intersection_at.y(),
        intersection_at.z()));
  }
  if (closed && !outward) add(fmt::format("inside out (volume {:.3f} mm³)", volume));
  return out;
}

SolidCheck check_solid(const TriangleMesh& mesh) {
  SolidCheck c;
  if (mesh.faces.empty() || !indices_valid(mesh)) return c;
  // Boundary edges straight from the soup, so that a non-manifold mesh still gets a count.
  std::map<std::pair<int, int>, int> edge_uses;
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      ++edge_uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [edge, uses] : edge_uses) c.boundary_edges += uses == 1 ? 1 : 0;
  try {
    FloatMesh sm;
    c.manifold = to_cgal(mesh, sm);
    if (!c.manifold) return c;
    c.closed = CGAL::is_closed(sm);
    std::vector<std::pair<FloatMesh::Face_index, FloatMesh::Face_index>> pairs;
    PMP::self_intersections(sm, std::back_inserter(pairs));
    c.self_intersecting = !pairs.empty();
    c.intersecting_pairs = static_cast<int>(pairs.size());
    if (!pairs.empty()) {
      Vec3 sum = Vec3::Zero();
      int k = 0;
      for (const auto f : {pairs.front().first, pairs.front().second}) {
        for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
          const auto& p = sm.point(v);
          sum += Vec3(p.x(), p.y(), p.z());
          ++k;
        }
      }
      c.intersection_at = sum / k;
    }
    std::vector<std::size_t> component(sm.number_of_faces());
    c.components =
        static_cast<int>(PMP::connected_components(sm, CGAL::make_property_map(component)));
    if (c.closed) {
      c.volume = PMP::volume(sm);
      c.outward = c.volume > 0;
    }
  } catch (const std::exception&) {
    c.manifold = false;
  }
  return c;
}

bool is_closed_manifold(const TriangleMesh& mesh) {
  const SolidCheck c = check_solid(mesh);
  return c.manifold && c.closed;
}

bool self_intersects(const TriangleMesh& mesh) {
  return check_solid(mesh).self_intersecting;
}

TriangleMesh convex_hull(std::span<const Vec3> points) {
  std::vector<Epick::Point_3> pts;
  pts.reserve(points.size());
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  if (pts.size() < 4) return {};
  try {
    FloatMesh hull;
    CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
    if (hull.number_of_faces() < 4 || !CGAL::is_closed(hull)) return {};
    return from_cgal(hull);
  } catch (const std::exception&) {
    return {};
  }
}

TriangleMesh rounded_to_float32(const TriangleMesh& mesh) {
  TriangleMesh out;
  std::map<std::array<float, 3>, int> index;
  std::vector<int> new_index(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    // + 0.0f: -0 and +0 are one point.
    const std::array<float, 3> key{static_cast<float>(v.x()) + 0.0f,
                                   static_cast<float>(v.y()) + 0.0f,
                                   static_cast<float>(v.z()) + 0.0f};
    const auto [it, inserted] = index.try_emplace(key, static_cast<int>(out.vertices.size()));
    if (inserted) out.vertices.emplace_back(key[0], key[1], key[2]);
    new_index[i] = it->second;
  }
  out.faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    out.faces.emplace_back(new_index[static_cast<std::size_t>(f[0])],
                           new_index[static_cast<std::size_t>(f[1])],
                           new_index[static_cast<std::size_t>(f[2])]);
  }
  return out;
}

std::optional<TriangleMesh> mesh_boolean(std::span<const SolidInput> add,
                                         std::span<const SolidInput> subtract,
                                         std::string_view what,
                                         Diagnostics& diags,
                                         const BooleanOptions& options) {
  auto fail = [&](const std::string& why) -> std::optional<TriangleMesh> {
    diags.error(codes::kBooleanFailed, fmt::format("{}: exact boolean failed: {}", what, why));
    return std::nullopt;
  };
  if (add.empty()) return TriangleMesh{};
  const std::size_t operations = add.size() - 1 + subtract.size();
  auto stopped = [&](std::size_t done) {
    if (!options.deadline || std::chrono::steady_clock::now() <= *options.deadline) return false;
    diags.error(codes::kTimeLimit,
                fmt::format("{}: stopped at the deadline after {} of {} boolean operations",
                            what,
                            done,
                            operations));
    return true;
  };
  try {
    std::vector<ExactMesh> adds(add.size()), subs(subtract.size());
    for (std::size_t i = 0; i < add.size(); ++i) {
      if (!to_exact(add[i], adds[i])) {
        return fail(fmt::format("solid {} to add is not a closed manifold", i + 1));
      }
    }
    for (std::size_t i = 0; i < subtract.size(); ++i) {
      if (!to_exact(subtract[i], subs[i])) {
        return fail(fmt::format("solid {} to subtract is not a closed manifold", i + 1));
      }
    }
    // For files, each union starts from a canonical order of the one before: corefinement
    // triangulates ties (cocircular points) in an order that follows memory addresses, and
    // the next union, the sliver removal and so the file would differ from run to run.
    const bool for_files = options.min_feature_mm > 0;
    ExactMesh result = adds[0];
    for (std::size_t i = 1; i < adds.size(); ++i) {
      if (stopped(i - 1)) return std::nullopt;
      ExactMesh out;
      if (!PMP::corefine_and_compute_union(result, adds[i], out)) {
        return fail(fmt::format("the union with solid {} is not a manifold", i + 1));
      }
      result = for_files ? canonical_exact(out) : std::move(out);
    }
    for (std::size_t i = 0; i < subs.size(); ++i) {
      if (!boxes_overlap(result, subs[i])) continue;
      if (stopped(adds.size() - 1 + i)) return std::nullopt;
      ExactMesh out;
      if (!PMP::corefine_and_compute_difference(result, subs[i], out)) {
        return fail(fmt::format("subtracting solid {} leaves a non-manifold", i + 1));
      }
      result = std::move(out);
    }
    if (options.min_feature_mm > 0) {
      // Needles: any triangle's shortest edge under the size (ratio threshold 1); caps: any
      // obtuse triangle (cosine threshold 0) whose height is under it.
      const double size = options.min_feature_mm;
      result = canonical_exact(result);
      PMP::experimental::remove_almost_degenerate_faces(
          result, 0.0, 1.0, size, CGAL::parameters::flip_triangle_height_threshold(size));
      // Then caps of any height flatter than 176° (needles off): with their near-straight
      // angle they lie within a rounding of their neighbours across a shallow crease.
      PMP::experimental::remove_almost_degenerate_faces(result, -0.9975, 1e6, size);
      if (!CGAL::is_closed(result)) return fail("removing slivers opened the solid");
      TriangleMesh rounded = from_cgal(result, /*exact_rounding=*/true);
      if (rounding_folds(rounded) || rounding_folds(rounded_to_float32(rounded))) {
        return fail(fmt::format(
            "the result with slivers under {:g} mm removed does not stay a solid in float32",
            size));
      }
      return canonical(std::move(rounded));
    }
    TriangleMesh rounded = from_cgal(result);
    if (rounding_folds(rounded)) {
      // Rounding the exact result to double folded a sliver (vertices closer than an ulp,
      // needles and caps of near-degenerate intersections). Collapse such sub-micrometre
      // triangles in exact arithmetic and round again.
      ExactMesh repaired = result;
      PMP::experimental::remove_almost_degenerate_faces(repaired, -0.99999, 1e4, 1e-4);
      TriangleMesh second = from_cgal(repaired);
      if (rounding_folds(second) || !CGAL::is_closed(repaired)) {
        return fail("rounding the exact result to double makes it intersect itself");
      }
      rounded = std::move(second);
    }
    return canonical(std::move(rounded));
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

namespace {
std::vector<SolidInput> as_inputs(std::span<const TriangleMesh> meshes) {
  std::vector<SolidInput> out;
  out.reserve(meshes.size());
  for (const TriangleMesh& m : meshes) out.push_back(SolidInput{m, Mat4::Identity(), {}});
  return out;
}
}  // namespace

std::optional<TriangleMesh> mesh_boolean(std::span<const TriangleMesh> add,
                                         std::span<const TriangleMesh> subtract,
                                         std::string_view what,
                                         Diagnostics& diags,
                                         const BooleanOptions& options) {
  const std::vector<SolidInput> a = as_inputs(add), b = as_inputs(subtract);
  return mesh_boolean(
      std::span<const SolidInput>(a), std::span<const SolidInput>(b), what, diags, options);
}

std::optional<TriangleMesh> mesh_union(std::span<const TriangleMesh> solids,
                                       std::string_view what,
                                       Diagnostics& diags,
                                       const BooleanOptions& options) {
  return mesh_boolean(solids, std::span<const TriangleMesh>(), what, diags, options);
}

std::optional<TriangleMesh> mesh_difference(const TriangleMesh& solid,
                                            std::span<const TriangleMesh> cutters,
                                            std::string_view what,
                                            Diagnostics& diags) {
  return mesh_boolean(std::span<const TriangleMesh>(&solid, 1), cutters, what, diags);
}

}  // namespace fabkit
