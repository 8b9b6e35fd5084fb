#pragma once
// The solver's tolerances, in one place, each with why it has its value. Units: mm for
// positions, degrees for angles; "slope" is mm of mean centre-of-mass height per mm (or per
// degree) of motion.

namespace fabkit::hacks::detail {

/// An objective whose slope along every allowed motion is below this has converged (step 1's
/// least squares, step 2's potential). 1e-9 is far below the 1e-6 that counts as equilibrium
/// in results, so a converged solve is an equilibrium with room to spare.
inline constexpr double kGradientTolerance = 1e-9;

/// A result whose potential still slopes by more than this along some allowed motion is not an
/// equilibrium (docs/result-format.md): it is reported as "did not converge", never as stable.
inline constexpr double kEquilibriumTolerance = 1e-6;

/// Step 1's candidates whose target errors differ by less than this (mm, degrees) are equally
/// near: step 2 relaxes them all and keeps the one that rests nearest (solve.cpp).
inline constexpr double kEquallyNear = 0.01;

/// Settling a candidate with its target held (step 2's start) ends once the potential slopes
/// by less than this: it is a start, and the relaxation that follows lets the target go and
/// goes on to kGradientTolerance whatever it is given. Its last models crawl: the 64-hook
/// chain's settling spent 12 of its 22 models gaining 0.002 of a potential of -6253 below
/// this slope (solve 374 -> 300 ms); the gallery rests in the same states (within 0.1 mm but
/// the reading nook's rings, 2.6 mm along directions that cost nothing).
inline constexpr double kSettleTolerance = 1e-4;
/// It also ends once kSettleWindow iterations together have lowered the potential (the mass's
/// mean height, mm: a difference, the same wherever the world is) by less than
/// kSettleProgressMm. Held targets whose chains pull nearly straight make such settlings creep,
/// failed projections shrinking the trust region step after step: the reading nook's two
/// settled 41 and 99 iterations (the second at its cap), gaining under 0.01 mm in their last
/// 30 and 50, and now 13 and 45 (its solve stage about 100 -> 85 ms); it rests where it did to
/// the printed digit, and of the gallery only the bird feeder moved, its S-hooks turned 4-8°
/// about their neutral directions (positions within 10⁻³ mm).
inline constexpr int kSettleWindow = 10;
inline constexpr double kSettleProgressMm = 0.01;

/// Cycle closures count as closed below this (mm, degrees) inside the solvers: round-off of
/// chains of a few hundred mm, well below the 1e-6 mm the results promise.
inline constexpr double kClosureTolerance = 1e-10;

/// A projection back onto the closures that cannot get below this has failed.
inline constexpr double kProjectionTolerance = 1e-7;

/// A spacing constraint (two connections on one primitive) within this of binding (mm) is
/// treated as active.
inline constexpr double kInequalityMargin = 1e-6;

/// Curvatures below this fraction of the largest are neutral: the potential does not change
/// along them (a hook on a level rod), so they get no Newton step.
inline constexpr double kNeutralCurvature = 1e-6;

/// The minimal orientation residuals of a closure also vanish at a half turn; a closed
/// configuration whose real orientation gap exceeds this (degrees) is rejected.
inline constexpr double kHalfTurnCheckDeg = 1e-3;

/// A target reached within this (mm and degrees) cannot be improved by more starts.
inline constexpr double kTargetReached = 1e-4;
/// Step 1's fits: a crawling fit whose ½‖r‖² is below this (the target within about 0.1 mm and
/// 0.1° of its goal: positions in mm, rotations in degrees) is not finished by Newton's method
/// (ManifoldSolverOptions::finish_above). Where a goal cannot be reached exactly, a 64-hook
/// chain's finish took 10 Newton models of 197 motions to bring it from 0.0741 to 0.0737 mm.
inline constexpr double kFitCloseEnough = 0.5 * 0.1 * 0.1;

/// solve() refuses a starting configuration whose closures are open by more than this (mm):
/// connect() verified it closed.
inline constexpr double kStartGapMm = 1e-3;

/// Below these the target's sag from step 1 to step 2 is not worth a note (mm, degrees).
inline constexpr double kSagNoteMm = 0.05;
inline constexpr double kSagNoteDeg = 0.05;

}  // namespace fabkit::hacks::detail
