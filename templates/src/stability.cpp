// Static equilibrium with linearised friction cones (paper §4.6).
#include "fabkit/templates/stability.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <numeric>

#include "fabkit/core/stop_clock.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "qp.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;

struct Contact {
  int lower = -1;               // body below along the normal (-1: the floor)
  int upper = -1;               // body pushed along +normal
  int axis = 2;                 // normal axis (+axis from lower to upper)
  std::array<Vec3, 4> corners;  // mm
};

}  // namespace

StabilityResult check_stability(const Template& t,
                                const ItemCatalog& catalog,
                                const StabilityOptions& o) {
  const auto start = Clock::now();
  StabilityResult out;
  out.element_stable.assign(static_cast<std::size_t>(t.element_count()), 1);
  std::vector<ElementId> principal;
  for (int e = 0; e < t.element_count(); ++e) {
    if (t.element(ElementId(e)).is_principal()) principal.push_back(ElementId(e));
  }
  if (principal.empty()) {
    out.stable = true;
    return out;
  }
  // Bodies: principal elements held together by connections.
  std::vector<int> parent(static_cast<std::size_t>(t.element_count()));
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int x) {
    return parent[x] == x ? x : parent[x] = root(parent[x]);
  };
  std::vector<char> anchored_element(parent.size(), 0);
  for (const Connection& c : t.connections) {
    if (c.principal.size() == 1) anchored_element[c.principal[0].value] = 1;
    for (std::size_t i = 1; i < c.principal.size(); ++i)
      parent[root(c.principal[i].value)] = root(c.principal[0].value);
  }
  std::map<int, int> body_of_root;
  std::vector<int> body_of(parent.size(), -1);
  for (ElementId e : principal) {
    const int r = root(e.value);
    if (!body_of_root.count(r)) {
      body_of_root[r] = static_cast<int>(out.bodies.size());
      out.bodies.emplace_back();
    }
    const int b = body_of_root[r];
    body_of[e.value] = b;
    out.bodies[b].elements.push_back(e);
    out.bodies[b].anchored = out.bodies[b].anchored || anchored_element[e.value];
  }
  const int nb = static_cast<int>(out.bodies.size());
  for (Body& b : out.bodies) {
    Vec3 moment = Vec3::Zero();
    for (ElementId e : b.elements) {
      const Box box = t.box(e);
      const Item* it = catalog.find(t.element(e).item);
      double m = it ? it->part_mass_kg(box.size) : 0.0;
      if (t.element(e).pattern) {
        // A pattern's mass is its parts', not its bounding box's.
        m = 0;
        for (const PlacedPart& p : t.placed_parts()) {
          if (p.element == e && it) m += it->part_mass_kg(p.box.size);
        }
      }
      b.mass_kg += m;
      moment += m * box.center;
    }
    b.center_of_mass = b.mass_kg > 0 ? Vec3(moment / b.mass_kg) : t.box(b.elements.front()).center;
  }
  // Contacts: touching faces between bodies, and the floor under the lowest parts.
  double floor = std::numeric_limits<double>::infinity();
  for (ElementId e : principal) floor = std::min(floor, t.box(e).min().z());
  const double tol = o.contact_tolerance_mm;
  std::vector<Contact> contacts;
  auto rectangle = [](int axis, double at, const Box& a, const Box& b) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double u0 = std::max(a.min()[u], b.min()[u]), u1 = std::min(a.max()[u], b.max()[u]);
    const double v0 = std::max(a.min()[v], b.min()[v]), v1 = std::min(a.max()[v], b.max()[v]);
    std::array<Vec3, 4> c;
    const std::array<std::pair<double, double>, 4> uv = {{{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}}};
    for (int i = 0; i < 4; ++i) {
      c[i][axis] = at;
      c[i][u] = uv[i].first;
      c[i][v] = uv[i].second;
    }
    return c;
  };
  for (std::size_t i = 0; i < principal.size(); ++i) {
    const ElementId a = principal[i];
    const Box ba = t.box(a);
    if (std::abs(ba.min().z() - floor) <= tol) {
      Box ground = ba;
      contacts.push_back({-1, body_of[a.value], 2, rectangle(2, floor, ba, ground)});
    }
    for (std::size_t j = i + 1; j < principal.size(); ++j) {
      const ElementId b = principal[j];
      if (body_of[a.value] == body_of[b.value]) continue;
      const Box bb = t.box(b);
      for (int k = 0; k < 3; ++k) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        if (ba.overlap(bb, u) <= tol || ba.overlap(bb, v) <= tol) continue;
        if (std::abs(ba.max()[k] - bb.min()[k]) <= tol) {
          contacts.push_back(
              {body_of[a.value], body_of[b.value], k, rectangle(k, ba.max()[k], ba, bb)});
        } else if (std::abs(bb.max()[k] - ba.min()[k]) <= tol) {
          contacts.push_back(
              {body_of[b.value], body_of[a.value], k, rectangle(k, bb.max()[k], ba, bb)});
        }
      }
    }
  }
  out.contacts = static_cast<int>(contacts.size());
  // Unknowns: per contact corner, a coefficient ≥ 0 per friction-cone edge.
  const int edges = std::max(3, o.cone_edges);
  const int per_contact = 4 * edges;
  const int nvar = per_contact * static_cast<int>(contacts.size());
  out.variables = nvar;
  // Rows: force (N) and torque about each body's centre of mass (N·m), per body, scaled by
  // the body's weight so that light and heavy bodies count alike.
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(6 * nb, nvar);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(6 * nb);
  std::vector<double> scale(nb, 1.0), load_scale(nb, 0.0);
  for (const Load& l : o.loads) {
    if (!l.element.valid() || l.element.value >= t.element_count() || body_of[l.element.value] < 0)
      continue;
    load_scale[body_of[l.element.value]] += l.force.norm();
  }
  for (int b = 0; b < nb; ++b) {
    scale[b] = 1.0 / std::max(1e-6, out.bodies[b].mass_kg * o.gravity + load_scale[b]);
  }
  auto add_wrench = [&](int b, int col, const Vec3& point_mm, const Vec3& f) {
    if (b < 0 || out.bodies[b].anchored) return;
    const Vec3 r = (point_mm - out.bodies[b].center_of_mass) * 1e-3;
    const Vec3 tq = r.cross(f);
    for (int k = 0; k < 3; ++k) {
      W(6 * b + k, col) += scale[b] * f[k];
      W(6 * b + 3 + k, col) += scale[b] * tq[k];
    }
  };
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const Contact& ct = contacts[c];
    const int u = (ct.axis + 1) % 3, v = (ct.axis + 2) % 3;
    for (int corner = 0; corner < 4; ++corner) {
      for (int j = 0; j < edges; ++j) {
        const double ang = 2 * std::numbers::pi * j / edges;
        Vec3 d = Vec3::Zero();
        d[ct.axis] = 1.0;
        d[u] = o.friction * std::cos(ang);
        d[v] = o.friction * std::sin(ang);
        const int col = static_cast<int>(c) * per_contact + corner * edges + j;
        add_wrench(ct.upper, col, ct.corners[corner], d);
        add_wrench(ct.lower, col, ct.corners[corner], -d);
      }
    }
  }
  for (int b = 0; b < nb; ++b) {
    if (out.bodies[b].anchored) continue;
    const double weight = out.bodies[b].mass_kg * o.gravity;
    w(6 * b + 2) += scale[b] * -weight;
  }
  for (const Load& l : o.loads) {
    if (!l.element.valid() || l.element.value >= t.element_count()) continue;
    const int b = body_of[l.element.value];
    if (b < 0 || out.bodies[b].anchored) continue;
    const Vec3 r = (l.point - out.bodies[b].center_of_mass) * 1e-3;
    const Vec3 tq = r.cross(l.force);
    for (int k = 0; k < 3; ++k) {
      w(6 * b + k) += scale[b] * l.force[k];
      w(6 * b + 3 + k) += scale[b] * tq[k];
    }
  }
  // min ‖W λ + w‖² over λ ≥ 0.
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(nvar);
  if (nvar > 0) {
    qp::Problem p;
    p.H = 2.0 * (W.transpose() * W + 1e-10 * Eigen::MatrixXd::Identity(nvar, nvar));
    p.g = 2.0 * W.transpose() * w;
    p.lower = Eigen::VectorXd::Zero(nvar);
    p.start = Eigen::VectorXd::Zero(nvar);
    qp::Settings s;
    const QpSolver solver =
        o.solver.value_or(nvar <= o.slsqp_up_to ? QpSolver::kSlsqp : QpSolver::kIpopt);
    s.backend = solver == QpSolver::kIpopt ? qp::Backend::kIpopt : qp::Backend::kSlsqp;
    s.tolerance = 1e-12;
    s.max_iterations = 2000;
    bool cut = false;
    if (o.deadline) {
      const double left = std::chrono::duration<double>(*o.deadline - Clock::now()).count();
      s.max_seconds = std::max(1e-4, left);
      cut = left <= 0;
    }
    const qp::Result r =
        cut ? qp::Result{p.start, {}, false, 0, "stopped at the deadline"} : qp::solve(p, s);
    lambda = r.z.cwiseMax(0.0);
    if (deadline_passed(o.deadline) && !r.converged) {
      // Cut short: the forces found so far say nothing about what would balance.
      out.timed_out = true;
      out.stable = false;
      for (Body& body : out.bodies) {
        body.stable = body.anchored;
        body.verdict = body.anchored ? "anchored" : "unknown";
      }
      out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      return out;
    }
    if (!r.converged) {
      out.diagnostics.warning(codes::kSolverFailed,
                              fmt::format("the contact-force QP did not converge ({}); the verdict "
                                          "may be pessimistic",
                                          r.message));
    }
  }
  const Eigen::VectorXd residual = W * lambda + w;
  out.stable = true;
  for (int b = 0; b < nb; ++b) {
    Body& body = out.bodies[b];
    if (body.anchored) {
      body.verdict = "anchored";
      continue;
    }
    const Vec3 f = residual.segment<3>(6 * b) / scale[b];
    const Vec3 tq = residual.segment<3>(6 * b + 3) / scale[b];
    body.unbalanced_force = f;
    body.unbalanced_torque = tq;
    Box extent = t.box(body.elements.front());
    for (ElementId e : body.elements) extent = extent.united(t.box(e));
    const double load = body.mass_kg * o.gravity + load_scale[b];
    const double size_m = std::max(1e-3, extent.size.norm() * 1e-3);
    const double rf = f.norm() / std::max(1e-9, load);
    const double rt = tq.norm() / std::max(1e-9, load * size_m);
    body.stable = rf <= o.imbalance && rt <= o.imbalance;
    body.verdict = body.stable ? "stable" : rt * size_m > rf * 0.5 * size_m ? "tips" : "slides";
    if (body.stable) continue;
    out.stable = false;
    for (ElementId e : body.elements) out.element_stable[e.value] = 0;
    std::vector<std::string> names;
    for (ElementId e : body.elements) names.push_back(t.element(e).name);
    out.diagnostics.error(
        codes::kUnstable,
        fmt::format("{} {} ({:.1f} kg; unbalanced {:.1f} N and {:.1f} N·m at "
                    "rest on the floor{})",
                    names.size() == 1 ? fmt::format("'{}'", names[0])
                                      : fmt::format("the parts joined to '{}' ({} parts: {})",
                                                    names[0],
                                                    names.size(),
                                                    fmt::join(names, ", ")),
                    body.verdict,
                    body.mass_kg,
                    f.norm(),
                    tq.norm(),
                    o.loads.empty() ? "" : " under the given loads"));
  }
  out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

}  // namespace fabkit::templates
