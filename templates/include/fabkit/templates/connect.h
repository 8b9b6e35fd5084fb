#pragma once
/// Connecting (paper §4.5): after snapping, the added template's principal elements that touch
/// the model's are *linked*; for each linked pair a connection is sought, first by transferring
/// one from the added template's source design, then by retrieving the closest connections of
/// the whole database by descriptor (materials, sizes weighted toward constrained dimensions,
/// the four plane distances per axis). The K closest are tried: a connection is accepted only
/// if the model with its connectors and relations stays feasible and no principal parameter
/// moves more than a threshold (eq. 4). Accepted connections, their connecting elements and
/// new geosemantic relations between the added template and the model are added to the model.

#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/manipulate.h"
#include "fabkit/templates/working_model.h"

namespace fabkit::templates {

struct ConnectOptions {
  int k = 5;                      ///< database connections tried per linked pair (paper: K = 5)
  double link_distance_mm = 1.0;  ///< elements closer than this are linked
  double error_threshold_mm =
      60;  ///< largest move of any principal parameter a connection may cause
  ManipulateOptions manipulate;
};

/// One connection tried for a linked pair.
struct ConnectionCandidate {
  std::string source;        ///< "coffee_table: leg_fl + shelf (LBR-40, 2 x SCR-3.5x16)"
  bool transferred = false;  ///< from the added template's own source design
  double descriptor_distance = 0;
  double error_mm = 0;  ///< largest principal parameter change, mm (inf: infeasible)
  bool feasible = false;
  bool accepted = false;
};

struct Link {
  ElementId added;     ///< in the model
  ElementId existing;  ///< in the model
  std::vector<ConnectionCandidate> tried;
  std::optional<ConnectionId> connection;  ///< the accepted one, in the model
  std::string message;  ///< "no connection found between 'shelf' and 'leg_fl' (tried ...)"
};

struct ConnectResult {
  std::vector<Link> links;
  bool all_connected = false;
  int relations_added = 0;  ///< new geosemantic relations between the template and the model
  double milliseconds = 0;
  Diagnostics diagnostics;  ///< a no-connection error per pair that could not be joined
};

/// Connects composition `added` to the rest of `model` (modified in place: connectors,
/// connections and relations added, parameters adjusted). Links that fail leave the model as
/// it was for that pair.
ConnectResult connect(WorkingModel& model,
                      const Composition& added,
                      const TemplateDatabase& db,
                      const ConnectOptions& options = {});

}  // namespace fabkit::templates
