#include "fabkit/flatpack/joint_widths.h"

namespace fabkit::flatpack {

DrawnWidths finger_and_opening(double nominal_mm, double kerf_mm, double interference_mm) {
  const double widen = (4 * kerf_mm + interference_mm) / 2;
  return {nominal_mm + widen, nominal_mm - widen};
}

double slot_width(double board_thickness_mm, double kerf_mm, double interference_mm) {
  return board_thickness_mm - 2 * kerf_mm - interference_mm;
}

double cut_solid_width(double drawn_mm, double kerf_mm) {
  return drawn_mm - 2 * kerf_mm;
}

double cut_opening_width(double drawn_mm, double kerf_mm) {
  return drawn_mm + 2 * kerf_mm;
}

}  // namespace fabkit::flatpack
