#pragma once
// Internals of solve.cpp exposed to the tests.

#include <vector>

#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

/// Largest difference between the analytic (twist) Jacobian and the automatically
/// differentiated one of step 1's (target) or step 2's (energy) rows at parameters `x`,
/// relative to the largest entry.
double jacobian_mismatch(const Assembly& assembly, const std::vector<double>& x, bool energy);

/// Largest difference between the analytic Jacobian and central finite differences of the
/// rows' values (step `h` in scaled units), relative to the largest entry.
double finite_difference_mismatch(const Assembly& assembly,
                                  const std::vector<double>& x,
                                  bool energy,
                                  double h = 1e-6);

}  // namespace fabkit::hacks::detail
