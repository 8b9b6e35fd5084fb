#pragma once
/// A start near rest for a long chain: each part hung from the one above it.

#include <optional>
#include <vector>

#include "kinematics.h"

namespace fabkit::hacks::detail {

/// From this many variables a group without cycles is hung part by part before it is relaxed
/// (below it the relaxation's own Newton steps are cheap, and the gallery's poses are theirs).
inline constexpr int kHangFrom = 48;

/// x with the group of `p` hung from the top down: in parent-before-child order, each part's
/// joint above it and its side of the joints below it are set where the part rests under its
/// own weight and the weights hanging from it, each lumped at its joint's connector (exact where
/// what hangs below a joint swings freely about it). One small Newton solve per part, so its cost
/// grows as the number of parts; a relaxation of the whole group polishes what the lumping leaves.
/// Returns nothing where the pass does not apply: a group with cycles or parts joined to several
/// others at once, a joint whose lower side has no free parameter (a rigid attachment is not a
/// weight at a point), or a part with more joint parameters than the pass solves for.
std::optional<std::vector<double>> hung_from_the_top(const Problem& p,
                                                     const Variables& vars,
                                                     const std::vector<double>& x);

}  // namespace fabkit::hacks::detail
