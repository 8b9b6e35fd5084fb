// Prisms over planar regions: CGAL's constrained Delaunay triangulation with nesting levels
// (the "mark domains" construction of CGAL's manual). The only translation unit including it.
#include "fabkit/core/extrude.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <list>
#include <map>

namespace fabkit {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int nesting_level = -1;
  bool in_domain() const { return nesting_level % 2 == 1; }
};
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

void mark_domains(Cdt& cdt, Cdt::Face_handle start, int index, std::list<Cdt::Edge>& border) {
  if (start->info().nesting_level != -1) return;
  std::list<Cdt::Face_handle> queue{start};
  while (!queue.empty()) {
    Cdt::Face_handle f = queue.front();
    queue.pop_front();
    if (f->info().nesting_level != -1) continue;
    f->info().nesting_level = index;
    for (int i = 0; i < 3; ++i) {
      Cdt::Edge e(f, i);
      Cdt::Face_handle n = f->neighbor(i);
      if (n->info().nesting_level == -1) {
        if (cdt.is_constrained(e)) {
          border.push_back(e);
        } else {
          queue.push_back(n);
        }
      }
    }
  }
}

void mark_domains(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().nesting_level = -1;
  std::list<Cdt::Edge> border;
  mark_domains(cdt, cdt.infinite_face(), 0, border);
  while (!border.empty()) {
    Cdt::Edge e = border.front();
    border.pop_front();
    Cdt::Face_handle n = e.first->neighbor(e.second);
    if (n->info().nesting_level == -1) {
      mark_domains(cdt, n, e.first->info().nesting_level + 1, border);
    }
  }
}

}  // namespace

TriangleMesh extrude_rings(std::span<const Ring2> rings, double z0, double z1) {
  Cdt cdt;
  for (const Ring2& ring : rings) {
    if (ring.size() < 3) continue;
    std::vector<Cdt::Vertex_handle> vs;
    for (const auto& p : ring) vs.push_back(cdt.insert(K::Point_2(p.x(), p.y())));
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const auto a = vs[i], b = vs[(i + 1) % vs.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  mark_domains(cdt);
  TriangleMesh mesh;
  std::map<Cdt::Vertex_handle, int> bottom;
  auto index = [&](Cdt::Vertex_handle v) {
    auto [it, inserted] = bottom.try_emplace(v, static_cast<int>(mesh.vertices.size()));
    if (inserted) {
      const auto& p = v->point();
      mesh.vertices.emplace_back(p.x(), p.y(), z0);
      mesh.vertices.emplace_back(p.x(), p.y(), z1);
    }
    return it->second;  // bottom copy; the top copy follows it
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->info().in_domain()) continue;
    const int a = index(f->vertex(0)), b = index(f->vertex(1)), c = index(f->vertex(2));
    mesh.faces.emplace_back(a + 1, b + 1, c + 1);  // top, counter-clockwise from above
    mesh.faces.emplace_back(a, c, b);              // bottom, facing down
    for (int i = 0; i < 3; ++i) {
      if (f->neighbor(i)->info().in_domain()) continue;
      // Edge opposite vertex i, in the face's counter-clockwise order: the region is on its
      // left, so the wall faces right.
      const int p = index(f->vertex(cdt.ccw(i))), q = index(f->vertex(cdt.cw(i)));
      mesh.faces.emplace_back(p, q, q + 1);
      mesh.faces.emplace_back(p, q + 1, p + 1);
    }
  }
  return mesh;
}

}  // namespace fabkit
