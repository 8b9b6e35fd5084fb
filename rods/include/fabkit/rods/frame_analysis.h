#pragma once
/// Structural analysis of a rod structure as a 3D frame (beyond the paper, which stops at
/// balance): every rod a 12-degree-of-freedom beam element with axial, bending and torsional
/// stiffness between its two nodes, rigid joints, self-weight plus point loads at nodes,
/// supports at the floor contacts. Reports per-rod utilisation (combined stress against
/// strength; Euler buckling for rods in compression) and the largest deflection.
///
/// Units: N, mm, MPa (N/mm²). z is up; gravity pulls along −z.

#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/rods/check.h"
#include "fabkit/rods/layout.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

struct FrameOptions {
  bool self_weight = true;  ///< rods' and joints' weight
  double gravity = 9.81;    ///< m/s²
  std::vector<PointLoad> loads;
  /// Where the structure is held. Empty: every floor contact (nodes within ground_tolerance of
  /// the lowest) is pinned (translations held, rotations free).
  std::vector<Support> supports;
  double ground_tolerance = 1.0;        ///< mm
  double buckling_length_factor = 1.0;  ///< K in P_cr = π²EI / (K L)²; 1: pinned-pinned
};

/// What one rod carries.
struct RodStress {
  double axial = 0;          ///< N: tension positive, the larger-magnitude end
  double moment = 0;         ///< N·mm: largest bending moment along the rod
  double torque = 0;         ///< N·mm
  double stress = 0;         ///< MPa: |N|/A + M/S combined with torsion as √(σ² + 3τ²)
  double buckling_load = 0;  ///< N: Euler load π²EI / (K L)²
  double utilisation = 0;    ///< max(stress / strength, compression / buckling load)
  std::string_view governing = "stress";  ///< "stress" or "buckling"
};

struct FrameResult {
  bool solved = false;
  std::vector<Vec3> displacement;  ///< mm per node
  std::vector<Vec3> rotation;      ///< rad per node (small rotations about x, y, z)
  double max_deflection = 0;       ///< mm, largest |displacement|
  int max_deflection_node = -1;
  std::vector<RodStress> rods;
  double max_utilisation = 0;
  int critical_rod = -1;
  std::vector<Support> supports;  ///< the supports used
  double total_load = 0;          ///< N, vertical, including self-weight
  /// rod-overstressed per rod above utilisation 1, mechanism when the frame cannot carry load.
  Diagnostics findings;
};

/// Linear static analysis. `joint_masses` (per node) adds the joints' weight; empty: none.
FrameResult analyse_frame(const Structure& s,
                          const Parameters& p,
                          const Layout& l,
                          const FrameOptions& options,
                          std::span<const JointMass> joint_masses = {});

}  // namespace fabkit::rods
