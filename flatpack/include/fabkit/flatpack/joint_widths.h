#pragma once
/// Joint widths of paper Appendix A, with fabkit's sign convention.
///
/// Convention: Δ (kerf_mm) is the material the cutter removes on EACH side of a drawn line, so
/// a drawn solid (finger) comes out 2Δ narrower and a drawn opening (dent, hole, slot) 2Δ wider.
/// δ (interference_mm) is how much wider a cut finger is than the cut opening it presses into.
///   finger–finger: w_f = w_d + 4Δ + δ   (paper A.1.1; drawn widths)
///   finger–hole:   w_f = w_h + 4Δ + δ   (paper A.1.2)
///   slot–slot:     cut slot = board thickness − δ, so the drawn slot is w_m − 2Δ − δ.
/// The paper prints the slot as w_s = w_m + 2Δ + δ; read with the convention that makes its
/// finger formulas right (Δ per side), that slot would come out w_m + 4Δ + δ wide, looser than
/// the board, so fabkit takes the signs that give the press fit the paper describes.
/// Finger and hole lengths equal the thickness of the board they go through (not corrected).

namespace fabkit::flatpack {

/// The drawn widths of a mating finger and opening whose nominal width is `nominal_mm`
/// (the centre-line pitch); the finger gains and the opening loses half of 4Δ + δ.
struct DrawnWidths {
  double finger_mm = 0;
  double opening_mm = 0;
};
DrawnWidths finger_and_opening(double nominal_mm, double kerf_mm, double interference_mm);

/// Drawn width of a slot that takes a board of `board_thickness_mm`.
double slot_width(double board_thickness_mm, double kerf_mm, double interference_mm);

/// What comes out of the cutter for a drawn solid / opening width.
double cut_solid_width(double drawn_mm, double kerf_mm);
double cut_opening_width(double drawn_mm, double kerf_mm);

}  // namespace fabkit::flatpack
