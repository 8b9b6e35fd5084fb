#pragma once
/// Connector-frame parameterisations (reference §2.3). C(q) = B · local(q), where B is the
/// primitive's base frame in its part. Templated so solvers can differentiate (ceres::Jet).
/// These functions never clamp: callers keep parameters inside their bounds.

#include <cmath>

#include "fabkit/core/frame.h"
#include "fabkit/hacks/primitive.h"

namespace fabkit::hacks {

/// Connector frame relative to the primitive's base frame. `q` holds connector_dof(kind)
/// values in the order of Primitive::connector_params().
template <class T>
Mat4T<T> connector_local(ConnectorKind kind, const PrimitiveShape& s, const T* q) {
  using std::cos;
  using std::sin;
  const T zero(0);
  const T deg(kDegToRad);
  switch (kind) {
    case ConnectorKind::kRod:  // (t, φ)
      return translation(zero, T(s.radius), (q[0] - T(0.5)) * T(s.length)) * rot_x(T(-90)) *
             rot_x(q[1] - T(90));
    case ConnectorKind::kRodCenterline:  // (t)
      return translation(zero, zero, (q[0] - T(0.5)) * T(s.length)) * rot_x(T(-90));
    case ConnectorKind::kHook:
    case ConnectorKind::kRing: {  // (θ): inner side of the wire
      const T r(s.arc_radius - s.thickness);
      const T th = q[0] * deg;
      return translation(zero, -r * sin(th), -r * cos(th)) * rot_x(-q[0]);
    }
    case ConnectorKind::kHookFlex:
    case ConnectorKind::kRingFlex: {  // (θ, φ)
      const T r(s.arc_radius - s.thickness);
      const T th = q[0] * deg;
      return translation(zero, -r * sin(th), -r * cos(th)) * rot_x(-q[0]) * rot_z(q[1] - T(90));
    }
    case ConnectorKind::kRingCenterline:  // (v0, v1)
      return rot_y(q[0]) * rot_x(q[1]);
    case ConnectorKind::kTube:
    case ConnectorKind::kTubeCenterline: {  // (t, θ)
      const T rho(kind == ConnectorKind::kTube ? s.inner_radius + s.thickness : s.inner_radius);
      const T th = q[1] * deg;
      return translation(zero, zero, (q[0] - T(0.5)) * T(s.length)) * rot_x(T(-90)) *
             translation(-rho * sin(th), zero, -rho * cos(th)) * rot_y(q[1]);
    }
    case ConnectorKind::kClip:  // (t)
      return translation(zero, zero, (q[0] - T(0.5)) * T(s.height));
    case ConnectorKind::kEdge:  // (t)
      return translation((q[0] - T(0.5)) * T(s.length), T(0.5 * s.width), zero);
    case ConnectorKind::kSurface:  // (t1, t2, s)
      return translation((q[1] - T(0.5)) * T(s.length), (T(0.5) - q[0]) * T(s.width), T(0.05)) *
             rot_z(q[2]);
    case ConnectorKind::kHemisphere: {  // (θ, φ, s)
      const T big_r(s.radius);
      const T th = q[0] * deg;
      const T ph = q[1] * deg;
      return translation(big_r * sin(ph), big_r * cos(ph) * sin(th), -big_r * cos(ph) * cos(th)) *
             rot_y(q[1]) * rot_x(-q[0]) * rot_z(q[2]);
    }
  }
  return Mat4T<T>::Identity();
}

/// Connector frame in the part's coordinates: B · local(q).
template <class T>
Mat4T<T> connector_frame(const Primitive& p, const T* q) {
  return p.frame.matrix().cast<T>() * connector_local<T>(p.connector_kind(), p.shape, q);
}

}  // namespace fabkit::hacks
