#pragma once
// The target of step 1 (paper §4.3.3): where end_with wants a primitive, modulo the
// primitive's symmetries (a rod spins freely about its axis, ...), as residuals for the
// solver and as a pose error for people.

#include <numbers>
#include <optional>

#include "constraints.h"
#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/solve.h"
#include "tolerances.h"

namespace fabkit::hacks::detail {

inline double value_of(double v) {
  return v;
}
template <class J>
requires requires(const J& j) {
  j.a;
}
double value_of(const J& j) {
  return j.a;
}

// Symmetries of a primitive as a target, in its own frame: a free axis (a rod spins about its
// axis, a ring about its own) and a half-turn that maps it onto itself (a rod end for end).
struct TargetSymmetry {
  std::optional<Vec3> free_axis;
  std::optional<Vec3> half_turn_axis;
};
TargetSymmetry target_symmetry(PrimitiveType t);

struct TargetModel {
  PartId part;
  Rigid<double> base;         // target primitive in its part
  Rigid<double> goal;         // where it should be
  Rigid<double> goal_turned;  // goal turned by the half-turn symmetry (if any)
  TargetSymmetry symmetry;
};

/// The assembly's target, if it has one that is connected.
std::optional<TargetModel> make_target(const Assembly& a);

inline constexpr int kTargetResiduals = 12;

// Position gap (mm) and orientation gap (≈ degrees) of the target, modulo its symmetries.
template <class T>
void target_residuals(const TargetModel& t, const Rigid<T>& part_frame, T* out) {
  const Rigid<T> actual = part_frame.then(t.base);
  for (int i = 0; i < 3; ++i) out[i] = actual.t[i] - T(t.goal.t[i]);
  for (int i = 3; i < kTargetResiduals; ++i) out[i] = T(0);
  if (t.symmetry.free_axis) {
    const Vec3T<T> u = actual.R * t.symmetry.free_axis->cast<T>();
    Vec3 g = t.goal.R * *t.symmetry.free_axis;
    if (t.symmetry.half_turn_axis) {
      // An axis symmetric end for end matches either direction: take the nearer.
      double d = 0;
      for (int i = 0; i < 3; ++i) d += value_of(u[i]) * g[i];
      if (d < 0) g = -g;
    }
    for (int i = 0; i < 3; ++i) out[3 + i] = (u[i] - T(g[i])) * T(kRadToDeg);
    return;
  }
  const Rigid<double>* goal = &t.goal;
  if (t.symmetry.half_turn_axis) {
    double d0 = 0;
    double d1 = 0;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        d0 += std::pow(value_of(actual.R(r, c)) - t.goal.R(r, c), 2);
        d1 += std::pow(value_of(actual.R(r, c)) - t.goal_turned.R(r, c), 2);
      }
    }
    if (d1 < d0) goal = &t.goal_turned;
  }
  int k = 3;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      out[k++] = (actual.R(r, c) - T(goal->R(r, c))) * T(kRotationResidualScale);
    }
  }
}

/// The target's position and orientation error at its part's frame.
PoseError pose_error(const TargetModel& t, const Rigid<double>& part_frame);

}  // namespace fabkit::hacks::detail
