#include "kinematics.h"

#include <ceres/jet.h>

#include <cmath>
#include <limits>

namespace fabkit::hacks::detail {

void local_connector_twists(const Primitive& prim, const double* q, Vec3* w, Vec3* v) {
  using Jet3 = ceres::Jet<double, 3>;
  const int dof = connector_dof(prim.connector_kind());
  Jet3 qj[3];
  for (int i = 0; i < dof; ++i) {
    qj[i] = Jet3(q[i]);
    qj[i].v[i] = 1.0;
  }
  Rigid<Jet3> l;
  apply_connector<Jet3>(prim.connector_kind(), prim.shape, qj, l);
  Mat3 r;
  Vec3 t;
  for (int a = 0; a < 3; ++a) {
    t[a] = l.t[a].a;
    for (int b = 0; b < 3; ++b) r(a, b) = l.R(a, b).a;
  }
  for (int j = 0; j < dof; ++j) {
    Mat3 dr;
    Vec3 dt;
    for (int a = 0; a < 3; ++a) {
      dt[a] = l.t[a].v[j];
      for (int b = 0; b < 3; ++b) dr(a, b) = l.R(a, b).v[j];
    }
    const Mat3 omega = dr * r.transpose();
    w[j] = Vec3(omega(2, 1), omega(0, 2), omega(1, 0));
    v[j] = dt - w[j].cross(t);
  }
}

bool Problem::covers(const Assembly& a, ConnectionId c) const {
  if (group < 0) return true;
  const Connection& conn = a.connection(c);
  return part_group[conn.first.part.index()] == group ||
         part_group[conn.second.part.index()] == group;
}

int group_count(const Assembly& a) {
  int count = 0;
  a.graph().movable_groups(&count);
  return count;
}

Problem make_problem(const Assembly& a, int group) {
  Problem p;
  p.assembly = &a;
  p.group = group;
  p.part_group = a.graph().movable_groups();
  p.target = make_target(a);
  if (p.target && group >= 0 && p.part_group[p.target->part.index()] != group) p.target.reset();
  for (ConnectionId c : a.cycle_connections()) {
    if (!p.covers(a, c)) continue;
    p.closures.push_back(c);
    p.free_axes.push_back(free_rotation_axis(a, c));
  }
  for (MultiConnectionPair& m : multi_connection_pairs(a)) {
    const ConnectionId c = a.parameters()[static_cast<std::size_t>(m.params_i.front())].connection;
    if (p.covers(a, c)) p.multi.push_back(std::move(m));
  }
  for (std::size_t i = 0; i < a.nodes().size(); ++i) {
    const PartNode& n = a.nodes()[i];
    const bool in = group < 0 || p.part_group[i] == group;
    const double m = n.environment || !in ? 0.0 : std::max(0.0, n.part->mass);
    p.masses.push_back(m);
    p.coms.push_back(n.part->center_of_mass);
    p.total_mass += m;
  }
  return p;
}

Variables select_variables(const Assembly& a, bool physics, const Problem* only) {
  Variables v;
  for (int i = 0; i < a.parameter_count(); ++i) {
    const ParamInfo& p = a.parameters()[static_cast<std::size_t>(i)];
    if (p.spec.constant) continue;
    if (physics && p.spec.fixed_under_physics) continue;
    if (only && !only->covers(a, p.connection)) continue;
    v.index.push_back(i);
    double scale = 1.0;
    if (!p.spec.is_angle()) {
      const Primitive& prim = a.node(p.part).part->primitive(p.primitive);
      const std::vector<double> cd = prim.critical_dim();
      double length = cd.empty() ? 100.0 : cd[0];
      if (p.spec.name == "t" && prim.type == PrimitiveType::kClip) length = prim.shape.height;
      if (p.spec.name == "t2" && cd.size() > 1) length = cd[1];
      scale = 1.0 / std::max(length, 1.0);
    }
    v.scale.push_back(scale);
  }
  return v;
}

std::vector<double> to_z(const Variables& v, const std::vector<double>& x) {
  std::vector<double> z;
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    z.push_back(x[static_cast<std::size_t>(v.index[k])] / v.scale[k]);
  }
  return z;
}

void from_z(const Variables& v, const std::vector<double>& z, std::vector<double>& x) {
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    x[static_cast<std::size_t>(v.index[k])] = z[k] * v.scale[k];
  }
}

double max_gap(const Assembly& a, const std::vector<double>& x, double* deg) {
  double mm = 0;
  double angle = 0;
  for (const ClosureGap& g : closure_gaps(a, x)) {
    mm = std::max(mm, g.position_mm);
    angle = std::max(angle, g.rotation_deg);
  }
  if (deg) *deg = angle;
  return mm;
}

Eigen::VectorXd scaled(const Variables& vars, const std::vector<double>& x) {
  const std::vector<double> z = to_z(vars, x);
  return Eigen::Map<const Eigen::VectorXd>(z.data(), static_cast<int>(z.size()));
}

void scaled_bounds(const Assembly& a,
                   const Variables& vars,
                   Eigen::VectorXd& lo,
                   Eigen::VectorXd& hi) {
  const int n = static_cast<int>(vars.index.size());
  lo = Eigen::VectorXd::Constant(n, -std::numeric_limits<double>::infinity());
  hi = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  for (int k = 0; k < n; ++k) {
    const ParamSpec& s =
        a.parameters()[static_cast<std::size_t>(vars.index[static_cast<std::size_t>(k)])].spec;
    if (s.tag == ParamTag::kUnbounded) continue;
    lo[k] = s.lo / vars.scale[static_cast<std::size_t>(k)];
    hi[k] = s.hi / vars.scale[static_cast<std::size_t>(k)];
  }
}

}  // namespace fabkit::hacks::detail
