// Connecting (paper §4.5, eq. 4).
#include "fabkit/templates/connect.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "fabkit/core/stop_clock.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/extract.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;

double box_distance(const Box& a, const Box& b) {
  return (a.center - b.center).cwiseAbs().sum() + (a.size - b.size).cwiseAbs().sum();
}

std::string connection_label(const Template& t, const Connection& c) {
  std::vector<std::string> p, k;
  for (ElementId e : c.principal) p.push_back(t.element(e).name);
  for (ElementId e : c.connecting) {
    const Element& el = t.element(e);
    k.push_back(el.pattern ? fmt::format("{} x {}", el.pattern->total(), el.item) : el.item);
  }
  return fmt::format("{}: {} ({})", t.name, fmt::join(p, " + "), fmt::join(k, ", "));
}

// A connection of `source` instantiated between model elements a and b (source principal
// p1 → a, p2 → b): its connecting elements are appended to `trial` and its relations remapped.
struct Instantiated {
  std::vector<ElementId> connecting;
  std::vector<Relation> hard, soft, own;  // own: per-element relations of the connectors
};

Instantiated instantiate(Template& trial,
                         const Template& source,
                         const Connection& c,
                         ElementId p1,
                         ElementId p2,
                         ElementId a,
                         ElementId b) {
  Instantiated out;
  std::map<int, int> element_map{{p1.value, a.value}, {p2.value, b.value}};
  // Place the connectors where they were relative to p1, moved with it.
  const Vec3 shift = trial.box(a).center - source.box(p1).center;
  for (ElementId e : c.connecting) {
    const int id = trial.element_count();
    Element copy = source.element(e);
    copy.node = trial.root();
    trial.elements.push_back(copy);
    Eigen::VectorXd grown(trial.q.size() + kParamsPerElement);
    grown << trial.q, source.q.segment<kParamsPerElement>(e.value * kParamsPerElement);
    grown.segment<3>(id * kParamsPerElement) += shift;
    trial.q = grown;
    element_map[e.value] = id;
    out.connecting.push_back(ElementId(id));
  }
  auto remap = [&](Relation r) {
    for (LinearTerm& t : r.terms) {
      t.index = element_map.at(t.index / kParamsPerElement) * kParamsPerElement +
                t.index % kParamsPerElement;
    }
    for (ElementId& e : r.elements) e = ElementId(element_map.at(e.value));
    for (PlaneRef& p : r.planes) p.element = ElementId(element_map.at(p.element.value));
    r.connection = ConnectionId();
    return r;
  };
  for (RelationId r : c.relations) out.hard.push_back(remap(source.relation(r)));
  for (RelationId r : c.placement) out.soft.push_back(remap(source.relation(r)));
  std::set<int> conn;
  for (ElementId e : c.connecting) conn.insert(e.value);
  for (const Relation& r : source.relations) {
    if (r.connection.valid() || r.elements.size() != 1 || !conn.count(r.elements[0].value))
      continue;
    out.own.push_back(remap(r));
  }
  return out;
}

struct Evaluation {
  bool feasible = false;
  double error = std::numeric_limits<double>::infinity();
  std::vector<ElementId> free;  // model (trial) ids, in local order
  Eigen::VectorXd q_local;      // their solved parameters
};

// Eq. 4 restricted to the elements that may move for this pair (the added template, the
// existing element it joins and the new connectors), the rest of the model held as it is.
Evaluation evaluate(Template trial,
                    const Instantiated& inst,
                    std::vector<ElementId> free,
                    const ConnectOptions& o) {
  Evaluation ev;
  for (const std::vector<Relation>* rs : {&inst.hard, &inst.soft, &inst.own}) {
    trial.relations.insert(trial.relations.end(), rs->begin(), rs->end());
  }
  free.insert(free.end(), inst.connecting.begin(), inst.connecting.end());
  const Template local = trial.restricted_to(free);
  const Eigen::Index n = local.q.size();
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(n);
  for (int e = 0; e < local.element_count(); ++e) {
    if (local.element(ElementId(e)).is_principal())
      weights.segment<kParamsPerElement>(e * kParamsPerElement).setOnes();
  }
  const ProjectResult r = project_to_feasible(local, local.q, weights, {}, o.manipulate);
  ev.feasible = r.feasible;
  ev.free = free;
  ev.q_local = r.q;
  double worst = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (weights[i] > 0) worst = std::max(worst, std::abs(r.q[i] - local.q[i]));
  }
  ev.error = r.feasible ? worst : std::numeric_limits<double>::infinity();
  return ev;
}

}  // namespace

ConnectResult connect(WorkingModel& wm,
                      const Composition& added,
                      const TemplateDatabase& db,
                      const ConnectOptions& o) {
  const auto start = Clock::now();
  ConnectResult out;
  Template& model = wm.model();
  const std::vector<ElementId> mine = model.elements_under(added.node);
  const std::set<ElementId> mine_set(mine.begin(), mine.end());
  std::vector<ElementId> theirs;
  for (int e = 0; e < model.element_count(); ++e) {
    const ElementId id(e);
    if (!mine_set.count(id) && model.element(id).is_principal()) theirs.push_back(id);
  }
  // Linked elements: touching faces (or edges) after snapping.
  std::vector<std::pair<ElementId, ElementId>> links;
  for (ElementId a : mine) {
    if (!model.element(a).is_principal()) continue;
    for (ElementId w : theirs) {
      const Box ba = model.box(a), bw = model.box(w);
      if (!ba.touches(bw, o.link_distance_mm)) continue;
      int overlapping = 0;
      for (int k = 0; k < 3; ++k) overlapping += ba.overlap(bw, k) > 1.0;
      if (overlapping >= 2) links.emplace_back(a, w);
    }
  }
  const std::string design = mine.empty() ? "" : model.element(mine.front()).source;
  const Template* td = db.source_template(design);
  std::vector<ElementId> mine_principal;
  for (ElementId e : mine) {
    if (model.element(e).is_principal()) mine_principal.push_back(e);
  }
  // While connectors are fitted, parts may shift but not into each other or the floor.
  {
    double floor = std::numeric_limits<double>::infinity();
    for (ElementId e : theirs) floor = std::min(floor, model.box(e).min().z());
    std::vector<Relation> guard = non_penetration_relations(model, mine_principal, theirs);
    if (std::isfinite(floor)) {
      for (ElementId e : mine_principal) {
        Relation r;
        r.kind = RelationKind::kOrder;
        r.equality = false;
        r.terms = {{center_index(e, 2), -1.0}, {size_index(e, 2), 0.5}};
        r.rhs = -floor;
        r.elements = {e};
        r.planes = {PlaneRef{e, 2, Side::kMin, ""}};
        if (model.box(e).min().z() >= floor - 1e-9) guard.push_back(std::move(r));
      }
    }
    for (Relation& r : guard) store_relation(model, std::move(r));
  }
  // The source design fitted once to the added template's shape: min ‖S q_D − q_A‖ (§4.5).
  Eigen::VectorXd fitted_source;
  std::set<int> added_sources;
  if (td) {
    Eigen::VectorXd ref = td->q;
    Eigen::VectorXd weights = Eigen::VectorXd::Zero(ref.size());
    for (ElementId e : mine) {
      const Element& el = model.element(e);
      if (el.source != design) continue;
      added_sources.insert(el.source_element.value);
      ref.segment<kParamsPerElement>(el.source_element.value * kParamsPerElement) =
          model.q.segment<kParamsPerElement>(e.value * kParamsPerElement);
      weights.segment<kParamsPerElement>(el.source_element.value * kParamsPerElement).setOnes();
    }
    for (int e = 0; e < td->element_count(); ++e) {
      if (weights[e * kParamsPerElement] == 0 && td->element(ElementId(e)).is_principal()) {
        weights.segment<kParamsPerElement>(e * kParamsPerElement).setConstant(1e-4);
      }
    }
    fitted_source = project_to_feasible(*td, ref, weights, {}, o.manipulate).q;
  }

  for (const auto& [a, w] : links) {
    Link link;
    link.added = a;
    link.existing = w;
    struct Candidate {
      const Template* source;
      ConnectionId connection;
      ElementId p1, p2;  // p1 → a, p2 → w
      bool transferred;
      double distance;
    };
    std::vector<Candidate> candidates;
    // 1. Transfer from the source design: connections joining a's source element to an element
    // outside the added template whose fitted box is closest to w.
    if (td && model.element(a).source == design) {
      const ElementId a_src = model.element(a).source_element;
      for (std::size_t ci = 0; ci < td->connections.size(); ++ci) {
        const Connection& c = td->connections[ci];
        if (c.principal.size() != 2 || c.connecting.empty()) continue;
        const int side = c.principal[0] == a_src ? 0 : c.principal[1] == a_src ? 1 : -1;
        if (side < 0) continue;
        const ElementId other = c.principal[1 - side];
        if (added_sources.count(other.value)) continue;
        const Box fitted = td->box(other, fitted_source);
        ElementId closest;
        double best = std::numeric_limits<double>::infinity();
        for (ElementId e : theirs) {
          const double d = box_distance(fitted, model.box(e));
          if (d < best) {
            best = d;
            closest = e;
          }
        }
        if (closest == w) {
          candidates.push_back({td, ConnectionId(static_cast<int>(ci)), a_src, other, true, 0.0});
        }
      }
    }
    // 2. The database's closest connections by descriptor.
    const ConnectionExample query = describe_pair(model, db.catalog(), a, w);
    std::vector<std::pair<double, Candidate>> ranked;
    const auto articulated = [](const Template& t, ElementId e) {
      for (const TemplateArticulation& art : t.articulations) {
        if (std::find(art.moving.begin(), art.moving.end(), e) != art.moving.end()) return &art;
      }
      return static_cast<const TemplateArticulation*>(nullptr);
    };
    const bool pair_moves = articulated(model, a) != articulated(model, w);
    for (const ConnectionExample& ex : db.connection_examples()) {
      bool swapped = false;
      const double d = descriptor_distance(query, ex, &swapped);
      if (!std::isfinite(d)) continue;
      const Template* src = db.source_template(ex.design);
      if (!src) continue;
      // Hinges and slides join a moving part to a fixed one: only for pairs that move so.
      if ((articulated(*src, ex.principal[0]) != articulated(*src, ex.principal[1])) !=
          pair_moves) {
        continue;
      }
      const ElementId p1 = swapped ? ex.principal[1] : ex.principal[0];
      const ElementId p2 = swapped ? ex.principal[0] : ex.principal[1];
      ranked.push_back({d, Candidate{src, ex.connection, p1, p2, false, d}});
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) {
      return x.first < y.first;
    });
    for (int i = 0; i < std::min<int>(o.k, static_cast<int>(ranked.size())); ++i)
      candidates.push_back(ranked[i].second);

    // Evaluate each (eq. 4); a transferred connection that passes wins, else the database's
    // candidate with the smallest error.
    int best_index = -1;
    Evaluation best_eval;
    std::vector<ElementId> free = mine;
    free.push_back(w);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      // Each candidate costs a copy of the model and a projection (about a millisecond): past
      // the deadline the rest are not tried, and the caller reports the time limit.
      if (deadline_passed(o.manipulate.deadline)) break;
      const Candidate& cand = candidates[i];
      const Connection& c = cand.source->connections[cand.connection.value];
      Template trial = model;
      const Instantiated inst = instantiate(trial, *cand.source, c, cand.p1, cand.p2, a, w);
      const Evaluation ev = evaluate(std::move(trial), inst, free, o);
      ConnectionCandidate report;
      report.source = connection_label(*cand.source, c);
      report.transferred = cand.transferred;
      report.descriptor_distance = cand.distance;
      report.error_mm = ev.error;
      report.feasible = ev.feasible;
      const bool passes = ev.feasible && ev.error <= o.error_threshold_mm;
      link.tried.push_back(report);
      if (!passes) continue;
      const bool better = best_index < 0 || (!candidates[best_index].transferred &&
                                             (cand.transferred || ev.error < best_eval.error));
      if (better) {
        best_index = static_cast<int>(i);
        best_eval = ev;
      }
    }
    if (best_index < 0) {
      std::vector<std::string> tried;
      for (const ConnectionCandidate& c : link.tried) {
        tried.push_back(
            fmt::format("{} ({})",
                        c.source,
                        c.feasible ? fmt::format("moves the design {:.0f} mm, more than {:g} mm",
                                                 c.error_mm,
                                                 o.error_threshold_mm)
                                   : std::string("its constraints cannot all hold here")));
      }
      link.message = fmt::format(
          "no connection found between '{}' and '{}'{}{}",
          model.element(a).name,
          model.element(w).name,
          tried.empty() ? "; the database has no connection between these materials" : "; tried: ",
          fmt::join(tried, "; "));
      out.links.push_back(std::move(link));
      continue;
    }
    link.tried[best_index].accepted = true;
    // Commit: the connectors join the model, their relations are stored at the pair's lowest
    // common ancestor under a new connection node, and the solved parameters are taken.
    const Candidate& chosen = candidates[best_index];
    const Connection& source_connection = chosen.source->connections[chosen.connection.value];
    Instantiated inst =
        instantiate(model, *chosen.source, source_connection, chosen.p1, chosen.p2, a, w);
    for (std::size_t i = 0; i < best_eval.free.size(); ++i) {
      model.q.segment<kParamsPerElement>(best_eval.free[i].value * kParamsPerElement) =
          best_eval.q_local.segment<kParamsPerElement>(static_cast<Eigen::Index>(i) *
                                                       kParamsPerElement);
    }
    Connection conn;
    conn.name = fmt::format("joint_{}_{}", model.element(a).name, model.element(w).name);
    conn.principal = {a, w};
    conn.connecting = inst.connecting;
    conn.source = chosen.source->name;
    for (const ElementId e : inst.connecting) {
      Element& el = model.elements[e.value];
      el.name = fmt::format("{}_{}", el.name, model.element(w).name);
    }
    NodeId parent = model.lowest_common_ancestor(model.element(a).node, model.element(w).node);
    if (model.node(parent).element) parent = model.node(parent).parent;
    for (Relation r : inst.hard)
      conn.relations.push_back(store_relation(model, std::move(r), parent));
    for (Relation r : inst.soft)
      conn.placement.push_back(store_relation(model, std::move(r), parent));
    for (Relation r : inst.own) store_relation(model, std::move(r), parent);
    link.connection = model.add_connection(std::move(conn), parent);
    out.links.push_back(std::move(link));
  }
  // New geosemantic relations between the added template and the model, read off the
  // connected geometry (paper §4.5, final composition).
  // A pair that found no connection is an error unless its added element is held by another
  // connection (a post screwed to the leg may also touch the seat: that contact just stays one).
  for (const Link& l : out.links) {
    if (l.connection) continue;
    bool held = false;
    for (const Link& other : out.links) held = held || (other.added == l.added && other.connection);
    if (held) {
      out.diagnostics.note(codes::kNoConnection,
                           l.message + fmt::format("; '{}' is held by its other connections",
                                                   model.element(l.added).name));
    } else {
      out.diagnostics.error(codes::kNoConnection, l.message);
    }
  }
  if (links.empty() && !mine_principal.empty()) {
    out.diagnostics.warning(codes::kFloatingPart,
                            fmt::format("'{}' touches nothing in the model: there is nothing to "
                                        "connect it to (move it against a part, or snap it)",
                                        added.name));
  }
  for (Relation& r : principal_relations(model, mine_principal, theirs)) {
    store_relation(model, std::move(r));
    ++out.relations_added;
  }
  // Final least squares (§4.5): the model nearest its connected configuration on which every
  // relation, new ones included, holds exactly (planes read as coplanar within the extraction
  // tolerance become exactly so).
  if (model.max_violation() > 1e-12) {
    Eigen::VectorXd weights = Eigen::VectorXd::Zero(model.q.size());
    for (int e = 0; e < model.element_count(); ++e) {
      if (model.element(ElementId(e)).is_principal())
        weights.segment<kParamsPerElement>(e * kParamsPerElement).setOnes();
    }
    const ProjectResult fin = project_to_feasible(model, model.q, weights, {}, o.manipulate);
    if (fin.feasible) model.q = fin.q;
  }
  out.all_connected = !out.diagnostics.has_errors() && !links.empty();
  out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

}  // namespace fabkit::templates
