#include "fabkit/rods/frame_analysis.h"

#include <fmt/format.h>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "fabkit/rods/diagnostic_codes.h"

namespace fabkit::rods {
namespace {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

// Local stiffness of a 3D beam (x along the beam; y, z principal axes), DOFs per node
// (ux, uy, uz, θx, θy, θz) with du_y/dx = θz and du_z/dx = −θy.
Mat12 local_stiffness(double L, double E, double G, double A, double Iy, double Iz, double J) {
  Mat12 k = Mat12::Zero();
  const double ea = E * A / L, gj = G * J / L;
  k(0, 0) = k(6, 6) = ea;
  k(0, 6) = -ea;
  k(3, 3) = k(9, 9) = gj;
  k(3, 9) = -gj;
  const double z12 = 12 * E * Iz / (L * L * L), z6 = 6 * E * Iz / (L * L), z4 = 4 * E * Iz / L,
               z2 = 2 * E * Iz / L;
  k(1, 1) = k(7, 7) = z12;
  k(1, 7) = -z12;
  k(1, 5) = k(1, 11) = z6;
  k(5, 7) = k(7, 11) = -z6;
  k(5, 5) = k(11, 11) = z4;
  k(5, 11) = z2;
  const double y12 = 12 * E * Iy / (L * L * L), y6 = 6 * E * Iy / (L * L), y4 = 4 * E * Iy / L,
               y2 = 2 * E * Iy / L;
  k(2, 2) = k(8, 8) = y12;
  k(2, 8) = -y12;
  k(2, 4) = k(2, 10) = -y6;
  k(4, 8) = k(8, 10) = y6;
  k(4, 4) = k(10, 10) = y4;
  k(4, 10) = y2;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < i; ++j) k(i, j) = k(j, i);
  }
  return k;
}

// Work-equivalent nodal loads of a uniform load q (local axes, N/mm) over length L.
Vec12 uniform_load(const Vec3& q, double L) {
  Vec12 f = Vec12::Zero();
  f.segment<3>(0) = q * L / 2;
  f.segment<3>(6) = q * L / 2;
  f(4) = -q.z() * L * L / 12;
  f(5) = q.y() * L * L / 12;
  f(10) = q.z() * L * L / 12;
  f(11) = -q.y() * L * L / 12;
  return f;
}

}  // namespace

FrameResult analyse_frame(const Structure& s,
                          const Parameters& p,
                          const Layout& l,
                          const FrameOptions& options,
                          std::span<const JointMass> joint_masses) {
  FrameResult r;
  const int n = static_cast<int>(s.nodes.size());
  const int dofs = 6 * n;
  const RodMaterial& m = p.rod_material;
  const double A = p.section_area(), I = p.section_inertia(), J = p.section_torsion();
  const double section_modulus = I / p.radius;
  const double g = options.gravity;

  // Supports.
  r.supports = options.supports;
  if (r.supports.empty()) {
    double ground = std::numeric_limits<double>::infinity();
    for (const Node& node : s.nodes) ground = std::min(ground, node.position.z());
    for (int i = 0; i < n; ++i) {
      if (s.nodes[static_cast<std::size_t>(i)].position.z() <= ground + options.ground_tolerance) {
        r.supports.push_back(Support{i, false, {}});
      }
    }
  }
  std::vector<bool> held(static_cast<std::size_t>(dofs), false);
  for (const Support& support : r.supports) {
    for (int k = 0; k < (support.fixed ? 6 : 3); ++k)
      held[static_cast<std::size_t>(6 * support.node + k)] = true;
  }

  // Assembly.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(s.rods.size() * 144);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dofs);
  std::vector<Mat12> k_local(s.rods.size());
  std::vector<Mat12> transform(s.rods.size());
  std::vector<Vec12> f_equivalent(s.rods.size());
  std::vector<Vec3> q_local(s.rods.size());
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    const double L = l.edge_length[e];
    Mat3 axes;  // rows: local x, y, z in world coordinates
    axes.row(0) = l.rotation[e].col(2).transpose();
    axes.row(1) = l.rotation[e].col(0).transpose();
    axes.row(2) = l.rotation[e].col(1).transpose();
    Mat12 t = Mat12::Zero();
    for (int b = 0; b < 4; ++b) t.block<3, 3>(3 * b, 3 * b) = axes;
    transform[e] = t;
    k_local[e] = local_stiffness(L, m.youngs_modulus, m.shear_modulus, A, I, I, J);
    const Mat12 k_global = t.transpose() * k_local[e] * t;
    // Self-weight: the rod as cut (length ℓ) spread over the element (node to node).
    Vec3 q_world = Vec3::Zero();
    if (options.self_weight) {
      const double weight = m.density * 1e-9 * A * std::max(0.0, l.rod_length[e]) * g;  // N
      q_world = Vec3(0, 0, -weight / L);
      r.total_load += weight;
    }
    q_local[e] = axes * q_world;
    f_equivalent[e] = uniform_load(q_local[e], L);
    const Vec12 f_global = t.transpose() * f_equivalent[e];
    const int nodes[2] = {s.rods[e].a, s.rods[e].b};
    for (int a = 0; a < 2; ++a) {
      f.segment<6>(6 * nodes[a]) += f_global.segment<6>(6 * a);
      for (int b = 0; b < 2; ++b) {
        for (int i = 0; i < 6; ++i) {
          for (int j = 0; j < 6; ++j) {
            const double v = k_global(6 * a + i, 6 * b + j);
            if (v != 0) triplets.emplace_back(6 * nodes[a] + i, 6 * nodes[b] + j, v);
          }
        }
      }
    }
  }
  if (options.self_weight) {
    for (std::size_t i = 0; i < joint_masses.size() && i < s.nodes.size(); ++i) {
      f(static_cast<Eigen::Index>(6 * i + 2)) -= joint_masses[i].mass * g;
      r.total_load += joint_masses[i].mass * g;
    }
  }
  for (const PointLoad& load : options.loads) {
    f.segment<3>(6 * load.node) += load.force;
    r.total_load -= load.force.z();
  }

  // Reduce to the free DOFs and solve.
  std::vector<int> free_index(static_cast<std::size_t>(dofs), -1);
  int free = 0;
  for (int d = 0; d < dofs; ++d) {
    if (!held[static_cast<std::size_t>(d)]) free_index[static_cast<std::size_t>(d)] = free++;
  }
  std::vector<Eigen::Triplet<double>> reduced;
  reduced.reserve(triplets.size());
  for (const auto& t : triplets) {
    const int i = free_index[static_cast<std::size_t>(t.row())],
              j = free_index[static_cast<std::size_t>(t.col())];
    if (i >= 0 && j >= 0) reduced.emplace_back(i, j, t.value());
  }
  Eigen::SparseMatrix<double> K(free, free);
  K.setFromTriplets(reduced.begin(), reduced.end());
  Eigen::VectorXd rhs(free);
  for (int d = 0; d < dofs; ++d) {
    if (free_index[static_cast<std::size_t>(d)] >= 0)
      rhs(free_index[static_cast<std::size_t>(d)]) = f(d);
  }
  Eigen::VectorXd u = Eigen::VectorXd::Zero(dofs);
  auto mechanism = [&](const std::string& why) {
    r.findings.error(codes::kMechanism,
                     fmt::format("the frame cannot carry its load: {} (supports at joint{} {})",
                                 why,
                                 r.supports.size() == 1 ? "" : "s",
                                 [&] {
                                   std::string out;
                                   for (const Support& sp : r.supports) {
                                     out += (out.empty() ? "" : ", ") + s.joint_label(sp.node);
                                   }
                                   return out.empty() ? std::string("none") : out;
                                 }()));
    return r;
  };
  if (free > 0) {
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(K);
    if (lu.info() != Eigen::Success) return mechanism("its stiffness matrix is singular");
    const Eigen::VectorXd x = lu.solve(rhs);
    const double residual = (K * x - rhs).norm();
    if (lu.info() != Eigen::Success || !x.allFinite() || residual > 1e-6 * (1 + rhs.norm())) {
      return mechanism("it is free to move (a mechanism)");
    }
    for (int d = 0; d < dofs; ++d) {
      if (free_index[static_cast<std::size_t>(d)] >= 0)
        u(d) = x(free_index[static_cast<std::size_t>(d)]);
    }
  }
  // A mechanism can still factor with tiny pivots: huge displacements give it away.
  double size = 1;
  for (const Node& node : s.nodes) size = std::max(size, node.position.norm());
  if (u.cwiseAbs().maxCoeff() > 1e3 * size) return mechanism("it is free to move (a mechanism)");
  r.solved = true;

  r.displacement.resize(s.nodes.size());
  r.rotation.resize(s.nodes.size());
  for (int i = 0; i < n; ++i) {
    r.displacement[static_cast<std::size_t>(i)] = u.segment<3>(6 * i);
    r.rotation[static_cast<std::size_t>(i)] = u.segment<3>(6 * i + 3);
    const double d = r.displacement[static_cast<std::size_t>(i)].norm();
    if (d > r.max_deflection) {
      r.max_deflection = d;
      r.max_deflection_node = i;
    }
  }

  // Member forces and utilisation.
  r.rods.resize(s.rods.size());
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    const double L = l.edge_length[e];
    Vec12 ue;
    ue.segment<6>(0) = u.segment<6>(6 * s.rods[e].a);
    ue.segment<6>(6) = u.segment<6>(6 * s.rods[e].b);
    const Vec12 fl = k_local[e] * (transform[e] * ue) - f_equivalent[e];
    RodStress& out = r.rods[e];
    const double n_a = -fl(0), n_b = fl(6);  // tension positive
    out.axial = std::abs(n_a) > std::abs(n_b) ? n_a : n_b;
    out.torque = std::abs(fl(3));
    const Vec3 q = q_local[e];
    for (int k = 0; k <= 8; ++k) {
      const double x = L * k / 8;
      const double mz = fl(5) - x * fl(1) - q.y() * x * x / 2;
      const double my = fl(4) + x * fl(2) + q.z() * x * x / 2;
      out.moment = std::max(out.moment, std::hypot(my, mz));
    }
    const double normal = std::max(std::abs(n_a), std::abs(n_b)) / A + out.moment / section_modulus;
    const double shear = out.torque * p.radius / J;
    out.stress = std::sqrt(normal * normal + 3 * shear * shear);
    const double kl = options.buckling_length_factor * L;
    out.buckling_load = std::numbers::pi * std::numbers::pi * m.youngs_modulus * I / (kl * kl);
    const double compression = std::max({0.0, -n_a, -n_b});
    const double u_stress = out.stress / m.strength, u_buckling = compression / out.buckling_load;
    out.utilisation = std::max(u_stress, u_buckling);
    out.governing = u_buckling > u_stress ? "buckling" : "stress";
    if (out.utilisation > r.max_utilisation) {
      r.max_utilisation = out.utilisation;
      r.critical_rod = static_cast<int>(e);
    }
    if (out.utilisation > 1) {
      r.findings.error(
          codes::kRodOverstressed,
          u_buckling > u_stress
              ? fmt::format("{} buckles: compression {:.1f} N exceeds its Euler load {:.1f} N "
                            "(utilisation {:.2f})",
                            s.rod_name(static_cast<int>(e)),
                            compression,
                            out.buckling_load,
                            out.utilisation)
              : fmt::format("{} is overstressed: {:.1f} MPa (axial {:.1f} N, moment {:.0f} N·mm) "
                            "exceeds the {} strength {:g} MPa (utilisation {:.2f})",
                            s.rod_name(static_cast<int>(e)),
                            out.stress,
                            out.axial,
                            out.moment,
                            m.name,
                            m.strength,
                            out.utilisation),
          s.rods[e].where);
    }
  }
  return r;
}

}  // namespace fabkit::rods
