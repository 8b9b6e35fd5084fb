#include "hanging.h"

#include <ceres/jet.h>
#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>

#include "fabkit/core/solvers/manifold_solver.h"

namespace fabkit::hacks::detail {
namespace {

// The most parameters one part's solve takes: its joint above (two sides of up to three) and
// its side of one joint below. A part with more is left to the relaxation (the pass does not
// apply).
constexpr int kMostParameters = 8;
using Jet = ceres::Jet<double, kMostParameters>;

// A weight hanging from a connector of the part: `mass` lumped at the connector's origin.
struct Load {
  const Connector* connector = nullptr;
  double mass = 0;
};

// One part on the joint it hangs by, under its own weight and the loads hanging from it: the
// mean height (mm, weighted by mass) of the part's centre of mass and of each load's
// connector, in the parameters of the joint above and of the part's sides of the joints below.
class PartUnderLoads : public solvers::ManifoldProblem {
 public:
  PartUnderLoads(const Assembly& a,
                 ConnectionId up,
                 const Rigid<double>& parent,
                 double mass,
                 const Vec3& centre,
                 std::vector<Load> loads,
                 std::vector<int> parameters,
                 std::vector<double> scales,
                 const std::vector<double>& x)
      : a_(a),
        up_(up),
        parent_(parent.cast<Jet>()),
        mass_(mass),
        centre_(centre),
        loads_(std::move(loads)),
        parameters_(std::move(parameters)),
        scales_(std::move(scales)),
        x_(x.begin(), x.end()) {
    // A mean, not a sum: the tolerances mean the same for a light part and a loaded one.
    double total = mass_;
    for (const Load& load : loads_) total += load.mass;
    scale_ = total > 0 ? 1.0 / total : 1.0;
  }

  int variables() const override { return static_cast<int>(parameters_.size()); }
  int objectives() const override { return 1; }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }

  void evaluate(const double* z, double* values, double* jacobian) override {
    const Jet v = potential(z);
    values[0] = v.a;
    for (int k = 0; k < variables(); ++k) jacobian[k] = v.v[k];
  }
  void evaluate_values(const double* z, double* values) override { values[0] = potential(z).a; }

  // Central differences of the exact slope: a handful of parameters, so a few evaluations.
  bool lagrangian_hessian(const double* z,
                          const std::vector<int>& rows,
                          const Eigen::VectorXd& lambda,
                          Eigen::MatrixXd& hessian) override {
    (void)rows;
    (void)lambda;
    const int n = variables();
    constexpr double kStep = 1e-4;
    std::vector<double> at(z, z + n);
    hessian.resize(n, n);
    for (int k = 0; k < n; ++k) {
      const double keep = at[static_cast<std::size_t>(k)];
      at[static_cast<std::size_t>(k)] = keep + kStep;
      const Jet up = potential(at.data());
      at[static_cast<std::size_t>(k)] = keep - kStep;
      const Jet down = potential(at.data());
      at[static_cast<std::size_t>(k)] = keep;
      for (int j = 0; j < n; ++j) hessian(j, k) = (up.v[j] - down.v[j]) / (2 * kStep);
    }
    hessian = 0.5 * (hessian + hessian.transpose()).eval();
    return true;
  }

  // The part's parameters at z, written into x.
  void write(const Eigen::VectorXd& z, std::vector<double>& x) const {
    for (std::size_t k = 0; k < parameters_.size(); ++k) {
      x[static_cast<std::size_t>(parameters_[k])] = z[static_cast<Eigen::Index>(k)] * scales_[k];
    }
  }

 private:
  Jet potential(const double* z) {
    for (std::size_t k = 0; k < parameters_.size(); ++k) {
      Jet& value = x_[static_cast<std::size_t>(parameters_[k])];
      value = Jet(z[k] * scales_[k]);
      value.v[static_cast<Eigen::Index>(k)] = scales_[k];
    }
    const Rigid<Jet> frame = a_.child_frame<Jet>(up_, parent_, x_.data());
    Jet v = mass_ * (frame.R.row(2).dot(centre_.cast<Jet>()) + frame.t.z());
    for (const Load& load : loads_) {
      v += load.mass * a_.connector_world<Jet>(*load.connector, frame, x_.data()).t.z();
    }
    return v * scale_;
  }

  const Assembly& a_;
  ConnectionId up_;
  Rigid<Jet> parent_;
  double mass_;
  Vec3 centre_;
  std::vector<Load> loads_;
  std::vector<int> parameters_;
  std::vector<double> scales_;
  std::vector<Jet> x_;
  double scale_ = 1;
};

}  // namespace

std::optional<std::vector<double>> hung_from_the_top(const Problem& p,
                                                     const Variables& vars,
                                                     const std::vector<double>& x) {
  if (!p.closures.empty() || !p.multi.empty()) return std::nullopt;
  const Assembly& a = *p.assembly;
  const KinematicGraph& g = a.graph();
  const std::size_t parts = a.nodes().size();
  auto moves = [&](std::size_t i) {
    return !a.nodes()[i].environment && (p.group < 0 || p.part_group[i] == p.group);
  };
  std::vector<int> slot(x.size(), -1);  // parameter -> index into vars
  for (std::size_t k = 0; k < vars.index.size(); ++k) {
    slot[static_cast<std::size_t>(vars.index[k])] = static_cast<int>(k);
  }
  Eigen::VectorXd lo, hi;
  scaled_bounds(a, vars, lo, hi);
  // The free parameters of one side of a connection.
  auto free_of = [&](const Connector& side, std::vector<int>& out) {
    for (std::size_t i = 0; i < side.params.size(); ++i) {
      const int k = slot[static_cast<std::size_t>(side.offset) + i];
      if (k >= 0) out.push_back(k);
    }
  };
  // What hangs below each tree connection.
  std::vector<double> below(a.connections().size(), 0.0);
  std::vector<std::vector<ConnectionId>> down(parts);
  for (std::size_t i = 0; i < parts; ++i) {
    const ConnectionId up = g.parent_edge(PartId{static_cast<int>(i)});
    if (!up.valid() || !moves(i)) continue;
    down[a.connection(up).first.part.index()].push_back(up);
    for (PartId q : g.below(up)) below[up.index()] += p.masses[q.index()];
  }

  std::vector<double> out = x;
  std::vector<Rigid<double>> frames = a.all_part_frames<double>(out.data());
  std::vector<std::string> last_kinds;
  Eigen::VectorXd last_z;
  // Parents precede their children in the assembly's order.
  for (std::size_t i = 0; i < parts; ++i) {
    if (!moves(i)) continue;
    const ConnectionId up = g.parent_edge(PartId{static_cast<int>(i)});
    if (!up.valid()) return std::nullopt;  // a part not hanging from anything
    const Connection& joint = a.connection(up);
    std::vector<int> local;
    free_of(joint.first, local);
    const std::size_t above = local.size();
    free_of(joint.second, local);
    // A part its joint holds rigidly is not a weight hanging from a point.
    if (local.size() == above) return std::nullopt;
    std::vector<Load> loads;
    for (ConnectionId d : down[i]) {
      const Connection& c = a.connection(d);
      std::vector<int> lower;
      free_of(c.second, lower);
      if (lower.empty()) return std::nullopt;
      free_of(c.first, local);
      loads.push_back({&c.first, below[d.index()]});
    }
    if (static_cast<int>(local.size()) > kMostParameters) return std::nullopt;
    std::vector<int> parameters;
    std::vector<double> scales;
    Eigen::VectorXd z(static_cast<Eigen::Index>(local.size()));
    Eigen::VectorXd l(z.size()), h(z.size());
    for (std::size_t k = 0; k < local.size(); ++k) {
      const auto v = static_cast<std::size_t>(local[k]);
      parameters.push_back(vars.index[v]);
      scales.push_back(vars.scale[v]);
      z[static_cast<Eigen::Index>(k)] =
          out[static_cast<std::size_t>(vars.index[v])] / vars.scale[v];
      l[static_cast<Eigen::Index>(k)] = lo[static_cast<Eigen::Index>(v)];
      h[static_cast<Eigen::Index>(k)] = hi[static_cast<Eigen::Index>(v)];
    }
    PartUnderLoads part(a,
                        up,
                        frames[joint.first.part.index()],
                        p.masses[i],
                        p.coms[i],
                        std::move(loads),
                        parameters,
                        scales,
                        out);
    // Parts of a chain hang alike: the joint above the last part solved, where its parameters
    // are the same kinds, is a start as good as this one's own (the lower of the two is taken).
    std::vector<std::string> kinds;
    for (int index : parameters) {
      const ParamInfo& info = a.parameters()[static_cast<std::size_t>(index)];
      kinds.push_back(
          fmt::format("{}/{}/{}/{}",
                      static_cast<int>(a.node(info.part).part->primitive(info.primitive).type),
                      info.spec.name,
                      info.spec.lo,
                      info.spec.hi));
    }
    const Eigen::VectorXd own = z;
    if (kinds == last_kinds) {
      double here = 0, there = 0;
      part.evaluate_values(z.data(), &here);
      part.evaluate_values(last_z.data(), &there);
      if (there < here) z = last_z;
    }
    solvers::ManifoldSolverOptions options;
    options.gradient_tolerance = 1e-6;
    options.max_step = 180;
    options.stop = p.stop;
    Eigen::VectorXd rest = solvers::ManifoldSolver(part, l, h, options).relax(z, 30).z;
    // A turn that costs nothing once the part hangs (about the vertical through its contact)
    // still slopes on the way there, and the descent can run it into a stop: every S-hook of
    // a 64-hook chain ended with its hooks' tilts at 45°. Such a parameter is put back where
    // the part's own start had it and held there, the others solved again, and that rest is
    // taken if it is as low: the free turns stay where the connects put them, as step 2 leaves
    // neutral directions, and the relaxation's projections do not clip them at their stops.
    {
      std::vector<Eigen::Index> stopped;
      for (Eigen::Index k = 0; k < rest.size(); ++k) {
        const bool at_stop = rest[k] <= l[k] + 1e-9 || rest[k] >= h[k] - 1e-9;
        if (at_stop && own[k] > l[k] + 1e-9 && own[k] < h[k] - 1e-9) stopped.push_back(k);
      }
      if (!stopped.empty()) {
        Eigen::VectorXd held = rest, hl = l, hh = h;
        for (Eigen::Index k : stopped) held[k] = hl[k] = hh[k] = own[k];
        held = solvers::ManifoldSolver(part, hl, hh, options).relax(held, 30).z;
        double before = 0, after = 0;
        part.evaluate_values(rest.data(), &before);
        part.evaluate_values(held.data(), &after);
        if (after <= before + 1e-9 * std::max(1.0, std::abs(before))) rest = held;
      }
    }
    part.write(rest, out);
    last_kinds = std::move(kinds);
    last_z = rest;
    frames[i] = a.child_frame<double>(up, frames[joint.first.part.index()], out.data());
  }
  // Lumping is exact only where what hangs below a joint swings freely: a start it made higher
  // than the one it was given is not taken (nor one a degenerate part's solve left undefined).
  const double hung = group_energy(p, out);
  if (!std::isfinite(hung) || hung > group_energy(p, x)) return std::nullopt;
  return out;
}

}  // namespace fabkit::hacks::detail
