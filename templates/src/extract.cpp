// Automatic template construction (paper §3.2, Appendices A and B).
#include "fabkit/templates/extract.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <set>

#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/diagnostic_codes.h"

namespace fabkit::templates {

namespace {

std::vector<int> elements_of_terms(const std::vector<LinearTerm>& terms) {
  std::set<int> s;
  for (const LinearTerm& t : terms) s.insert(t.index / kParamsPerElement);
  return {s.begin(), s.end()};
}

// Merges equal indices and drops zero coefficients, sorted by index.
std::vector<LinearTerm> canonical(std::vector<LinearTerm> terms) {
  std::map<int, double> m;
  for (const LinearTerm& t : terms) m[t.index] += t.coefficient;
  std::vector<LinearTerm> out;
  for (const auto& [i, c] : m) {
    if (std::abs(c) > 1e-12) out.push_back({i, c});
  }
  return out;
}

// Relation "a − b (= or ≤) 0" between two affine expressions.
Relation difference(const AffineExpr& a, const AffineExpr& b, RelationKind kind, bool equality) {
  Relation r;
  r.kind = kind;
  r.equality = equality;
  std::vector<LinearTerm> terms = a.terms;
  for (const LinearTerm& t : b.terms) terms.push_back({t.index, -t.coefficient});
  r.terms = canonical(std::move(terms));
  r.rhs = b.constant - a.constant;
  for (int e : elements_of_terms(r.terms)) r.elements.push_back(ElementId(e));
  return r;
}

struct Instance {
  ElementId element;
  AffineBox affine;
  Box value;
  std::string pose;       // "" = design pose
  int articulation = -1;  // which articulation moved it (pose instances)
};

bool moves_in(const Template& t, int articulation, ElementId e) {
  if (articulation < 0) return false;
  const auto& m = t.articulations[articulation].moving;
  return std::find(m.begin(), m.end(), e) != m.end();
}

// Whether two instances may be related: different elements, and a pose instance only with
// elements that stay put in that articulation.
bool related_pair(const Template& t, const Instance& a, const Instance& b) {
  if (a.element == b.element) return false;
  if (a.articulation >= 0 && b.articulation >= 0) return false;
  if (a.articulation >= 0 && moves_in(t, a.articulation, b.element)) return false;
  if (b.articulation >= 0 && moves_in(t, b.articulation, a.element)) return false;
  return true;
}

std::string row_key(const Relation& r) {
  std::string k = r.equality ? "=" : "<";
  for (const LinearTerm& t : r.terms) k += fmt::format("{}:{:.9g},", t.index, t.coefficient);
  return k + fmt::format("|{:.6f}", r.rhs);
}

}  // namespace

std::optional<std::array<int, 3>> item_axes(const Item& item, const Vec3& size) {
  std::array<int, 3> perm{0, 1, 2};
  do {
    bool ok = true;
    for (int a = 0; a < 3 && ok; ++a) {
      const ItemDimension& d = item.dims[perm[a]];
      if (!(size[a] > 0)) ok = false;
      if (!d.resizable && std::abs(size[a] - d.mm) > 0.5) ok = false;
      if (d.resizable && size[a] > d.mm + 0.5) ok = false;
    }
    if (ok) return perm;
  } while (std::next_permutation(perm.begin(), perm.end()));
  return std::nullopt;
}

RelationId store_relation(Template& t, Relation r, NodeId node) {
  if (!node.valid()) {
    node = r.elements.empty() ? t.root() : t.element(r.elements.front()).node;
    for (ElementId e : r.elements) node = t.lowest_common_ancestor(node, t.element(e).node);
    // Relations never live on a leaf unless they concern that element alone.
    if (t.node(node).element && r.elements.size() > 1) node = t.node(node).parent;
  }
  r.node = node;
  const RelationId id(static_cast<int>(t.relations.size()));
  t.relations.push_back(std::move(r));
  t.nodes[node.value].relations.push_back(id);
  return id;
}

std::vector<Relation> principal_relations(const Template& t,
                                          const std::vector<ElementId>& first,
                                          const std::vector<ElementId>& second,
                                          const ExtractOptions& options) {
  const double tol = options.plane_tolerance_mm;
  const bool split = !second.empty();
  std::set<ElementId> in_first(first.begin(), first.end()), in_second(second.begin(), second.end());
  std::vector<ElementId> all = first;
  all.insert(all.end(), second.begin(), second.end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());

  std::vector<Instance> inst;
  for (ElementId e : all) {
    if (!t.element(e).is_principal()) continue;
    inst.push_back({e, t.affine_box(e), t.box(e), "", -1});
  }
  const std::size_t design_count = inst.size();
  for (std::size_t a = 0; a < t.articulations.size(); ++a) {
    const TemplateArticulation& art = t.articulations[a];
    if (art.type == JointType::kBall) continue;
    for (ElementId e : art.moving) {
      if (!std::binary_search(all.begin(), all.end(), e) || !t.element(e).is_principal()) continue;
      Instance i;
      i.element = e;
      i.affine = rest_pose_box(t, art, e);
      i.value = i.affine.value(t.q);
      i.pose = rest_pose_name(art);
      i.articulation = static_cast<int>(a);
      inst.push_back(std::move(i));
    }
  }
  auto allowed = [&](const Instance& a, const Instance& b) {
    if (!related_pair(t, a, b)) return false;
    if (!split) return true;
    return (in_first.count(a.element) && in_second.count(b.element)) ||
           (in_second.count(a.element) && in_first.count(b.element));
  };

  std::vector<Relation> out;
  std::set<std::string> seen;
  auto emit = [&](Relation r) {
    if (r.terms.empty()) return;
    const std::string key = row_key(r);
    if (!seen.insert(key).second) return;
    out.push_back(std::move(r));
  };

  // Groups of coinciding values; each member is tied to the nearest earlier member it may be
  // related to, which chains the paper's "a = b = c" into rows a − b, b − c.
  struct Member {
    std::size_t instance;
    Side side;
    double value;
  };
  auto chain = [&](std::vector<Member> members, int axis, RelationKind kind) {
    std::stable_sort(members.begin(), members.end(), [](const Member& a, const Member& b) {
      return a.value < b.value;
    });
    std::size_t start = 0;
    while (start < members.size()) {
      std::size_t end = start + 1;
      while (end < members.size() && members[end].value - members[start].value <= tol) ++end;
      std::vector<Member> group(members.begin() + start, members.begin() + end);
      std::sort(group.begin(), group.end(), [&](const Member& a, const Member& b) {
        const Instance& ia = inst[a.instance];
        const Instance& ib = inst[b.instance];
        if (ia.element != ib.element) return ia.element < ib.element;
        if (ia.articulation != ib.articulation) return ia.articulation < ib.articulation;
        return static_cast<int>(a.side) < static_cast<int>(b.side);
      });
      // Each member is tied to the earlier member closest to it in the hierarchy (deepest
      // common ancestor; the nearest one on ties), so every subtree keeps a connected chain of
      // its own members: sub-templates stay self-contained.
      for (std::size_t i = 1; i < group.size(); ++i) {
        const Instance& b = inst[group[i].instance];
        std::size_t best = group.size();
        int best_depth = -1;
        for (std::size_t j = i; j-- > 0;) {
          const Instance& a = inst[group[j].instance];
          if (!allowed(a, b)) continue;
          const int depth = t.depth(
              t.lowest_common_ancestor(t.element(a.element).node, t.element(b.element).node));
          if (depth > best_depth) {
            best_depth = depth;
            best = j;
          }
        }
        if (best == group.size()) continue;
        const Instance& a = inst[group[best].instance];
        Relation r = difference(a.affine.plane(axis, group[best].side),
                                b.affine.plane(axis, group[i].side),
                                kind,
                                true);
        r.planes = {PlaneRef{a.element, axis, group[best].side, a.pose},
                    PlaneRef{b.element, axis, group[i].side, b.pose}};
        emit(std::move(r));
      }
      start = end;
    }
  };

  for (int k = 0; k < options.axes; ++k) {
    std::vector<Member> planes, centres;
    for (std::size_t i = 0; i < inst.size(); ++i) {
      planes.push_back({i, Side::kMin, inst[i].value.min()[k]});
      planes.push_back({i, Side::kMax, inst[i].value.max()[k]});
      if (i < design_count) centres.push_back({i, Side::kCenter, inst[i].value.center[k]});
    }
    chain(planes, k, RelationKind::kCoplanar);
    chain(centres, k, RelationKind::kConcentric);
  }

  // Reflective symmetry: identical elements mirrored about a third element's centre.
  if (!split) {
    for (std::size_t i = 0; i < design_count; ++i) {
      for (std::size_t j = i + 1; j < design_count; ++j) {
        const Element& ea = t.element(inst[i].element);
        const Element& eb = t.element(inst[j].element);
        if (ea.item != eb.item) continue;
        const Box& a = inst[i].value;
        const Box& b = inst[j].value;
        if ((a.size - b.size).cwiseAbs().maxCoeff() > tol) continue;
        if (ea.pattern.has_value() != eb.pattern.has_value()) continue;
        for (int k = 0; k < options.axes; ++k) {
          bool mirror = std::abs(a.center[k] - b.center[k]) > tol;
          for (int m = 0; m < 3 && mirror; ++m) {
            if (m != k && std::abs(a.center[m] - b.center[m]) > tol) mirror = false;
          }
          if (!mirror) continue;
          const double mid = 0.5 * (a.center[k] + b.center[k]);
          for (std::size_t c = 0; c < design_count; ++c) {
            if (c == i || c == j) continue;
            if (std::abs(inst[c].value.center[k] - mid) > tol) continue;
            AffineExpr half_sum;
            half_sum.terms = {{center_index(inst[i].element, k), 0.5},
                              {center_index(inst[j].element, k), 0.5}};
            Relation r =
                difference(half_sum, inst[c].affine.center[k], RelationKind::kSymmetric, true);
            r.planes = {PlaneRef{inst[i].element, k, Side::kCenter, ""},
                        PlaneRef{inst[j].element, k, Side::kCenter, ""},
                        PlaneRef{inst[c].element, k, Side::kCenter, ""}};
            emit(std::move(r));
            break;
          }
        }
      }
    }
  }

  // Order: elements that face each other across an axis stay on their sides.
  for (std::size_t i = 0; i < inst.size(); ++i) {
    for (std::size_t j = i + 1; j < inst.size(); ++j) {
      if (!allowed(inst[i], inst[j])) continue;
      const Box& a = inst[i].value;
      const Box& b = inst[j].value;
      for (int k = 0; k < options.axes; ++k) {
        bool facing = true;
        for (int m = 0; m < options.axes && facing; ++m) {
          if (m != k && a.overlap(b, m) <= options.overlap_min_mm) facing = false;
        }
        if (!facing) continue;
        std::size_t lo = i, hi = j;
        if (a.max()[k] <= b.min()[k] - tol) {
          lo = i;
          hi = j;
        } else if (b.max()[k] <= a.min()[k] - tol) {
          lo = j;
          hi = i;
        } else {
          continue;  // touching (coplanar) or overlapping
        }
        Relation r = difference(inst[lo].affine.plane(k, Side::kMax),
                                inst[hi].affine.plane(k, Side::kMin),
                                RelationKind::kOrder,
                                false);
        r.planes = {PlaneRef{inst[lo].element, k, Side::kMax, inst[lo].pose},
                    PlaneRef{inst[hi].element, k, Side::kMin, inst[hi].pose}};
        emit(std::move(r));
      }
    }
  }
  return out;
}

std::vector<Relation> non_penetration_relations(const Template& t,
                                                const std::vector<ElementId>& first,
                                                const std::vector<ElementId>& second,
                                                const ExtractOptions& options) {
  std::vector<Relation> out;
  const double tol = options.plane_tolerance_mm;
  for (ElementId a : first) {
    if (!t.element(a).is_principal()) continue;
    const Box ba = t.box(a);
    const AffineBox aa = t.affine_box(a);
    for (ElementId b : second) {
      if (a == b || !t.element(b).is_principal()) continue;
      const Box bb = t.box(b);
      const AffineBox ab = t.affine_box(b);
      for (int k = 0; k < options.axes; ++k) {
        bool facing = true;
        for (int m = 0; m < options.axes && facing; ++m) {
          if (m != k && ba.overlap(bb, m) <= options.overlap_min_mm) facing = false;
        }
        if (!facing) continue;
        Relation r;
        if (ba.max()[k] <= bb.min()[k] + tol) {
          r = difference(
              aa.plane(k, Side::kMax), ab.plane(k, Side::kMin), RelationKind::kOrder, false);
          r.planes = {PlaneRef{a, k, Side::kMax, ""}, PlaneRef{b, k, Side::kMin, ""}};
        } else if (bb.max()[k] <= ba.min()[k] + tol) {
          r = difference(
              ab.plane(k, Side::kMax), aa.plane(k, Side::kMin), RelationKind::kOrder, false);
          r.planes = {PlaneRef{b, k, Side::kMax, ""}, PlaneRef{a, k, Side::kMin, ""}};
        } else {
          continue;
        }
        out.push_back(std::move(r));
      }
    }
  }
  return out;
}

void connection_relations(const Template& t,
                          const Connection& c,
                          std::vector<Relation>& hard,
                          std::vector<Relation>& soft,
                          const ExtractOptions& options) {
  const double tol = options.plane_tolerance_mm;
  // Four comparisons per axis between two elements' bounding planes: equal planes stay equal,
  // the others keep their order (this also keeps a screw inside the parts it joins).
  auto compare = [&](ElementId a, ElementId b) {
    const Box ba = t.box(a), bb = t.box(b);
    const AffineBox aa = t.affine_box(a), ab = t.affine_box(b);
    for (int k = 0; k < options.axes; ++k) {
      for (Side sa : {Side::kMin, Side::kMax}) {
        for (Side sb : {Side::kMin, Side::kMax}) {
          const double va = sa == Side::kMin ? ba.min()[k] : ba.max()[k];
          const double vb = sb == Side::kMin ? bb.min()[k] : bb.max()[k];
          Relation r;
          if (std::abs(va - vb) <= tol) {
            r = difference(aa.plane(k, sa), ab.plane(k, sb), RelationKind::kCoplanar, true);
          } else if (va < vb) {
            r = difference(aa.plane(k, sa), ab.plane(k, sb), RelationKind::kOrder, false);
          } else {
            r = difference(ab.plane(k, sb), aa.plane(k, sa), RelationKind::kOrder, false);
          }
          r.planes = {PlaneRef{a, k, sa, ""}, PlaneRef{b, k, sb, ""}};
          if (va > vb + tol) std::swap(r.planes[0], r.planes[1]);
          if (!r.terms.empty()) hard.push_back(std::move(r));
        }
      }
    }
  };
  for (ElementId e : c.connecting) {
    for (ElementId p : c.principal) compare(e, p);
  }
  for (std::size_t i = 0; i < c.connecting.size(); ++i) {
    for (std::size_t j = i + 1; j < c.connecting.size(); ++j) {
      if (t.box(c.connecting[i]).touches(t.box(c.connecting[j]), options.contact_tolerance_mm)) {
        compare(c.connecting[i], c.connecting[j]);
      }
    }
  }

  // The contact patch: where the first two principal elements meet (or the gap between
  // them); with one principal element, its box.
  if (c.principal.empty()) return;
  const ElementId pa = c.principal[0];
  const ElementId pb = c.principal.size() > 1 ? c.principal[1] : c.principal[0];
  const Box ba = t.box(pa), bb = t.box(pb);
  const AffineBox aa = t.affine_box(pa), ab = t.affine_box(pb);
  std::array<AffineExpr, 3> lo, hi;
  std::array<double, 3> lo_v{}, hi_v{};
  for (int k = 0; k < 3; ++k) {
    const bool a_min = ba.min()[k] >= bb.min()[k];
    const bool a_max = ba.max()[k] <= bb.max()[k];
    lo[k] = a_min ? aa.plane(k, Side::kMin) : ab.plane(k, Side::kMin);
    hi[k] = a_max ? aa.plane(k, Side::kMax) : ab.plane(k, Side::kMax);
    lo_v[k] = std::max(ba.min()[k], bb.min()[k]);
    hi_v[k] = std::min(ba.max()[k], bb.max()[k]);
    if (lo_v[k] > hi_v[k]) {  // a gap: the patch spans it
      std::swap(lo[k], hi[k]);
      std::swap(lo_v[k], hi_v[k]);
      // lo is now the smaller max, hi the larger min.
      lo[k] = ba.max()[k] <= bb.max()[k] ? aa.plane(k, Side::kMax) : ab.plane(k, Side::kMax);
      hi[k] = ba.min()[k] >= bb.min()[k] ? aa.plane(k, Side::kMin) : ab.plane(k, Side::kMin);
    }
  }
  for (ElementId e : c.connecting) {
    const Box be = t.box(e);
    const Element& el = t.element(e);
    for (int k = 0; k < options.axes; ++k) {
      const double extent = hi_v[k] - lo_v[k];
      AffineExpr centre;
      centre.terms = {{center_index(e, k), 1.0}};
      AffineExpr target = lo[k];
      if (extent > 1.0) {
        // Keep the same fraction of the patch.
        const double u = (be.center[k] - lo_v[k]) / extent;
        for (const LinearTerm& term : hi[k].terms)
          target.terms.push_back({term.index, u * term.coefficient});
        for (const LinearTerm& term : lo[k].terms)
          target.terms.push_back({term.index, -u * term.coefficient});
        target.constant = (1 - u) * lo[k].constant + u * hi[k].constant;
      } else {
        target.constant += be.center[k] - lo_v[k];
      }
      Relation r = difference(centre, target, RelationKind::kPlacement, true);
      r.soft = true;
      r.planes = {PlaneRef{e, k, Side::kCenter, ""}};
      if (!r.terms.empty()) soft.push_back(std::move(r));
      bool along_pattern = false;
      if (el.pattern) {
        for (int d = 0; d < el.pattern->dims; ++d) along_pattern |= el.pattern->axis[d] == k;
      }
      if ((along_pattern || el.resizable[k]) && extent > 1.0) {
        const double f = be.size[k] / extent;
        AffineExpr size;
        size.terms = {{size_index(e, k), 1.0}};
        AffineExpr span;
        for (const LinearTerm& term : hi[k].terms)
          span.terms.push_back({term.index, f * term.coefficient});
        for (const LinearTerm& term : lo[k].terms)
          span.terms.push_back({term.index, -f * term.coefficient});
        span.constant = f * (hi[k].constant - lo[k].constant);
        Relation s = difference(size, span, RelationKind::kPlacement, true);
        s.soft = true;
        s.planes = {PlaneRef{e, k, Side::kMax, ""}};
        if (!s.terms.empty()) soft.push_back(std::move(s));
      }
    }
  }
}

namespace {

// ---- patterns (Appendix A) -------------------------------------------------------------------

struct PatternCandidate {
  std::vector<int> parts;  // in grid order (direction 0 fastest)
  Pattern pattern;
};

// Maximal runs of constant spacing of the parts `ids` along `axis` (sorted by coordinate).
std::vector<std::vector<int>> runs_along(const std::vector<int>& ids,
                                         const std::vector<DesignPart>& parts,
                                         int axis,
                                         double tol) {
  std::vector<std::vector<int>> runs;
  std::vector<int> sorted = ids;
  std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
    return parts[a].box.center[axis] < parts[b].box.center[axis];
  });
  const double size = parts[ids.front()].box.size[axis];
  std::size_t i = 0;
  while (i + 1 < sorted.size()) {
    const double step = parts[sorted[i + 1]].box.center[axis] - parts[sorted[i]].box.center[axis];
    if (step < size - tol || step <= tol) {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j + 1 < sorted.size() && std::abs(parts[sorted[j + 1]].box.center[axis] -
                                             parts[sorted[j]].box.center[axis] - step) <= tol) {
      ++j;
    }
    runs.emplace_back(sorted.begin() + i, sorted.begin() + j + 1);
    i = j;
  }
  return runs;
}

std::vector<PatternCandidate> find_pattern_candidates(const std::vector<int>& ids,
                                                      const std::vector<DesignPart>& parts,
                                                      double tol) {
  std::vector<PatternCandidate> out;
  auto key = [&](int p, int a, int b) {
    return std::pair{std::llround(parts[p].box.center[a] / tol),
                     std::llround(parts[p].box.center[b] / tol)};
  };
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    std::map<std::pair<long long, long long>, std::vector<int>> lines;
    for (int p : ids) lines[key(p, a, b)].push_back(p);
    std::vector<std::vector<int>> runs;
    for (auto& [_, line] : lines) {
      if (line.size() < 2) continue;
      for (auto& r : runs_along(line, parts, k, tol)) runs.push_back(std::move(r));
    }
    for (const auto& r : runs) {
      PatternCandidate c;
      c.parts = r;
      c.pattern.dims = 1;
      c.pattern.axis = {k, a};
      c.pattern.count = {static_cast<int>(r.size()), 1};
      c.pattern.step = {parts[r[1]].box.center[k] - parts[r[0]].box.center[k], 0};
      c.pattern.part_size = parts[r[0]].box.size;
      out.push_back(c);
    }
    // 2D: parallel runs of equal count, spacing and start, evenly spaced along a second axis.
    for (int m : {a, b}) {
      const int third = 3 - k - m;
      std::map<std::tuple<int, long long, long long, long long>, std::vector<int>> families;
      for (std::size_t r = 0; r < runs.size(); ++r) {
        const auto& run = runs[r];
        const long long step =
            std::llround((parts[run[1]].box.center[k] - parts[run[0]].box.center[k]) / tol);
        families[{static_cast<int>(run.size()),
                  step,
                  std::llround(parts[run[0]].box.center[k] / tol),
                  std::llround(parts[run[0]].box.center[third] / tol)}]
            .push_back(static_cast<int>(r));
      }
      for (auto& [_, members] : families) {
        if (members.size() < 2) continue;
        std::sort(members.begin(), members.end(), [&](int x, int y) {
          return parts[runs[x][0]].box.center[m] < parts[runs[y][0]].box.center[m];
        });
        const double size_m = parts[runs[members[0]][0]].box.size[m];
        std::size_t i = 0;
        while (i + 1 < members.size()) {
          const double step = parts[runs[members[i + 1]][0]].box.center[m] -
                              parts[runs[members[i]][0]].box.center[m];
          if (step < size_m - tol) {
            ++i;
            continue;
          }
          std::size_t j = i + 1;
          while (j + 1 < members.size() &&
                 std::abs(parts[runs[members[j + 1]][0]].box.center[m] -
                          parts[runs[members[j]][0]].box.center[m] - step) <= tol) {
            ++j;
          }
          PatternCandidate c;
          for (std::size_t r = i; r <= j; ++r) {
            c.parts.insert(c.parts.end(), runs[members[r]].begin(), runs[members[r]].end());
          }
          const auto& run0 = runs[members[i]];
          c.pattern.dims = 2;
          c.pattern.axis = {k, m};
          c.pattern.count = {static_cast<int>(run0.size()), static_cast<int>(j - i + 1)};
          c.pattern.step = {parts[run0[1]].box.center[k] - parts[run0[0]].box.center[k], step};
          c.pattern.part_size = parts[run0[0]].box.size;
          out.push_back(c);
          i = j;
        }
      }
    }
  }
  return out;
}

std::string common_prefix_name(const std::vector<std::string>& names) {
  if (names.empty()) return "pattern";
  std::string p = names.front();
  for (const std::string& n : names) {
    std::size_t i = 0;
    while (i < p.size() && i < n.size() && p[i] == n[i]) ++i;
    p.resize(i);
  }
  while (!p.empty() && (std::isdigit(static_cast<unsigned char>(p.back())) || p.back() == '_' ||
                        p.back() == '-')) {
    p.pop_back();
  }
  return p.empty() ? names.front() + "_pattern" : p;
}

std::string common_group(const std::vector<std::string>& groups) {
  if (groups.empty()) return "";
  std::vector<std::string> parts;
  std::string g = groups.front();
  for (const std::string& other : groups) {
    // Longest common prefix of whole path segments.
    std::size_t i = 0, last = 0;
    while (i < g.size() && i < other.size() && g[i] == other[i]) {
      ++i;
      if (i == g.size() || g[i] == '/') last = i;
    }
    if (i == g.size() && (i == other.size() || other[i] == '/')) last = i;
    g.resize(last);
  }
  return g;
}

}  // namespace

std::optional<Template> make_template(const SourceDesign& design,
                                      const ItemCatalog* catalog,
                                      Diagnostics& diags,
                                      const ExtractOptions& options) {
  const std::vector<DesignPart>& parts = design.parts;
  const int n = static_cast<int>(parts.size());
  const double ctol = options.contact_tolerance_mm;
  bool ok = true;

  // 1. Items: which dimension of the item lies along each axis, and what may be resized.
  std::vector<const Item*> items(n, nullptr);
  std::vector<std::array<int, 3>> axes(n, std::array<int, 3>{0, 1, 2});
  for (int i = 0; i < n; ++i) {
    const DesignPart& p = parts[i];
    if (p.item.empty()) continue;
    items[i] = catalog ? catalog->find(p.item) : nullptr;
    if (!items[i]) {
      std::vector<std::string> ids = catalog ? catalog->ids() : std::vector<std::string>{};
      diags.error(
          codes::kUnknownItem,
          fmt::format("part '{}': unknown item '{}'{}", p.name, p.item, did_you_mean(p.item, ids)),
          p.where);
      ok = false;
      continue;
    }
    auto mapping = item_axes(*items[i], p.box.size);
    if (!mapping) {
      const Item& it = *items[i];
      auto dim = [&](int k) {
        return fmt::format("{} {:g} mm{}",
                           std::array<const char*, 3>{"length", "width", "thickness"}[k],
                           it.dims[k].mm,
                           it.dims[k].resizable ? " (resizable up to this)" : " (fixed)");
      };
      diags.error(codes::kItemMismatch,
                  fmt::format("part '{}': a {:g} x {:g} x {:g} mm piece cannot be made from item "
                              "{} ({}: {}, {}, {})",
                              p.name,
                              p.box.size.x(),
                              p.box.size.y(),
                              p.box.size.z(),
                              it.id,
                              it.name,
                              dim(0),
                              dim(1),
                              dim(2)),
                  p.where);
      ok = false;
      continue;
    }
    axes[i] = *mapping;
  }
  if (!ok) return std::nullopt;

  // 2. Connection clusters: connecting parts that touch each other hold the same joint.
  std::vector<int> cluster(n, -1);
  {
    std::vector<int> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> root = [&](int x) {
      return parent[x] == x ? x : parent[x] = root(parent[x]);
    };
    for (int i = 0; i < n; ++i) {
      if (parts[i].role != PartRole::kConnecting) continue;
      for (int j = i + 1; j < n; ++j) {
        if (parts[j].role != PartRole::kConnecting) continue;
        if (parts[i].box.touches(parts[j].box, ctol)) parent[root(i)] = root(j);
      }
    }
    std::map<int, int> ids;
    for (int i = 0; i < n; ++i) {
      if (parts[i].role != PartRole::kConnecting) continue;
      const int r = root(i);
      if (!ids.count(r)) ids[r] = static_cast<int>(ids.size());
      cluster[i] = ids[r];
    }
  }
  int cluster_count = 0;
  for (int c : cluster) cluster_count = std::max(cluster_count, c + 1);
  std::vector<std::set<int>> cluster_principal(cluster_count);
  for (int i = 0; i < n; ++i) {
    if (cluster[i] < 0) continue;
    for (int j = 0; j < n; ++j) {
      if (parts[j].role == PartRole::kPrincipal && parts[i].box.touches(parts[j].box, ctol)) {
        cluster_principal[cluster[i]].insert(j);
      }
    }
  }
  for (int c = 0; c < cluster_count; ++c) {
    if (!cluster_principal[c].empty()) continue;
    for (int i = 0; i < n; ++i) {
      if (cluster[i] == c) {
        diags.warning(codes::kFloatingPart,
                      fmt::format("connecting part '{}' touches no principal part", parts[i].name),
                      parts[i].where);
        break;
      }
    }
  }

  // 3. Patterns: identical parts (same item, same size, same sub-assembly or joint) evenly
  // spaced in one or two directions; largest first.
  std::vector<int> element_of(n, -1);
  Template t;
  t.name = design.name;
  t.title = design.title;
  t.category = design.category;
  std::vector<std::vector<int>> element_parts;
  std::vector<std::optional<Pattern>> element_patterns;
  auto find_patterns_of = [&](PartRole role) {
    if (!options.find_patterns) return;
    std::map<std::string, std::vector<int>> identical;
    for (int i = 0; i < n; ++i) {
      const DesignPart& p = parts[i];
      if (p.role != role) continue;
      const std::string where =
          p.role == PartRole::kConnecting ? fmt::format("joint{}", cluster[i]) : "group:" + p.group;
      identical[fmt::format("{}|{}|{:.2f}|{:.2f}|{:.2f}",
                            where,
                            p.item,
                            p.box.size.x(),
                            p.box.size.y(),
                            p.box.size.z())]
          .push_back(i);
    }
    for (auto& [key, ids] : identical) {
      const bool connecting = role == PartRole::kConnecting;
      const int min_count =
          connecting ? options.min_connecting_pattern : options.min_principal_pattern;
      if (static_cast<int>(ids.size()) < min_count) continue;
      std::vector<PatternCandidate> cands =
          find_pattern_candidates(ids, parts, options.plane_tolerance_mm);
      std::stable_sort(cands.begin(), cands.end(), [](const auto& a, const auto& b) {
        return a.parts.size() > b.parts.size();
      });
      std::set<int> used;
      for (const PatternCandidate& c : cands) {
        if (static_cast<int>(c.parts.size()) < min_count) continue;
        if (c.pattern.dims == 2 && !connecting &&
            std::max(c.pattern.count[0], c.pattern.count[1]) < options.min_principal_pattern) {
          continue;  // a 2 x 2 grid (four legs) is four elements, not a pattern
        }
        bool free = true;
        for (int p : c.parts) free = free && !used.count(p);
        if (!free) continue;
        for (int p : c.parts) {
          used.insert(p);
          element_of[p] = static_cast<int>(element_parts.size());
        }
        element_parts.push_back(c.parts);
        element_patterns.push_back(c.pattern);
      }
    }
  };
  auto single_elements_of = [&](PartRole role) {
    for (int i = 0; i < n; ++i) {
      if (element_of[i] >= 0 || parts[i].role != role) continue;
      element_of[i] = static_cast<int>(element_parts.size());
      element_parts.push_back({i});
      element_patterns.push_back(std::nullopt);
    }
  };
  find_patterns_of(PartRole::kPrincipal);
  single_elements_of(PartRole::kPrincipal);
  // Joints are known by the principal elements they join (a pattern of slats is one).
  for (auto& ps : cluster_principal) {
    std::set<int> es;
    for (int p : ps) es.insert(element_of[p]);
    ps = es;
  }
  // One connection per set of joined principal elements: the five screws holding five slats to a
  // rail are one joint (and one pattern), not five.
  {
    std::map<std::set<int>, int> by_principal;
    std::vector<int> renumber(cluster_count, -1);
    std::vector<std::set<int>> merged;
    for (int c = 0; c < cluster_count; ++c) {
      auto [it, inserted] =
          by_principal.emplace(cluster_principal[c], static_cast<int>(merged.size()));
      if (inserted || cluster_principal[c].empty()) {
        if (!inserted) it->second = static_cast<int>(merged.size());
        renumber[c] = static_cast<int>(merged.size());
        merged.push_back(cluster_principal[c]);
      } else {
        renumber[c] = it->second;
      }
    }
    for (int& c : cluster) {
      if (c >= 0) c = renumber[c];
    }
    cluster_principal = merged;
    cluster_count = static_cast<int>(merged.size());
  }
  find_patterns_of(PartRole::kConnecting);
  single_elements_of(PartRole::kConnecting);
  // Order elements by their first part, so element order follows the file.
  std::vector<int> order(element_parts.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return *std::min_element(element_parts[a].begin(), element_parts[a].end()) <
           *std::min_element(element_parts[b].begin(), element_parts[b].end());
  });

  // 4. Elements and their parameters.
  const int ne = static_cast<int>(order.size());
  std::vector<int> new_of_old(ne);
  for (int e = 0; e < ne; ++e) new_of_old[order[e]] = e;
  t.elements.resize(ne);
  t.q.resize(ne * kParamsPerElement);
  std::vector<int> element_cluster(ne, -1);
  for (int e = 0; e < ne; ++e) {
    const std::vector<int>& ps = element_parts[order[e]];
    const DesignPart& first = parts[ps.front()];
    Element& el = t.elements[e];
    el.role = first.role;
    el.item = first.item;
    el.pattern = element_patterns[order[e]];
    for (int p : ps) {
      el.part_names.push_back(parts[p].name);
      element_of[p] = e;
    }
    el.name = el.pattern ? common_prefix_name(el.part_names) : first.name;
    el.source = design.name;
    el.source_element = ElementId(e);
    element_cluster[e] = cluster[ps.front()];
    Box b = first.box;
    for (int p : ps) b = b.united(parts[p].box);
    const Item* item = items[ps.front()];
    for (int k = 0; k < 3; ++k) {
      el.item_dim[k] = axes[ps.front()][k];
      const ItemDimension d = item ? item->dims[el.item_dim[k]] : ItemDimension{1e5, true};
      el.resizable[k] = d.resizable;
      el.max_size[k] = d.resizable ? d.mm : first.box.size[k];
      if (el.pattern) {
        for (int dd = 0; dd < el.pattern->dims; ++dd) {
          if (el.pattern->axis[dd] == k) {
            el.resizable[k] = true;
            el.max_size[k] = 1e5;
          }
        }
      }
    }
    if (el.pattern) {
      for (int k = 0; k < 3; ++k) {
        el.pattern->part_resizable[k] = item ? item->dims[axes[ps.front()][k]].resizable : true;
      }
    }
    t.q.segment<3>(e * kParamsPerElement) = b.center;
    t.q.segment<3>(e * kParamsPerElement + 3) = b.size;
  }
  // Make element names unique.
  {
    std::map<std::string, int> count;
    for (const Element& el : t.elements) ++count[el.name];
    std::map<std::string, int> next;
    for (Element& el : t.elements) {
      if (count[el.name] > 1) el.name += "_" + std::to_string(++next[el.name]);
    }
  }

  // 5. Hierarchy: the design's groups, principal elements as leaves; each connection gets a
  // node under the lowest common ancestor of the principal elements it joins.
  t.nodes.push_back(Node{design.name, NodeId(), {}, std::nullopt, false, {}, {}});
  std::map<std::string, NodeId> group_nodes{{"", t.root()}};
  auto group_node = [&](const std::string& path) {
    std::string so_far;
    NodeId at = t.root();
    std::size_t start = 0;
    while (start < path.size()) {
      std::size_t slash = path.find('/', start);
      if (slash == std::string::npos) slash = path.size();
      const std::string name = path.substr(start, slash - start);
      so_far += (so_far.empty() ? "" : "/") + name;
      auto it = group_nodes.find(so_far);
      if (it == group_nodes.end()) {
        const NodeId id(static_cast<int>(t.nodes.size()));
        t.nodes.push_back(Node{name, at, {}, std::nullopt, false, {}, {}});
        t.nodes[at.value].children.push_back(id);
        it = group_nodes.emplace(so_far, id).first;
      }
      at = it->second;
      start = slash + 1;
    }
    return at;
  };
  auto add_leaf = [&](int e, NodeId parent) {
    const NodeId id(static_cast<int>(t.nodes.size()));
    t.nodes.push_back(Node{t.elements[e].name, parent, {}, ElementId(e), false, {}, {}});
    t.nodes[parent.value].children.push_back(id);
    t.elements[e].node = id;
  };
  for (int e = 0; e < ne; ++e) {
    if (t.elements[e].role != PartRole::kPrincipal) continue;
    std::vector<std::string> groups;
    for (int p : element_parts[order[e]]) groups.push_back(parts[p].group);
    add_leaf(e, group_node(common_group(groups)));
  }
  // Connections, one per cluster.
  std::vector<int> cluster_connection(cluster_count, -1);
  for (int c = 0; c < cluster_count; ++c) {
    Connection conn;
    // cluster_principal holds element indices from before the reordering.
    std::set<int> principal_elements;
    for (int e : cluster_principal[c]) principal_elements.insert(new_of_old[e]);
    for (int e : principal_elements) conn.principal.push_back(ElementId(e));
    NodeId lca;
    for (ElementId e : conn.principal) {
      lca = lca.valid() ? t.lowest_common_ancestor(lca, t.element(e).node) : t.element(e).node;
    }
    if (!lca.valid()) lca = t.root();
    if (t.node(lca).element) lca = t.node(lca).parent;
    std::vector<std::string> names;
    for (ElementId e : conn.principal) names.push_back(t.element(e).name);
    conn.name = names.empty() ? fmt::format("joint_{}", c + 1)
                              : "joint_" + fmt::format("{}", fmt::join(names, "_"));
    conn.node = lca;
    conn.source = design.name;
    const NodeId cn(static_cast<int>(t.nodes.size()));
    t.nodes.push_back(Node{conn.name, lca, {}, std::nullopt, true, {}, {}});
    t.nodes[lca.value].children.push_back(cn);
    for (int e = 0; e < ne; ++e) {
      if (element_cluster[e] == c) {
        add_leaf(e, cn);
        conn.connecting.push_back(ElementId(e));
      }
    }
    cluster_connection[c] = static_cast<int>(t.connections.size());
    t.nodes[lca.value].connections.push_back(ConnectionId(static_cast<int>(t.connections.size())));
    t.connections.push_back(std::move(conn));
  }
  // Unique sibling names.
  for (Node& nd : t.nodes) {
    std::map<std::string, int> seen;
    for (NodeId c : nd.children) {
      Node& child = t.nodes[c.value];
      if (seen[child.name]++ > 0) child.name += "_" + std::to_string(seen[child.name]);
    }
  }

  // 6. Articulations in template terms.
  for (const Articulation& a : design.articulations) {
    TemplateArticulation ta;
    ta.name = a.name;
    ta.type = a.type;
    ta.axis = a.axis;
    ta.direction = a.direction;
    ta.lower = a.lower;
    ta.upper = a.upper;
    for (const std::string& pn : a.parts) {
      for (int i = 0; i < n; ++i) {
        if (parts[i].name != pn) continue;
        const ElementId e(element_of[i]);
        if (std::find(ta.moving.begin(), ta.moving.end(), e) == ta.moving.end())
          ta.moving.push_back(e);
      }
    }
    if (ta.moving.empty()) continue;
    ta.pivot_element = ta.moving.front();
    const Box pb = t.box(ta.pivot_element);
    for (int k = 0; k < 3; ++k) {
      ta.pivot_fraction[k] = pb.size[k] > 0 ? (a.pivot[k] - pb.min()[k]) / pb.size[k] : 0.5;
    }
    if (a.type == JointType::kHinge && std::abs(std::remainder(a.upper - a.lower, 90.0)) > 1e-6) {
      diags.warning(codes::kInvalidValue,
                    fmt::format("articulation '{}': the rest poses differ by {:g}°, not a multiple "
                                "of 90°; only its design pose constrains the template",
                                a.name,
                                a.upper - a.lower),
                    a.where);
      ta.upper = ta.lower;
    }
    t.articulations.push_back(std::move(ta));
  }

  // 7. Relations.
  // Per element: catalog sizes (fixed dimensions, longest stock) and positive sizes.
  for (int e = 0; e < ne; ++e) {
    const Element& el = t.elements[e];
    const ElementId id(e);
    for (int k = 0; k < options.axes; ++k) {
      const double size = t.q[size_index(id, k)];
      Relation r;
      r.terms = {{size_index(id, k), 1.0}};
      r.elements = {id};
      r.planes = {PlaneRef{id, k, Side::kMax, ""}};
      if (!el.item.empty() && !el.resizable[k]) {
        r.kind = RelationKind::kFixedSize;
        r.equality = true;
        r.rhs = size;
        store_relation(t, r, el.node);
        continue;
      }
      if (!el.item.empty() && el.max_size[k] < 1e5) {
        Relation m = r;
        m.kind = RelationKind::kMaxSize;
        m.equality = false;
        m.rhs = el.max_size[k];
        store_relation(t, m, el.node);
      }
      Relation lo = r;
      lo.kind = RelationKind::kMinSize;
      lo.equality = false;
      lo.terms = {{size_index(id, k), -1.0}};
      double least = std::min(1.0, size);
      if (el.pattern) {
        for (int d = 0; d < el.pattern->dims; ++d) {
          if (el.pattern->axis[d] == k) least = el.pattern->part_size[k];
        }
      }
      lo.rhs = -least;
      store_relation(t, lo, el.node);
    }
  }
  // Between principal elements.
  std::vector<ElementId> principal;
  for (int e = 0; e < ne; ++e) {
    if (t.elements[e].is_principal()) principal.push_back(ElementId(e));
  }
  for (Relation& r : principal_relations(t, principal, {}, options))
    store_relation(t, std::move(r));
  // Connections.
  for (std::size_t c = 0; c < t.connections.size(); ++c) {
    std::vector<Relation> hard, soft;
    connection_relations(t, t.connections[c], hard, soft, options);
    // Stored with the connection, at the lowest common ancestor of its principal elements.
    const NodeId at = t.connections[c].node;
    for (Relation& r : hard) {
      r.connection = ConnectionId(static_cast<int>(c));
      t.connections[c].relations.push_back(store_relation(t, std::move(r), at));
    }
    for (Relation& r : soft) {
      r.connection = ConnectionId(static_cast<int>(c));
      t.connections[c].placement.push_back(store_relation(t, std::move(r), at));
    }
  }
  return t;
}

}  // namespace fabkit::templates
