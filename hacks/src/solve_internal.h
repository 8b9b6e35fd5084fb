#pragma once
// Internals of solve.cpp exposed to the tests.

#include <vector>

#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

/// Largest difference between the analytic (twist) Jacobian and the automatically
/// differentiated one of step 1's (target) or step 2's (energy) rows at parameters `x`,
/// relative to the largest entry.
double jacobian_mismatch(const Assembly& assembly, const std::vector<double>& x, bool energy);

}  // namespace fabkit::hacks::detail
