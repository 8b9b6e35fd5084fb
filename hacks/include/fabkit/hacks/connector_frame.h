#pragma once
/// Connector-frame parameterisations (reference §2.3). C(q) = B · local(q), where B is the
/// primitive's base frame in its part. Templated so solvers can differentiate (ceres::Jet).
/// These functions never clamp: callers keep parameters inside their bounds.

#include <cmath>

#include "fabkit/core/frame.h"
#include "fabkit/hacks/primitive.h"

namespace fabkit::hacks {

/// Right-multiplies `m` by the connector frame relative to the primitive's base frame.
/// `q` holds connector_dof(kind) values in the order of Primitive::connector_params().
/// `m` is a Rigid<T>, or anything with its translate / rotate_x / rotate_y / rotate_z (the
/// solver's twist recorder follows the same elementary motions: kinematics.cpp).
template <class T, class Frame>
void apply_connector(ConnectorKind kind, const PrimitiveShape& s, const T* q, Frame& m) {
  using std::cos;
  using std::sin;
  const T zero(0);
  const T deg(kDegToRad);
  switch (kind) {
    case ConnectorKind::kRod:  // (t, φ, ψ): T(0, 0, (t-½)L) · Rz(ψ) · T(0, r, 0) · Rx(φ-180)
      // ψ puts the contact anywhere around the rod's surface; at ψ = 0 this is the reference's
      // RodMCF, T(0, r, (t-½)L) · Rx(-90) · Rx(φ-90), whose contact is one fixed line.
      m.translate(zero, zero, (q[0] - T(0.5)) * T(s.length))
          .rotate_z(q[2])
          .translate(zero, T(s.radius), zero)
          .rotate_x(q[1] - T(180));
      return;
    case ConnectorKind::kRodCenterline:  // (t): T(0, 0, (t-½)L) · Rx(-90)
      m.translate(zero, zero, (q[0] - T(0.5)) * T(s.length)).rotate_x(T(-90));
      return;
    case ConnectorKind::kHook:
    case ConnectorKind::kRing:
    case ConnectorKind::kHookFlex:
    case ConnectorKind::kRingFlex: {  // (θ[, φ]): inner side of the wire, T(0, -r sinθ, -r cosθ) ·
                                      // Rx(-θ)
      const T r(s.arc_radius - s.thickness);
      const T th = q[0] * deg;
      // Rx(-θ) has cosine cos θ and sine −sin θ (the same doubles: cos is even and sin odd to
      // the last bit), so the angle's sine and cosine are taken once.
      const T cos_th = cos(th);
      const T sin_th = sin(th);
      m.translate(zero, -r * sin_th, -r * cos_th).rotate_x(-q[0], cos_th, -sin_th);
      if (kind == ConnectorKind::kHookFlex || kind == ConnectorKind::kRingFlex) {
        m.rotate_z(q[1] - T(90));
      }
      return;
    }
    case ConnectorKind::kRingCenterline:  // (v0, v1): Ry(v0) · Rx(v1)
      m.rotate_y(q[0]).rotate_x(q[1]);
      return;
    case ConnectorKind::kTube:
    case ConnectorKind::kTubeCenterline: {  // (t, θ)
      const T rho(kind == ConnectorKind::kTube ? s.inner_radius + s.thickness : s.inner_radius);
      const T th = q[1] * deg;
      const T cos_th = cos(th);
      const T sin_th = sin(th);
      m.translate(zero, zero, (q[0] - T(0.5)) * T(s.length))
          .rotate_x(T(-90))
          .translate(-rho * sin_th, zero, -rho * cos_th)
          .rotate_y(q[1], cos_th, sin_th);
      return;
    }
    case ConnectorKind::kClip:  // (t)
      m.translate(zero, zero, (q[0] - T(0.5)) * T(s.height));
      return;
    case ConnectorKind::kEdge:  // (t)
      m.translate((q[0] - T(0.5)) * T(s.length), T(0.5 * s.width), zero);
      return;
    case ConnectorKind::kSurface:  // (t1, t2, s)
      m.translate((q[1] - T(0.5)) * T(s.length), (T(0.5) - q[0]) * T(s.width), T(0.05))
          .rotate_z(q[2]);
      return;
    case ConnectorKind::kHemisphere: {  // (θ, φ, s)
      const T big_r(s.radius);
      const T th = q[0] * deg;
      const T ph = q[1] * deg;
      const T cos_th = cos(th);
      const T sin_th = sin(th);
      const T cos_ph = cos(ph);
      const T sin_ph = sin(ph);
      m.translate(big_r * sin_ph, big_r * cos_ph * sin_th, -big_r * cos_ph * cos_th)
          .rotate_y(q[1], cos_ph, sin_ph)
          .rotate_x(-q[0], cos_th, -sin_th)
          .rotate_z(q[2]);
      return;
    }
  }
}

/// Connector frame in the part's coordinates: B · local(q).
template <class T>
Rigid<T> connector_transform(const Primitive& p, const T* q) {
  Rigid<T> m = Rigid<T>::from_matrix(p.frame.matrix());
  apply_connector<T>(p.connector_kind(), p.shape, q, m);
  return m;
}

/// Same as a 4×4 homogeneous matrix.
template <class T>
Mat4T<T> connector_frame(const Primitive& p, const T* q) {
  return connector_transform<T>(p, q).matrix();
}

}  // namespace fabkit::hacks
