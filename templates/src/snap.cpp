// Snapping (paper §4.4, eq. 3).
#include "fabkit/templates/snap.h"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "fabkit/templates/diagnostic_codes.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;

double plane_value(const Box& b, int axis, Side side) {
  return side == Side::kMin ? b.min()[axis] : side == Side::kMax ? b.max()[axis] : b.center[axis];
}

// A plane of the local (added) template as a row: Σ terms = value.
Relation plane_row(const AffineExpr& plane,
                   double value,
                   const PlaneRef& added,
                   const PlaneRef& target) {
  Relation r;
  r.kind = RelationKind::kCoplanar;
  r.equality = true;
  r.terms = plane.terms;
  r.rhs = value - plane.constant;
  r.planes = {added, target};
  return r;
}

int rank_of(const std::vector<Eigen::VectorXd>& rows, Eigen::Index n) {
  if (rows.empty()) return 0;
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), n);
  for (std::size_t i = 0; i < rows.size(); ++i)
    m.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(m);
  qr.setThreshold(1e-9);
  return static_cast<int>(qr.rank());
}

Eigen::VectorXd dense(const std::vector<LinearTerm>& terms, Eigen::Index n) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  for (const LinearTerm& t : terms) v[t.index] += t.coefficient;
  return v;
}

}  // namespace

SnapResult snap(const WorkingModel& wm,
                const Composition& added,
                const TemplateDatabase& db,
                const SnapOptions& o) {
  const auto start = Clock::now();
  SnapResult out;
  const Template& model = wm.model();
  out.q = model.q;
  const std::vector<ElementId> mine = model.elements_under(added.node);  // local i ↔ mine[i]
  std::set<ElementId> mine_set(mine.begin(), mine.end());
  const Template local = model.subtree(added.node);
  const Eigen::Index n = local.q.size();
  // The model's planes (everything but the added template), principal elements only.
  struct ModelPlane {
    ElementId element;
    int axis;
    Side side;
    double value;
  };
  std::vector<ModelPlane> planes;
  for (int e = 0; e < model.element_count(); ++e) {
    const ElementId id(e);
    if (mine_set.count(id) || !model.element(id).is_principal()) continue;
    const Box b = model.box(id);
    for (int k = 0; k < 3; ++k) {
      planes.push_back({id, k, Side::kMin, b.min()[k]});
      planes.push_back({id, k, Side::kMax, b.max()[k]});
    }
  }
  if (planes.empty()) {
    out.snapped = true;  // nothing to snap to: the first template stays where it is
    out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return out;
  }

  // Constraints from the source design: coplanarities between the added elements and the
  // elements they were joined to there.
  struct SourceConstraint {
    ElementId local_element;
    int axis;
    Side side_added, side_target;
  };
  std::vector<SourceConstraint> source;
  const std::string design = local.element_count() ? local.element(ElementId(0)).source : "";
  if (const Template* td = db.source_template(design)) {
    std::map<int, ElementId> local_of_source;  // source element → local element
    for (int i = 0; i < local.element_count(); ++i) {
      const Element& el = local.element(ElementId(i));
      if (el.source == design) local_of_source[el.source_element.value] = ElementId(i);
    }
    std::set<int> joined;  // source elements outside the added part, joined to it
    for (const Connection& c : td->connections) {
      bool has_mine = false;
      for (ElementId e : c.principal) has_mine = has_mine || local_of_source.count(e.value);
      if (!has_mine) continue;
      for (ElementId e : c.principal) {
        if (!local_of_source.count(e.value)) joined.insert(e.value);
      }
    }
    // Coplanar planes (read off the source design's geometry: a coplanarity group ties every
    // member to every other, whatever rows the chain stored).
    for (const auto& [src, le] : local_of_source) {
      if (!local.element(le).is_principal()) continue;
      const Box mine_box = td->box(ElementId(src));
      for (int other : joined) {
        const Box ob = td->box(ElementId(other));
        for (int k = 0; k < 3; ++k) {
          for (Side sa : {Side::kMin, Side::kMax}) {
            for (Side sb : {Side::kMin, Side::kMax}) {
              if (std::abs(plane_value(mine_box, k, sa) - plane_value(ob, k, sb)) > 0.05) continue;
              source.push_back({le, k, sa, sb});
            }
          }
        }
      }
    }
  }
  // Independent rows not already fixed by the added template's own equalities.
  std::vector<Eigen::VectorXd> fixed_rows;
  for (const Relation& r : local.relations) {
    if (r.equality && !r.soft) fixed_rows.push_back(dense(r.terms, n));
  }
  const int base_rank = rank_of(fixed_rows, n);
  std::vector<SourceConstraint> independent;
  std::vector<Eigen::VectorXd> rows = fixed_rows;
  int rank = base_rank;
  for (const SourceConstraint& sc : source) {
    rows.push_back(
        dense(local.affine_box(sc.local_element).plane(sc.axis, sc.side_added).terms, n));
    const int r = rank_of(rows, n);
    if (r > rank) {
      rank = r;
      independent.push_back(sc);
    } else {
      rows.pop_back();
    }
  }
  const int R = static_cast<int>(independent.size());
  out.source_constraints = R;
  int K = o.k;
  while (K > 1 && std::pow(static_cast<double>(K), R) > o.max_combinations) --K;
  out.candidates_per_constraint = K;
  // The K model planes nearest each constraint's plane, with the same normal.
  std::vector<std::vector<ModelPlane>> candidates(R);
  for (int i = 0; i < R; ++i) {
    const SourceConstraint& sc = independent[i];
    const double now = plane_value(local.box(sc.local_element), sc.axis, sc.side_added);
    std::vector<ModelPlane> same;
    for (const ModelPlane& p : planes) {
      if (p.axis == sc.axis && p.side == sc.side_target) same.push_back(p);
    }
    std::sort(same.begin(), same.end(), [&](const ModelPlane& a, const ModelPlane& b) {
      return std::abs(a.value - now) < std::abs(b.value - now);
    });
    // Planes at the same height are one candidate.
    std::vector<ModelPlane> distinct;
    for (const ModelPlane& p : same) {
      bool dup = false;
      for (const ModelPlane& d : distinct) dup = dup || std::abs(d.value - p.value) < 1e-6;
      if (!dup) distinct.push_back(p);
      if (static_cast<int>(distinct.size()) == K) break;
    }
    candidates[i] = distinct;
  }
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(n);
  for (int e = 0; e < local.element_count(); ++e) {
    if (local.element(ElementId(e)).is_principal())
      weights.segment<kParamsPerElement>(e * kParamsPerElement).setOnes();
  }
  auto to_model_ref = [&](ElementId local_e, int axis, Side side) {
    return PlaneRef{mine[local_e.value], axis, side, ""};
  };
  // Eq. 3 for every combination of candidate planes; the cheapest feasible one wins.
  std::vector<Relation> best_rows;
  ProjectResult best;
  best.cost = std::numeric_limits<double>::infinity();
  std::vector<int> pick(R, 0);
  bool any_candidates = true;
  for (int i = 0; i < R; ++i) any_candidates = any_candidates && !candidates[i].empty();
  if (R > 0 && any_candidates) {
    while (true) {
      std::vector<Relation> extra;
      for (int i = 0; i < R; ++i) {
        const SourceConstraint& sc = independent[i];
        const ModelPlane& target = candidates[i][pick[i]];
        extra.push_back(plane_row(local.affine_box(sc.local_element).plane(sc.axis, sc.side_added),
                                  target.value,
                                  to_model_ref(sc.local_element, sc.axis, sc.side_added),
                                  PlaneRef{target.element, target.axis, target.side, ""}));
      }
      ++out.combinations;
      ProjectResult r = project_to_feasible(local, local.q, weights, extra, o.manipulate);
      if (r.feasible && r.cost < best.cost) {
        best = r;
        best_rows = extra;
      }
      int d = 0;
      while (d < R && ++pick[d] == static_cast<int>(candidates[d].size())) pick[d++] = 0;
      if (d == R) break;
    }
  }
  Eigen::VectorXd q_local = local.q;
  std::vector<Relation> chosen_rows;
  if (best.feasible) {
    q_local = best.q;
    chosen_rows = best_rows;
    out.cost = best.cost;
  }
  // Alignment of the remaining prominent planes (every rest pose included).
  struct AddedPlane {
    AffineExpr expr;
    PlaneRef ref;
    double value;
  };
  std::vector<AddedPlane> mine_planes;
  for (int e = 0; e < local.element_count(); ++e) {
    const ElementId le(e);
    if (!local.element(le).is_principal()) continue;
    const AffineBox ab = local.affine_box(le);
    for (int k = 0; k < 3; ++k) {
      for (Side s : {Side::kMin, Side::kMax}) {
        AffineExpr ex = ab.plane(k, s);
        mine_planes.push_back({ex, to_model_ref(le, k, s), ex.value(q_local)});
      }
    }
  }
  for (const TemplateArticulation& a : local.articulations) {
    if (a.type == JointType::kBall) continue;
    for (ElementId le : a.moving) {
      if (!local.element(le).is_principal()) continue;
      const AffineBox pb = rest_pose_box(local, a, le);
      for (int k = 0; k < 3; ++k) {
        for (Side s : {Side::kMin, Side::kMax}) {
          AffineExpr ex = pb.plane(k, s);
          PlaneRef ref = to_model_ref(le, k, s);
          ref.pose = rest_pose_name(a);
          mine_planes.push_back({ex, ref, ex.value(q_local)});
        }
      }
    }
  }
  struct Alignment {
    std::size_t plane;
    ModelPlane target;
    double distance;
  };
  std::vector<Alignment> alignments;
  for (std::size_t i = 0; i < mine_planes.size(); ++i) {
    const AddedPlane& ap = mine_planes[i];
    const ModelPlane* closest = nullptr;
    for (const ModelPlane& p : planes) {
      if (p.axis != ap.ref.axis) continue;
      if (!closest || std::abs(p.value - ap.value) < std::abs(closest->value - ap.value))
        closest = &p;
    }
    if (closest && std::abs(closest->value - ap.value) < o.align_distance_mm) {
      alignments.push_back({i, *closest, std::abs(closest->value - ap.value)});
    }
  }
  std::stable_sort(alignments.begin(),
                   alignments.end(),
                   [](const Alignment& a, const Alignment& b) { return a.distance < b.distance; });
  std::vector<Eigen::VectorXd> determined = fixed_rows;
  for (const Relation& r : chosen_rows) determined.push_back(dense(r.terms, n));
  int determined_rank = rank_of(determined, n);
  for (const Alignment& al : alignments) {
    const AddedPlane& ap = mine_planes[al.plane];
    determined.push_back(dense(ap.expr.terms, n));
    const int r = rank_of(determined, n);
    if (r == determined_rank) {  // this plane is already restricted
      determined.pop_back();
      continue;
    }
    std::vector<Relation> trial = chosen_rows;
    trial.push_back(plane_row(ap.expr,
                              al.target.value,
                              ap.ref,
                              PlaneRef{al.target.element, al.target.axis, al.target.side, ""}));
    ProjectResult pr = project_to_feasible(local, local.q, weights, trial, o.manipulate);
    if (!pr.feasible) {
      determined.pop_back();
      continue;
    }
    determined_rank = r;
    chosen_rows = trial;
    q_local = pr.q;
    out.cost = pr.cost;
  }
  for (std::size_t i = 0; i < chosen_rows.size(); ++i) {
    const Relation& r = chosen_rows[i];
    SnapConstraint c;
    c.added = r.planes[0];
    c.target = r.planes[1];
    c.value = plane_value(model.box(c.target.element), c.target.axis, c.target.side);
    c.from_source = i < best_rows.size() && best.feasible;
    out.chosen.push_back(c);
  }
  for (std::size_t i = 0; i < mine.size(); ++i) {
    out.q.segment<kParamsPerElement>(mine[i].value * kParamsPerElement) =
        q_local.segment<kParamsPerElement>(static_cast<Eigen::Index>(i) * kParamsPerElement);
  }
  out.snapped = true;
  if (R > 0 && !best.feasible) {
    out.diagnostics.warning(codes::kConstrained,
                            fmt::format("'{}' could not be placed like in its source design '{}' "
                                        "({} constraint{}, {} placements tried); only nearby "
                                        "planes were aligned",
                                        added.name,
                                        design,
                                        R,
                                        R == 1 ? "" : "s",
                                        out.combinations));
  }
  out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

}  // namespace fabkit::templates
