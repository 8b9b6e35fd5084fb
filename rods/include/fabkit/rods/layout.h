#pragma once
/// The quantities of RodSteward Appendix A: per node-edge offsets g_ij, rod lengths ℓ_ij and
/// the per-edge rotations R_{ij}. Only trigonometry: fast enough to recompute on every edit.

#include <array>
#include <vector>

#include "fabkit/core/frame.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

/// Eq. (6): the safe offset g = (r + ε) · sqrt((1 + c) / (1 − c)) for the largest cosine c
/// between a rod and another rod at the same node (mm). c = cos θ; 90° gives g = r + ε.
double safe_offset(double max_cosine, double radius_plus_tolerance);

/// Eq. (1): the rotation taking e_z to the unit vector `w`, R = I + [e_z×w]× +
/// [e_z×w]×² / (1 + e_z·w), for w in the upper half space (e_z·w ≥ 0). Below, where Eq. (1)
/// loses precision and divides by zero at −e_z, it is the half turn about x composed with Eq.
/// (1) of the turned vector: the same direction, a numerically stable twist.
Mat3 rotation_to(const Vec3& w);

/// One end of a rod: the rod seen from the joint it enters.
struct RodEnd {
  int rod = 0;
  int node = 0;
  int end = 0;            ///< 0: the rod's node a, 1: node b
  Vec3 direction;         ///< unit vector from the node along the rod (ŵ_ij)
  double max_cosine = 0;  ///< c_ij (Eq. 5); −2 at a node holding only this rod
  int closest_rod = -1;   ///< the other rod at this node that sets c_ij (−1: none)
  double offset = 0;      ///< g_ij, mm (Eq. 6; the leaf offset at a single-rod node)
  /// Rotation placing the profile: z along `direction`, the polygon's vertices where the
  /// rod's canonical rotation R_{ab} puts them, so both ends of a rod agree (Fig. 17).
  Mat3 frame = Mat3::Identity();
};

struct Layout {
  std::vector<std::array<RodEnd, 2>> ends;  ///< per rod: at node a, at node b
  std::vector<double> edge_length;          ///< ‖p_b − p_a‖, mm
  std::vector<double> rod_length;         ///< ℓ = ‖p_b − p_a‖ − g_ab − g_ba (Eq. 7), mm
  std::vector<Mat3> rotation;             ///< R_{ab} (Eq. 1) per rod
  std::vector<std::vector<int>> rods_at;  ///< rods per node
  /// The ends at `node` (one per rod meeting there), in the order of rods_at.
  std::vector<const RodEnd*> ends_at(int node) const;
  const RodEnd& end_at(int rod, int node) const;
};

/// Offsets, lengths and rotations of every rod.
Layout compute_layout(const Structure& s, const Parameters& p);

}  // namespace fabkit::rods
