#pragma once
/// A printable test plate of sockets over a range of tolerances ε for the design's rod radius
/// and profile, each labelled with its ε (RodSteward §6: print it first, push a real rod into
/// each socket, and pick the ε that fits).

#include <optional>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

struct ToleranceBoardOptions {
  double from = -0.1;  ///< mm, the tightest ε
  double to = 0.3;     ///< mm, the loosest ε
  double step = 0.05;  ///< mm
  double depth = 0;    ///< mm, socket depth; 0: the design's h
  int columns = 5;     ///< sockets per row
};

struct ToleranceBoard {
  TriangleMesh mesh;                 ///< closed solid, z = 0 on the print bed, mm
  std::vector<double> tolerances;    ///< ε of each socket, mm
  std::vector<Vec3> socket_centres;  ///< the top centre of each socket, mm
  double pitch = 0;                  ///< mm between socket centres
};

/// The board: a plate σ thicker than the socket depth, one socket of radius r + ε per
/// tolerance (the design's profile, circumscribing the circle for round rods), and its ε
/// engraved beside it ("+0.10"). Input diagnostics for a bad range (step ≤ 0, more than 60
/// sockets, r + ε ≤ 0); nullopt on failure.
std::optional<ToleranceBoard> make_tolerance_board(const Parameters& p,
                                                   const ToleranceBoardOptions& options,
                                                   Diagnostics& diags);

}  // namespace fabkit::rods
