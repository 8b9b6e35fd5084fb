#pragma once
// Constraint residuals shared by verification and solving: cycle closure (paper §4.3.2)
// and multi-connection spacing (§4.3.1). Templated for automatic differentiation.

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

/// Residuals per cycle-closing connection: 3 position (mm) + 9 rotation entries scaled so
/// that their squared norm is the rotation angle in degrees squared (for small angles).
inline constexpr int kClosureResiduals = 12;
/// ‖R1 − R2‖_F ≈ √2·θ, so this factor turns Frobenius entries into degrees.
inline constexpr double kRotationResidualScale = kRadToDeg / 1.4142135623730951;

/// Axis (in the connection frame) about which a closure may rotate freely, e.g. a cable's
/// centre line spinning in the rings it threads (RodCtl has no spin parameter).
inline std::optional<Vec3> free_rotation_axis(const Assembly& a, ConnectionId id) {
  const Connection& c = a.connection(id);
  auto kind = [&](const Connector& k) {
    return a.node(k.part).part->primitive(k.primitive).connector_kind();
  };
  if (kind(c.second) == ConnectorKind::kRodCenterline) return Vec3::UnitY();
  if (kind(c.first) == ConnectorKind::kRodCenterline) {
    return c.offset.topLeftCorner<3, 3>().transpose() * Vec3::UnitY();
  }
  return std::nullopt;
}

template <class T>
void closure_residuals(
    const Assembly& a, ConnectionId id, const std::optional<Vec3>& free_axis, const T* x, T* out) {
  const auto [f1, f2] = a.connection_frames<T>(id, x);
  for (int i = 0; i < 3; ++i) out[i] = f1.t[i] - f2.t[i];
  if (free_axis) {
    const Vec3T<T> axis = free_axis->cast<T>();
    const Vec3T<T> d = f1.R * axis - f2.R * axis;
    for (int i = 0; i < 3; ++i) out[3 + i] = d[i] * T(kRadToDeg);
    for (int i = 6; i < kClosureResiduals; ++i) out[i] = T(0);
    return;
  }
  int k = 3;
  for (int col = 0; col < 3; ++col) {
    for (int row = 0; row < 3; ++row) {
      out[k++] = (f1.R(row, col) - f2.R(row, col)) * T(kRotationResidualScale);
    }
  }
}

/// Two connections on one multiply-connected primitive that must stay apart:
/// f = Σ_k (|t_j,k − t_i,k|·L_k − need_k) ≥ 0 (reference §5.4).
struct MultiConnectionPair {
  std::vector<int> params_i;  ///< indices into x of the first connection's critical-dim params
  std::vector<int> params_j;
  std::vector<double> length;  ///< the primitive's critical dimension per axis
  std::vector<double> need;    ///< cd_i + cd_j per axis
  std::string description;
};

std::vector<MultiConnectionPair> multi_connection_pairs(const Assembly& a);

template <class T>
T multi_connection_value(const MultiConnectionPair& p, const T* x) {
  using std::abs;
  T f(0);
  for (std::size_t k = 0; k < p.params_i.size(); ++k) {
    f += abs(x[p.params_j[k]] - x[p.params_i[k]]) * T(p.length[k]) - T(p.need[k]);
  }
  return f;
}

}  // namespace fabkit::hacks::detail
